"""A World's qpos trajectory as a BVH clip (one BVH joint per body), for Blender and other animation
tools.

Axes and units: BVH (x, y, z) = (x, z, −y) of MuJoCo's z-up world. That axis map is the inverse of
Blender's default BVH import (forward −Z, up Y), so the clip lands in Blender exactly where it
stands in MuJoCo. Lengths are in metres by default (`units="m"`: Blender's default import scale 1
gives a life-size character) or centimetres (`units="cm"`, the unit of most motion-capture BVH and
of MotionBuilder-style tools).

Skeleton: each body's BVH joint sits at its MuJoCo joint anchor (the body origin for the root and
for bodies without a joint). The rest pose (all channels zero) is the relax pose, so offsets are the
relax-pose vectors from parent anchor to child anchor; the root has 6 channels (absolute position,
so root motion is kept, then ZXY rotation), the other joints 3 (ZXY). Every foot of the character
ends in an End Site at its toe site: on the foot's own body when that body points along the foot
(heel to toe), otherwise on an added joint `<foot>_foot` at the heel, fixed to its parent (channels
always zero), so the foot's bone points from heel to toe. Other leaf bodies get an End Site at the
tip of their first box: the face centre farthest from their anchor.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
from scipy.spatial.transform import Rotation

from eigengait.body_tree import in_subtree
from eigengait.errors import UserInputError
from eigengait.geometry import quat_to_mat
from eigengait.motion.bvh import BvhClip, BvhJoint, write_bvh
from eigengait.sim.world import World

UNIT_SCALE = {"m": 1.0, "cm": 100.0}  # BVH length units per metre
DEFAULT_UNITS = "m"
FOOT_ALIGNMENT_DEG = 45.0  # a body whose anchor→toe is within this of heel→toe is the foot's bone
MUJOCO_TO_BVH = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])  # rows: BVH x, y, z
ROOT_CHANNELS = ["Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation"]
JOINT_CHANNELS = ["Zrotation", "Xrotation", "Yrotation"]
EULER_ORDER = "ZXY"  # intrinsic, matching the channel order above


def skeleton_bodies(world: World) -> list[int]:
    """Body ids of the character in MuJoCo's depth-first order (parents before children), root
    first. (Below the root every joint is a ball or a hinge: the loader refuses others.)"""
    model = world.model
    return [b for b in range(model.nbody) if in_subtree(model, b, world.root_body)]


def anchor_points(world: World, data: mujoco.MjData, bodies: list[int]) -> np.ndarray:
    """World positions (m) of each body's first joint anchor, or its origin if it has no joint
    (len(bodies) × 3)."""
    model = world.model
    return np.array(
        [
            data.xanchor[model.body_jntadr[b]] if model.body_jntnum[b] else data.xpos[b]
            for b in bodies
        ]
    )


def _local_anchor(model: mujoco.MjModel, body: int) -> np.ndarray:
    return model.jnt_pos[model.body_jntadr[body]] if model.body_jntnum[body] else np.zeros(3)


def _leaf_tip(model: mujoco.MjModel, body: int) -> np.ndarray | None:
    """Tip of the body's first box in the body frame: its face centre farthest from the anchor
    (m)."""
    geoms = [
        g
        for g in range(
            model.body_geomadr[body], model.body_geomadr[body] + model.body_geomnum[body]
        )
        if not model.geom(g).name.startswith("contact:")
    ]
    boxes = [g for g in geoms if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX]
    if boxes:
        g = boxes[0]
        axes = quat_to_mat(model.geom_quat[g])
        faces = (
            model.geom_pos[g]
            + np.concatenate([axes * model.geom_size[g], -axes * model.geom_size[g]], axis=1).T
        )
    elif geoms:
        faces = model.geom_pos[geoms]
    else:
        return None
    return faces[np.argmax(np.linalg.norm(faces - _local_anchor(model, body), axis=1))]


def _foot_ends(
    world: World, leaves: set[int]
) -> dict[int, tuple[np.ndarray | None, np.ndarray, str]]:
    """Per leaf body carrying a toe site: (heel of an added foot joint or None, toe, foot name),
    body frame (m)."""
    model, ends = world.model, {}
    for foot, sites in world.character.feet.items():
        toe_id = model.site(sites.toe).id
        body = int(model.site_bodyid[toe_id])
        if body not in leaves:
            continue
        toe = model.site_pos[toe_id].copy()
        heel = model.site_pos[model.site(sites.heel).id].copy() if sites.heel else None
        along = toe - _local_anchor(model, body)
        aligned = heel is None or _angle_deg(along, toe - heel) <= FOOT_ALIGNMENT_DEG
        ends[body] = (None if aligned else heel, toe, foot)
    return ends


def _angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    return float(
        np.degrees(np.arccos(np.clip(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)), -1, 1)))
    )


def _unit_scale(units: str) -> float:
    if units not in UNIT_SCALE:
        raise UserInputError(
            f"unknown BVH length unit '{units}'", field="bvh_units", fix="use m or cm"
        )
    return UNIT_SCALE[units]


def trajectory_to_clip(
    world: World, qpos: np.ndarray, fps: float, units: str = DEFAULT_UNITS
) -> BvhClip:
    """BVH clip of a qpos trajectory (T × nq) sampled at `fps` frames per second, lengths in `units`
    ("m" or "cm"; axes and skeleton: module doc)."""
    model = world.model
    qpos = np.atleast_2d(qpos)
    if qpos.shape[1] != model.nq:
        raise UserInputError(
            f"trajectory has {qpos.shape[1]} coordinates per frame, the model {model.nq}",
            field="qpos",
        )
    bodies = skeleton_bodies(world)
    data = mujoco.MjData(model)

    def pose(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        return anchor_points(world, data, bodies), data.xmat[bodies].reshape(-1, 3, 3).copy()

    rest_points, rest_rot = pose(model.qpos0)
    scale = _unit_scale(units) * MUJOCO_TO_BVH
    leaves = {b for b in bodies if not any(int(model.body_parentid[c]) == b for c in bodies[1:])}
    feet = _foot_ends(world, leaves)
    names = {model.body(b).name for b in bodies}
    joints: list[BvhJoint] = []
    joint_of_body: dict[int, int] = {}
    body_index = []  # per BVH joint: index into `bodies`, or None for an added foot joint
    for i, b in enumerate(bodies):
        parent_body = int(model.body_parentid[b])
        parent = -1 if i == 0 else joint_of_body[parent_body]
        offset = (
            np.zeros(3)
            if parent < 0
            else scale @ (rest_points[i] - rest_points[body_index[parent]])
        )
        anchor = _local_anchor(model, b)
        heel, toe, foot = feet.get(b, (None, None, None))
        tip = toe if b in feet else (_leaf_tip(model, b) if b in leaves else None)
        end_site = None if tip is None or heel is not None else scale @ rest_rot[i] @ (tip - anchor)
        joint_of_body[b] = len(joints)
        body_index.append(i)
        joints.append(
            BvhJoint(
                name=model.body(b).name or f"body{b}",
                parent=parent,
                offset=offset,
                channels=ROOT_CHANNELS if parent < 0 else JOINT_CHANNELS,
                end_site=end_site,
            )
        )
        if heel is not None:
            body_index.append(None)
            joints.append(
                BvhJoint(
                    name=_unique(f"{foot}_foot", names),
                    parent=joint_of_body[b],
                    offset=scale @ rest_rot[i] @ (heel - anchor),
                    channels=JOINT_CHANNELS,
                    end_site=scale @ rest_rot[i] @ (toe - heel),
                )
            )

    frames = np.zeros((len(qpos), 3 + 3 * len(joints)))
    moving = [k for k, i in enumerate(body_index) if i is not None]
    columns = np.concatenate([3 + 3 * k + np.arange(3) for k in moving])
    # index into `bodies` of each parent
    parents = [body_index[joints[k].parent] for k in moving[1:]]
    for t, q in enumerate(qpos):
        points, rot = pose(q)
        # Each body's rotation away from its relax orientation, expressed in BVH axes.
        rel = MUJOCO_TO_BVH @ rot @ rest_rot.transpose(0, 2, 1) @ MUJOCO_TO_BVH.T
        local = np.array(
            [rel[0]] + [rel[p].T @ rel[i] for p, i in zip(parents, range(1, len(bodies)))]
        )
        frames[t, :3] = scale @ points[0]
        frames[t, columns] = Rotation.from_matrix(local).as_euler(EULER_ORDER, degrees=True).ravel()
    frames[:, 3:] = np.rad2deg(np.unwrap(np.deg2rad(frames[:, 3:]), axis=0))
    return BvhClip(joints=joints, frame_time=1.0 / fps, frames=frames)


def _unique(name: str, taken: set[str]) -> str:
    while name in taken:
        name += "_end"
    taken.add(name)
    return name


def write_trajectory_bvh(
    world: World,
    qpos: np.ndarray,
    source_fps: float,
    path: str | Path,
    fps: float | None = None,
    units: str = DEFAULT_UNITS,
) -> BvhClip:
    """Write a qpos trajectory (T × nq, recorded at `source_fps`) as BVH at exactly `fps` frames per
    second (default: `source_fps`), resampled by time (`eigengait.motion.resample`); see
    :func:`trajectory_to_clip`."""
    from eigengait.motion.resample import at_frame_rate

    if fps is not None and fps != source_fps:
        qpos = at_frame_rate(world.model, qpos, source_fps, fps)
    clip = trajectory_to_clip(world, qpos, fps or source_fps, units)
    write_bvh(clip, path)
    return clip
