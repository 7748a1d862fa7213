"""Retarget a BVH clip onto a character by per-joint global rotation mapping.

Method. For each mapped pair (BVH joint b → MJCF joint driving body k) the body's world orientation
is

    W_k(t) = Rw_b(t) · A_k · B_k⁰,

where Rw_b(t) = C·G_b(t)·Cᵀ is the BVH joint's global rotation in world axes (C maps file axes to
world axes, from the mapping file or detected by `conventions`: y-up/+Z-forward/+X-left CMU files
become z-up/+x-forward/+y-left), B_k⁰ is the body's world orientation in the character's relax pose,
and A_k is the rest offset between the skeletons: the smallest rotation taking the body's rest bone
direction onto the BVH joint's bone direction in the BVH rest pose (all channel rotations zero).
Bone directions point from a joint to the mean of its nearest mapped descendants (else its first
child, End Site or first geom). A body that carries a foot (toe and heel sites) uses heel → toe as
its bone and the BVH bone is flattened onto the floor plane (the sole is flat in the rest pose): the
built-in humanoid has no ankle, so its shin-and-foot body follows the mocap foot, which keeps stance
feet flat. The root body takes the root joint's rotation with no offset. Joint quaternions follow
from parent and child orientations; unmapped joints stay at their relax rotation; a lone hinge keeps
the component about its axis, a body on several hinges gets all of them (`hinge_chain`).

Root position: the BVH root trajectory in world axes, scaled by the ratio of the character's
standing root height to the BVH root height above its lowest point in the first frame (a leg-length
scale) times the factor that keeps the stance feet still under the character's legs (`root_scale`),
moved to start at x = y = 0 and shifted vertically so that the feet touch the floor (`grounding`:
the capture floor's drift and hovering supporting feet removed). The feet are then levelled
(`foot_level`: a constant correction per foot so that a foot standing still is flat, or with
`levelling="flat"` where the clip's own foot is flat, `flat_feet`), every joint is brought into its
range and the path is grounded again.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np
from pydantic import BaseModel, ConfigDict, field_validator

from eigengait.body_tree import body_hinges
from eigengait.geometry import mat_to_quat, quat_exp, quat_log, quat_to_mat
from eigengait.errors import UserInputError
from eigengait.files import load_model
from eigengait.motion.bvh import BvhClip, end_site_positions, frame_points, global_transforms
from eigengait.motion.conventions import detect_conventions, rest_stands
from eigengait.motion.flat_feet import clip_flat_frames
from eigengait.motion.foot_level import level_feet
from eigengait.motion.grounding import floor_offset, lowest_foot_points
from eigengait.motion.hinge_chain import hinge_angles
from eigengait.motion.rest_offsets import planted_frames, rest_offsets
from eigengait.motion.root_scale import leg_consistent_factor
from eigengait.motion.skeleton_names import LEG_ROLES, find_roles, roles_of_names
from eigengait.motion.soles import sole_points
from eigengait.sim.root import require_free_root
from eigengait.sim.world import World

# World axis ← file axis, as signed file axis names (CMU convention: up +Y, forward +Z, left +X).
CMU_AXES = {"x": "+z", "y": "+x", "z": "+y"}

# Character joint driven by each body-part role of `skeleton_names` (the walker has ankles: its shin
# follows the mocap lower leg and its foot body the mocap foot; the ankleless humanoid's shin
# follows the mocap foot).
_UPPER = {
    "root": "root",
    "torso": "torso",
    "head": "head",
    **{
        f"{s}_{p}": f"{s}_{p}" for s in ("left", "right") for p in ("upper_arm", "forearm", "thigh")
    },
}
CHARACTER_ROLES = {
    "walker": {
        **_UPPER,
        **{f"{s}_{p}": f"{s}_{p}" for s in ("left", "right") for p in ("shin", "foot")},
    },
    "humanoid": {**_UPPER, "left_foot": "left_shin", "right_foot": "right_shin"},
}


class MappingFile(BaseModel):
    """A mapping file (YAML): ``joints`` maps BVH joint names to MJCF joint names; the BVH root maps
    to the MJCF free joint; ``axes`` gives each world axis as a signed file axis (default: detected,
    see `conventions`)."""

    model_config = ConfigDict(extra="forbid")
    eigengait_mapping: int = 1
    joints: dict[str, str]
    axes: dict[str, str] | None = None

    @field_validator("axes")
    @classmethod
    def _axes_are_a_rotation(cls, axes: dict[str, str] | None) -> dict[str, str] | None:
        if axes is not None:
            axis_matrix(axes)
        return axes


def axis_matrix(axes: dict[str, str]) -> np.ndarray:
    """3×3 proper rotation C with world = C @ file, from {'x': '+z', 'y': '+x', 'z': '+y'}-style
    axes."""
    if sorted(axes) != ["x", "y", "z"]:
        raise ValueError("axes must give exactly x, y and z")
    matrix = np.zeros((3, 3))
    for row, world in enumerate("xyz"):
        text = axes[world].strip().lower()
        sign, name = (-1.0, text[1:]) if text.startswith("-") else (1.0, text.lstrip("+"))
        if name not in ("x", "y", "z"):
            raise ValueError(f"axis '{axes[world]}' must be one of ±x, ±y, ±z")
        matrix[row, "xyz".index(name)] = sign
    if not np.isclose(np.linalg.det(matrix), 1.0):
        raise ValueError("axes must form a right-handed rotation (no mirroring)")
    return matrix


@dataclass
class Mapping:
    """BVH joint → MJCF joint (the BVH root → the MJCF free joint), and the file-to-world axis
    rotation (None: detected from the clip by `clip_axes`)."""

    joints: dict[str, str]
    axes: np.ndarray | None = None


def load_mapping(path: str | Path) -> Mapping:
    """Read and validate a YAML mapping file."""
    parsed = load_model(
        MappingFile,
        path,
        "write 'joints: {BVH_JOINT: MJCF_JOINT, ...}' and optionally 'axes: {x: +z, y: +x, z: "
        "+y}'.",
        allow_empty=True,
    )
    return Mapping(
        joints=dict(parsed.joints), axes=None if parsed.axes is None else axis_matrix(parsed.axes)
    )


def builtin_mapping(character_name: str, clip: BvhClip, world: World | None = None) -> Mapping:
    """The character's mapping from the clip's joint names (`skeleton_names`); legs and root
    required. A built-in character's roles (CHARACTER_ROLES) are used when the model has every
    joint they name; otherwise, given the character's `world`, its bodies' names are read the same
    way (`body_roles`: dm_control's `right_thigh` or `lfemur`), each role driving its body's first
    joint."""
    roles = find_roles(clip)
    wanted = CHARACTER_ROLES.get(character_name, {})
    if world is not None and not (
        wanted and set(wanted.values()) - {"root"} <= set(world.character.joints)
    ):
        wanted = body_roles(world)
    missing = [r for r in wanted if (r in LEG_ROLES or r.endswith("_shin")) and r not in roles]
    legs = [r for r in LEG_ROLES if r != "root"]
    if not set(legs) <= set(wanted) or missing:
        known = ", ".join(CHARACTER_ROLES)
        why = f"the clip lacks {', '.join(missing)}" if missing else "no leg bodies found by name"
        raise UserInputError(
            f"the clip's skeleton (root '{clip.joints[0].name}') matches no mapping for character "
            f"'{character_name}' (built-in mappings: {known}; {why}).",
            field="BVH joints",
            fix=(
                "pass a mapping file (mapping='map.yaml') naming, for each MJCF joint, the BVH "
                "joint that drives it."
            ),
        )
    return Mapping(joints={roles[r]: joint for r, joint in wanted.items() if r in roles})


def body_roles(world: World) -> dict[str, str]:
    """Role → MJCF joint read from the model's body names (`skeleton_names.roles_of_names`): the
    first joint of the body each role names, the free joint ('root') for the root; bodies with no
    joint or with the free joint are not read."""
    model = world.model
    jointed = [
        model.body(b).name
        for b in range(1, model.nbody)
        if model.body_jntnum[b] and b != world.root_body
    ]
    found = roles_of_names(jointed)
    roles = {"root": "root"}
    for role, body in found.items():
        if role != "root":
            roles[role] = model.joint(int(model.body_jntadr[model.body(body).id])).name
    return roles


def clip_axes(mapping: Mapping, clip: BvhClip, start_frame: int = 1) -> np.ndarray:
    """The mapping's axes, else the detected ones, else (legs not found by name) the CMU
    convention."""
    if mapping.axes is not None:
        return mapping.axes
    roles = find_roles(clip)
    if not set(LEG_ROLES) <= set(roles):
        return axis_matrix(CMU_AXES)
    return detect_conventions(clip, roles, start_frame).axes


@dataclass
class RetargetedClip:
    """Character poses (F, nq) at the clip's frame times, the root translation's scale (m per file
    unit), the factor by which it differs from the hip-height scale (`root_scale`), each foot's
    levelling (degrees, `foot_level`) and, per foot whose clip joint has a toe, the frames (F,)
    bool in which the clip's foot stands flat (`flat_feet`)."""

    qpos: np.ndarray
    frame_time: float
    scale: float
    root_factor: float = 1.0
    foot_level_deg: dict[str, float] = field(default_factory=dict)
    flat_frames: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def duration(self) -> float:
        return (len(self.qpos) - 1) * self.frame_time


def _check_mapping(mapping: Mapping, clip: BvhClip, world: World) -> tuple[dict[int, int], int]:
    """Validate names (the character's root a free joint, a planar one refused by
    `require_free_root`); returns {bvh joint index: MJCF joint id} and the BVH root index."""
    model = world.model
    require_free_root(model, world.root_body, str(world.character.path), "track")
    names = {j.name: i for i, j in enumerate(clip.joints)}
    pairs, root = {}, None
    for bvh_name, joint_name in mapping.joints.items():
        if bvh_name not in names:
            raise UserInputError(
                f"the mapping names BVH joint '{bvh_name}', which the clip does not have.",
                field=f"joints.{bvh_name}",
                fix=f"BVH joints are: {', '.join(names)}.",
            )
        jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint_name)
        if jid < 0 and model.body(world.root_body).jntnum and joint_name == "root":
            jid = int(model.body_jntadr[world.root_body])
        if jid < 0:
            raise UserInputError(
                f"the mapping names MJCF joint '{joint_name}', which the character does not have.",
                field=f"joints.{bvh_name}",
                fix=f"MJCF joints are: {', '.join(world.character.joints)} (and the free joint).",
            )
        if model.jnt_type[jid] == mujoco.mjtJoint.mjJNT_FREE:
            root = names[bvh_name]
        elif int(model.jnt_type[jid]) not in (
            int(mujoco.mjtJoint.mjJNT_BALL),
            int(mujoco.mjtJoint.mjJNT_HINGE),
        ):
            raise UserInputError(
                f"MJCF joint '{joint_name}' is neither ball nor hinge.", field=f"joints.{bvh_name}"
            )
        pairs[names[bvh_name]] = jid
    if root is None:
        raise UserInputError(
            "the mapping does not drive the character's free joint.",
            field="joints",
            fix=f"map the BVH root '{clip.joints[0].name}' to the free joint "
            f"('{model.joint(int(model.body_jntadr[world.root_body])).name or 'root'}').",
        )
    return pairs, root


def _left_unless_rest_stands(
    clip: BvhClip,
    roles: dict[str, str],
    axes: np.ndarray,
    pos: np.ndarray,
    pairs: dict[int, int],
) -> np.ndarray | None:
    """(F, 3) unit world directions from the right thigh to the left one when the clip's rest pose
    does not stand; None when it does or when its legs are not found by name (`roles`:
    `find_roles`; `pos`: the frames' joint positions, file axes, (F, J, 3)). The thighs must then
    be mapped."""
    if not set(LEG_ROLES) <= set(roles) or rest_stands(clip, roles, axes[2]):
        return None
    left, right = _thighs(clip, roles)
    if left not in pairs or right not in pairs:
        raise UserInputError(
            "the clip's rest pose does not stand (its legs are not under its hips with all "
            "rotations zero), so the retarget takes its rest offsets from the motion, which needs "
            f"the thighs '{roles['left_thigh']}' and '{roles['right_thigh']}' mapped.",
            field="joints",
            fix="map both thighs to the character's thigh joints in the mapping file.",
        )
    across = (pos[:, left] - pos[:, right]) @ axes.T
    return across / np.linalg.norm(across, axis=1, keepdims=True)


def _thighs(clip: BvhClip, roles: dict[str, str]) -> tuple[int, int]:
    """Joint indices of the left and right thighs named in `roles` (`find_roles`)."""
    return clip.joint_index(roles["left_thigh"]), clip.joint_index(roles["right_thigh"])


def _root_up(
    clip: BvhClip,
    pairs: dict[int, int],
    root: int,
    thighs: tuple[int, int],
    rot: np.ndarray,
    pos: np.ndarray,
    body_of: dict[int, int],
    xpos: np.ndarray,
    axes: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The root's up direction, from its thighs' midpoint to its other mapped descendants (the
    torso), in the root joint's own frame (file axes, averaged over the poses `rot`, `pos`:
    `global_transforms`) and on the character (world, relax pose): the root's bone when the rest
    pose does not stand (the mean of all its mapped descendants lies too close to it to give a
    direction; `thighs`: the left and right thighs' joint indices)."""
    left, right = thighs
    parents = [j.parent for j in clip.joints]
    others = [k for k in _nearest_mapped(parents, root, set(pairs)) if k not in (left, right)]
    if not others:  # no torso mapped: the file's up (`axes[2]`), averaged, is the character's
        return np.einsum("fji,j->i", rot[:, root], axes[2]) / len(pos), np.array([0.0, 0, 1])
    up = pos[:, others].mean(axis=1) - (pos[:, left] + pos[:, right]) / 2
    body_up = (
        xpos[[body_of[k] for k in others]].mean(axis=0)
        - (xpos[body_of[left]] + xpos[body_of[right]]) / 2
    )
    return np.einsum("fji,fj->i", rot[:, root], up) / len(pos), body_up


def _nearest_mapped(parents: list[int], start: int, mapped: set[int]) -> list[int]:
    """Mapped descendants of `start` with no mapped node between them and `start`."""
    children: dict[int, list[int]] = {}
    for i, p in enumerate(parents):
        children.setdefault(p, []).append(i)
    found, stack = [], list(children.get(start, []))
    while stack:
        node = stack.pop()
        if node in mapped:
            found.append(node)
        else:
            stack.extend(children.get(node, []))
    return found


def _bvh_bones(
    clip: BvhClip, pairs: dict[int, int], rot: np.ndarray, pos: np.ndarray
) -> dict[int, np.ndarray]:
    """Bone direction of every mapped BVH joint in its own frame (file axes), averaged over the
    poses `rot`, `pos` (`global_transforms` of the rest pose, or of the motion when the rest pose
    does not stand)."""
    ends = end_site_positions(clip, rot, pos)
    parents = [j.parent for j in clip.joints]
    bones = {}
    for b in pairs:
        targets = _nearest_mapped(parents, b, set(pairs))
        children = [i for i, p in enumerate(parents) if p == b]
        if targets:
            tip = pos[:, targets].mean(axis=1)
        elif children:
            tip = pos[:, children[0]]
        else:
            tip = ends.get(b, pos[:, b])
        bone = np.einsum("fji,fj->i", rot[:, b], tip - pos[:, b]) / len(pos)
        if np.linalg.norm(bone) < 1e-9 and parents[b] >= 0:
            # a zero-length bone (an End Site on its joint, as in Bandai Namco's heads) continues
            # the parent's
            bone = np.einsum("fji,fj->i", rot[:, b], pos[:, b] - pos[:, parents[b]]) / len(pos)
        bones[b] = bone if np.linalg.norm(bone) >= 1e-9 else np.array([0.0, 1.0, 0.0])
    return bones


def _foot_sites(world: World) -> dict[int, tuple[int, int]]:
    """Body id → (heel site id, toe site id) for feet with both sites."""
    model, out = world.model, {}
    for foot in world.character.feet.values():
        if foot.toe and foot.heel:
            toe, heel = model.site(foot.toe).id, model.site(foot.heel).id
            out[int(model.site_bodyid[toe])] = (heel, toe)
    return out


def _body_rest_bones(
    world: World, data: mujoco.MjData, bodies: dict[int, int]
) -> dict[int, np.ndarray]:
    """Bone direction (world, relax pose) of every driven body, keyed by body id."""
    model = world.model
    parents = [int(p) if i else -1 for i, p in enumerate(model.body_parentid)]
    feet = _foot_sites(world)
    bones = {}
    for body in bodies.values():
        if body in feet:
            heel, toe = feet[body]
            bones[body] = data.site_xpos[toe] - data.site_xpos[heel]
            continue
        targets = _nearest_mapped(parents, body, set(bodies.values()))
        if targets:
            bones[body] = data.xpos[targets].mean(axis=0) - data.xpos[body]
        else:
            geoms = np.flatnonzero(model.geom_bodyid == body)
            bones[body] = (
                data.geom_xpos[geoms[0]] - data.xpos[body] if len(geoms) else np.array([0.0, 0, 1])
            )
    return bones


def facing_turn(world: World, data: mujoco.MjData) -> np.ndarray:
    """The turn about the vertical (3 × 3) that makes the character in its relax pose (kinematics
    in `data`) face +x, where the retarget sets the clip's forward: its feet's mean heel-to-toe
    direction, or none if a foot lacks a heel or a toe. eigengait's characters face +x already;
    dm_control's CMU humanoid faces −y."""
    feet = _foot_sites(world)
    if not feet or len(feet) < len(world.character.feet):
        return np.eye(3)
    ahead = sum(data.site_xpos[toe] - data.site_xpos[heel] for heel, toe in feet.values())
    heading = float(np.arctan2(ahead[1], ahead[0]))
    c, s = np.cos(heading), np.sin(heading)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


LEVELLINGS = ("still", "flat")  # the frames a foot is levelled on (`foot_level`, `flat_feet`)


def retarget(
    clip: BvhClip, world: World, mapping: Mapping, start_frame: int = 1, levelling: str = "still"
) -> RetargetedClip:
    """Character poses for frames ``start_frame..end`` of the clip (frame 0 of CMU files is a
    synthetic T-pose); `levelling`: the frames each foot is levelled on, its still frames or the
    clip's own flat frames (LEVELLINGS)."""
    if levelling not in LEVELLINGS:
        raise UserInputError(
            f"unknown levelling '{levelling}'.",
            field="levelling",
            fix=f"use one of: {', '.join(LEVELLINGS)}.",
        )
    if not 0 <= start_frame < clip.n_frames - 1:
        raise UserInputError(
            f"start frame {start_frame} is outside the clip's frames 0..{clip.n_frames - 2} (two "
            "frames at least).",
            field="start_frame",
            fix=f"use a start frame from 0 to {clip.n_frames - 2}.",
        )
    model = world.model
    pairs, root = _check_mapping(mapping, clip, world)
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    turn = facing_turn(world, data)
    rest_world = turn @ data.xmat.reshape(-1, 3, 3)
    body_of = {b: int(model.jnt_bodyid[j]) for b, j in pairs.items()}
    axes = clip_axes(mapping, clip, start_frame)

    rot, pos = global_transforms(clip)
    rot, pos = rot[start_frame:], pos[start_frame:]
    world_rot = axes @ rot @ axes.T  # (F, J, 3, 3) world axes
    roles = find_roles(clip)
    left = _left_unless_rest_stands(clip, roles, axes, pos, pairs)
    bvh_bones = _bvh_bones(
        clip, pairs, *(global_transforms(clip.rest()) if left is None else (rot, pos))
    )
    body_bones = {k: turn @ v for k, v in _body_rest_bones(world, data, body_of).items()}
    if left is not None:
        bvh_bones[root], body_bones[body_of[root]] = _root_up(
            clip, pairs, root, _thighs(clip, roles), rot, pos, body_of, data.xpos @ turn.T, axes
        )
    feet = _foot_sites(world)
    offsets = rest_offsets(
        world_rot,
        {b: axes @ bvh_bones[b] for b in body_of},
        {b: body_bones[body] for b, body in body_of.items()},
        {b: planted_frames(pos[:, b] @ axes[2]) for b, body in body_of.items() if body in feet},
        root,
        left,
    )
    orient = {body: world_rot[:, b] @ offsets[b] @ rest_world[body] for b, body in body_of.items()}

    n = len(rot)
    qpos = np.tile(model.qpos0, (n, 1))
    world_orient = {0: np.broadcast_to(np.eye(3), (n, 3, 3))}
    joint_of_body = {body: pairs[b] for b, body in body_of.items()}
    for body in range(1, model.nbody):
        parent = int(model.body_parentid[body])
        local = quat_to_mat(model.body_quat[body])
        if body not in orient:
            world_orient[body] = world_orient[parent] @ local
            continue
        world_orient[body] = orient[body]
        jid = joint_of_body[body]
        adr = model.jnt_qposadr[jid]
        relative = (
            np.swapaxes(local, -1, -2) @ np.swapaxes(world_orient[parent], -1, -2) @ orient[body]
        )
        quat = mat_to_quat(relative)
        if model.jnt_type[jid] == mujoco.mjtJoint.mjJNT_FREE:
            qpos[:, adr + 3 : adr + 7] = _continuous(mat_to_quat(orient[body]))
        elif model.jnt_type[jid] == mujoco.mjtJoint.mjJNT_BALL:
            qpos[:, adr : adr + 4] = _continuous(quat)
        elif len(hinges := body_hinges(model, body)) > 1:
            bounded = len(hinges) >= 3  # fewer make a least-squares turn, clamped below
            qpos[:, model.jnt_qposadr[hinges]] = hinge_angles(
                relative, model.jnt_axis[hinges], _hinge_ranges(model, hinges) if bounded else None
            )
        else:
            qpos[:, adr] = quat_log(quat) @ model.jnt_axis[jid]

    hips = (
        [j for j in _thighs(clip, roles) if j in body_of]
        if {"left_thigh", "right_thigh"} <= set(roles)
        else []
    )
    if len(hips) < 2:  # the roots stand for the hips
        hips = [root]
    height_bvh = np.mean([(axes @ pos[0, j])[2] for j in hips]) - _lowest_bvh_point(
        clip, axes, start_frame
    )
    height = np.mean([data.xpos[body_of[j]][2] for j in hips])
    hip_scale = float(height / height_bvh)
    root_adr = model.jnt_qposadr[pairs[root]]
    hip_path = hip_scale * pos[:, hips].mean(axis=1) @ axes.T
    hip_path[:, :2] -= hip_path[0, :2]
    below = _hips_from_root(model, qpos, root_adr, [body_of[j] for j in hips])
    below[:, :2] -= below[0, :2]
    _place_root(world, qpos, root_adr, hip_path - below, clip.frame_time)
    factor = leg_consistent_factor(hip_path, sole_points(world, qpos), clip.frame_time)
    _place_root(world, qpos, root_adr, factor * hip_path - below, clip.frame_time)
    foot_names = {int(model.geom_bodyid[g[0]]): name for name, g in world.foot_spheres.items()}
    flat = clip_flat_frames(clip, rot, pos, axes, [b for b in body_of if body_of[b] in foot_names])
    flat_by_foot = {foot_names[body_of[b]]: frames for b, frames in flat.items()}
    qpos, levelled = level_feet(
        world, qpos, clip.frame_time, flat_by_foot if levelling == "flat" else None
    )
    _clamp_to_joint_ranges(model, qpos)
    _place_root(world, qpos, root_adr, factor * hip_path - below, clip.frame_time)
    return RetargetedClip(qpos, clip.frame_time, hip_scale * factor, factor, levelled, flat_by_foot)


def _hinge_ranges(model: mujoco.MjModel, hinges: list[int]) -> np.ndarray:
    """(k, 2) ranges (rad) of the hinges, ±inf for one with no limit."""
    free = np.array([-np.inf, np.inf])
    return np.array([model.jnt_range[j] if model.jnt_limited[j] else free for j in hinges])


def _clamp_to_joint_ranges(model: mujoco.MjModel, qpos: np.ndarray) -> None:
    """Bring every limited joint of poses qpos (F, nq) into its range, in place: a ball joint's
    rotation is shortened to its largest angle about the same axis, a hinge clipped. A pose past a
    limit cannot be reached in physics, and its PD would only press the joint into the limit
    (the head of the Daz CMU walk 05_01 is turned 60–91°)."""
    for j in np.flatnonzero(model.jnt_limited):
        adr, low, high = model.jnt_qposadr[j], *model.jnt_range[j]
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE:
            qpos[:, adr] = np.clip(qpos[:, adr], low, high)
        elif model.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL:
            rotvec = quat_log(qpos[:, adr : adr + 4])
            angle = np.linalg.norm(rotvec, axis=1, keepdims=True)
            qpos[:, adr : adr + 4] = quat_exp(
                rotvec * np.minimum(1.0, high / np.maximum(angle, 1e-12))
            )


def _hips_from_root(
    model: mujoco.MjModel, qpos: np.ndarray, root_adr: int, hips: list[int]
) -> np.ndarray:
    """(F, 3) world offset (m) from the root body's origin to the mean origin of the `hips` bodies
    in each pose of qpos (F, nq): the thighs' joints hang below a root that is the chest
    (dm_control's suite humanoid) and turn about it with the body."""
    data = mujoco.MjData(model)
    out = np.zeros((len(qpos), 3))
    for i, q in enumerate(qpos):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        out[i] = data.xpos[hips].mean(axis=0) - q[root_adr : root_adr + 3]
    return out


def _place_root(
    world: World, qpos: np.ndarray, root_adr: int, root_path: np.ndarray, frame_time: float
) -> None:
    """Write the root path (F, 3) into qpos, lowered so that the feet touch the floor
    (`grounding`)."""
    qpos[:, root_adr : root_adr + 3] = root_path
    qpos[:, root_adr + 2] -= floor_offset(lowest_foot_points(world, qpos), frame_time)


def _continuous(quat: np.ndarray) -> np.ndarray:
    """Flip quaternion signs so consecutive frames stay in the same hemisphere."""
    flips = np.sum(quat[1:] * quat[:-1], axis=-1) < 0
    signs = np.concatenate([[1.0], np.where(np.cumsum(flips) % 2, -1.0, 1.0)])
    return quat * signs[:, None]


def _lowest_bvh_point(clip: BvhClip, axes: np.ndarray, frame: int) -> float:
    """World height (file units) of the lowest joint or End Site in one frame."""
    _, points = frame_points(clip, clip.frames[frame : frame + 1])
    return float((points[0] @ axes.T)[:, 2].min())
