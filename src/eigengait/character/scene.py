"""Turn a user's MJCF scene into an eigengait character spec, by fixed and documented rules.

* **The creature** is one articulated tree under `<worldbody>`: the body named by `body` (sidecar
  `body:` or `--body`), else the largest tree (most bodies, then most mass) among the worldbody's
  children that have joints. Other bodies stay in the scene as they are.
* **The root**: a free joint is kept; a root with no joint gets one (a note says so) and, if the
  creature's extent along y exceeds 1.2 × its extent along z (a Y-up model made to be attached by
  another tool), is turned +90° about x so that it stands along z; a root with slide/hinge joints
  (a planar root such as slide x, slide z, hinge y) keeps them as the character's rigid degrees of
freedom.
* **The model's actuators, sensors and keyframes are removed**: eigengait drives every internal
  degree of freedom with its own torque motors and reads its own sensors; a keyframe would no longer
  fit the state or the controls.
* **Reserved names**: everything eigengait adds is named with a prefix in `RESERVED_PREFIXES`; a
  model whose own names use one is refused, so the added names can never clash.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np

from eigengait.body_tree import in_subtree
from eigengait.errors import UserInputError

RESERVED_PREFIXES = ("eigengait:", "motor:", "spring:", "contact:", "pos:")
ROOT_JOINT_TYPES = (mujoco.mjtJoint.mjJNT_SLIDE, mujoco.mjtJoint.mjJNT_HINGE)
ADDED_FREE_JOINT = "eigengait:root"
UNNAMED_ROOT = "eigengait:body"  # the name given to an unnamed root body


@dataclass
class Scene:
    """What preparing the spec found: the creature's root body, its rigid root joints, and notes for
    the user."""

    root: str
    # planar root joints; empty for a free root
    root_joints: list[str] = field(default_factory=list)
    added_free_joint: bool = False
    # element kind -> how many of the model's were removed
    removed: dict[str, int] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


def compile_spec(spec: mujoco.MjSpec, path: Path | None = None) -> mujoco.MjModel:
    """`spec.compile()`, its errors as UserInputError naming `path`, without MuJoCo's deprecation
    notice on a model's own `settotalmass` (meant for the model's author; every command would print
    it several times)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="compiler attribute 'settotalmass' is deprecated")
        try:
            return spec.compile()
        except ValueError as exc:
            msg = str(exc).strip().replace("\n", " ")
            raise UserInputError(
                f"MuJoCo cannot compile the model: {msg}",
                file=path,
                fix="fix the MJCF so that `mujoco.MjModel.from_xml_path` loads it",
            ) from None


def _subtree(body) -> list:
    out, stack = [], [body]
    while stack:
        b = stack.pop()
        out.append(b)
        stack.extend(b.bodies)
    return out


def _has_joints(body) -> bool:
    return any(b.joints for b in _subtree(body))


def _tree_size(body) -> tuple[int, float]:
    return len(_subtree(body)), sum(float(b.mass) for b in _subtree(body))


def choose_root(spec: mujoco.MjSpec, path: Path, body: str | None):
    """The creature's root body: `body` if given, else the largest articulated tree under the
    worldbody."""
    trees = [b for b in spec.worldbody.bodies if _has_joints(b)]
    names = ", ".join(b.name or "(unnamed)" for b in trees) or "(none)"
    if body is not None:
        chosen = [
            b
            for b in spec.worldbody.bodies
            if b.name == body or (body == UNNAMED_ROOT and not b.name)
        ]
        if not chosen:
            raise UserInputError(
                f"no body '{body}' directly under <worldbody>",
                file=path,
                field="body",
                fix=f"name one of the articulated bodies: {names}",
            )
        return chosen[0]
    if not trees:
        raise UserInputError(
            "the model has no joints: nothing can move",
            file=path,
            field="worldbody",
            fix="add hinge or ball joints between the creature's bodies",
        )
    return max(trees, key=_tree_size)


def _check_reserved_names(spec: mujoco.MjSpec, path: Path) -> None:
    model = compile_spec(spec, path)
    for kind in (
        mujoco.mjtObj.mjOBJ_BODY,
        mujoco.mjtObj.mjOBJ_GEOM,
        mujoco.mjtObj.mjOBJ_SITE,
        mujoco.mjtObj.mjOBJ_JOINT,
        mujoco.mjtObj.mjOBJ_CAMERA,
        mujoco.mjtObj.mjOBJ_TEXTURE,
        mujoco.mjtObj.mjOBJ_MATERIAL,
        mujoco.mjtObj.mjOBJ_LIGHT,
        mujoco.mjtObj.mjOBJ_TENDON,
    ):
        for i in range(_count(model, kind)):
            name = mujoco.mj_id2name(model, kind, i) or ""
            if name.startswith(RESERVED_PREFIXES):
                what = kind.name[len("mjOBJ_") :].lower()
                raise UserInputError(
                    f"{what} name '{name}' uses a prefix eigengait reserves for what it adds",
                    file=path,
                    field=f"{what} '{name}'",
                    fix=f"rename it without the prefixes {', '.join(RESERVED_PREFIXES)}",
                )


def _count(model: mujoco.MjModel, kind: mujoco.mjtObj) -> int:
    return {
        mujoco.mjtObj.mjOBJ_BODY: model.nbody,
        mujoco.mjtObj.mjOBJ_GEOM: model.ngeom,
        mujoco.mjtObj.mjOBJ_SITE: model.nsite,
        mujoco.mjtObj.mjOBJ_JOINT: model.njnt,
        mujoco.mjtObj.mjOBJ_CAMERA: model.ncam,
        mujoco.mjtObj.mjOBJ_TEXTURE: model.ntex,
        mujoco.mjtObj.mjOBJ_MATERIAL: model.nmat,
        mujoco.mjtObj.mjOBJ_LIGHT: model.nlight,
        mujoco.mjtObj.mjOBJ_TENDON: model.ntendon,
    }[kind]


def _is_y_up(spec: mujoco.MjSpec, root: str) -> bool:
    model = compile_spec(spec)
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    r = model.body(root).id
    geoms = [g for g in range(model.ngeom) if in_subtree(model, int(model.geom_bodyid[g]), r)]
    if not geoms:
        return False
    lo = np.min([data.geom_xpos[g] - model.geom_rbound[g] for g in geoms], axis=0)
    hi = np.max([data.geom_xpos[g] + model.geom_rbound[g] for g in geoms], axis=0)
    _, y, z = hi - lo
    return bool(y > 1.2 * z)


def _body_quat(spec: mujoco.MjSpec, name: str) -> np.ndarray:
    model = compile_spec(spec)
    return model.body(name).quat.copy()


def prepare(spec: mujoco.MjSpec, path: Path, body: str | None = None) -> Scene:
    """Edit `spec` in place into an eigengait character (rules in the module docstring)."""
    _check_reserved_names(spec, path)
    root = choose_root(spec, path, body)
    where = f"body '{root.name}'" if root.name else "the root body (unnamed)"
    root.name = root.name or UNNAMED_ROOT
    scene = Scene(root=root.name)
    for kind, elements in (
        ("actuator", spec.actuators),
        ("sensor", spec.sensors),
        ("keyframe", spec.keys),
    ):
        items = list(elements)
        for element in items:
            spec.delete(element)
        if items:
            scene.removed[kind] = len(items)
    if scene.removed:
        scene.notes.append(
            "removed the model's "
            + ", ".join(f"{n} {k}(s)" for k, n in scene.removed.items())
            + ": eigengait drives every joint with its own motors and sensors"
        )

    joints = list(root.joints)
    if not joints:
        root.add_freejoint(name=ADDED_FREE_JOINT)
        scene.added_free_joint = True
        scene.notes.append(
            f"the root body '{root.name}' had no joint: added a free joint '{ADDED_FREE_JOINT}'"
        )
        if _is_y_up(spec, root.name):
            q = np.zeros(4)
            mujoco.mju_mulQuat(
                q, np.array([np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0]), _body_quat(spec, root.name)
            )
            root.quat = q
            root.alt.type = mujoco.mjtOrientation.mjORIENTATION_QUAT
            scene.notes.append(
                "the creature is longest along y (Y-up): turned +90° about x to stand along z"
            )
    elif any(j.type == mujoco.mjtJoint.mjJNT_FREE for j in joints):
        if len(joints) != 1:
            raise UserInputError(
                "the root body has a free joint and other joints",
                file=path,
                field=where,
                fix="keep only the free joint on the root body",
            )
    else:
        for j in joints:
            if j.type not in ROOT_JOINT_TYPES or not j.name:
                raise UserInputError(
                    "a root joint must be a named slide or hinge (or one free joint)",
                    file=path,
                    field=where,
                    fix="name the root's slide/hinge joints",
                )
        scene.root_joints = [j.name for j in joints]
        scene.notes.append(
            f"root '{root.name}' moves by its own joints ({', '.join(scene.root_joints)}): "
            "kept as the character's rigid degrees of freedom"
        )
    for b in _subtree(root)[1:]:
        for j in b.joints:
            if j.type == mujoco.mjtJoint.mjJNT_FREE:
                raise UserInputError(
                    "only the root body may have a free joint",
                    file=path,
                    field=f"joint '{j.name}' in body '{b.name}'",
                    fix="remove the free joint",
                )
    return scene
