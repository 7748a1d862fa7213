"""Load and validate a character: MJCF with a free-joint root and stiff ball/hinge joints, plus metadata.

The loaded :class:`Character` can produce a fresh `mujoco.MjSpec` at any relax pose (see `relax.py`): the
springs rest at the relax pose, joint frames and limits are measured from it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np

from eigengait.character.library import resolve_character
from eigengait.character.metadata import CharacterMetadata, Foot, load_metadata, sidecar_path
from eigengait.errors import UserInputError

JOINT_DOFS = {mujoco.mjtJoint.mjJNT_BALL: 3, mujoco.mjtJoint.mjJNT_HINGE: 1}


@dataclass
class Character:
    """A validated character. `path` is its MJCF file; `joints` lists the internal joints in model order."""
    name: str
    path: Path
    meta: CharacterMetadata
    joints: list[str]
    joint_dofs: dict[str, int]
    stiffness: dict[str, np.ndarray] = field(repr=False)   # joint -> (3,) or (1,) N·m/rad, joint frame

    @property
    def internal_dofs(self) -> int:
        return sum(self.joint_dofs.values())

    @property
    def feet(self) -> dict[str, Foot]:
        return self.meta.feet

    @property
    def is_anisotropic(self) -> bool:
        return any(np.ptp(k) > 0 for k in self.stiffness.values())

    def raw_spec(self) -> mujoco.MjSpec:
        """The user's MJCF as a fresh spec, unchanged."""
        return _parse(self.path)


def _parse(path: Path) -> mujoco.MjSpec:
    try:
        return mujoco.MjSpec.from_file(str(path))
    except Exception as exc:  # MuJoCo raises ValueError with its own parser message
        msg = str(exc).strip().replace("\n", " ")
        raise UserInputError(f"malformed MJCF: {msg}", file=path, fix="fix the XML so MuJoCo can load it") from None


def _root_body(spec: mujoco.MjSpec, path: Path):
    roots = [b for b in spec.worldbody.bodies]
    movable = [b for b in roots if b.joints]
    if len(movable) != 1:
        raise UserInputError(f"expected exactly one moving body under <worldbody>, found {len(movable)}",
                             file=path, field="worldbody",
                             fix="put the whole creature under one root body with a <freejoint/>")
    root = movable[0]
    if len(root.joints) != 1 or root.joints[0].type != mujoco.mjtJoint.mjJNT_FREE:
        raise UserInputError("the root body has no free joint", file=path, field=f"body '{root.name}'",
                             fix="add <freejoint/> to the root body")
    return root


def load_character(name_or_path: str | Path) -> Character:
    """Load a built-in character by name or a user MJCF path, with its sidecar if present."""
    path = resolve_character(name_or_path)
    spec = _parse(path)
    side = sidecar_path(path)
    meta = load_metadata(side) if side.exists() else CharacterMetadata()
    _root_body(spec, path)
    try:
        model = spec.compile()
    except Exception as exc:
        raise UserInputError(f"MuJoCo cannot compile the model: {exc}", file=path) from None

    joints, dofs, stiffness = [], {}, {}
    for j in range(model.njnt):
        jtype = mujoco.mjtJoint(model.jnt_type[j])
        name = model.joint(j).name
        if jtype == mujoco.mjtJoint.mjJNT_FREE:
            if model.body_parentid[model.jnt_bodyid[j]] != 0:
                raise UserInputError("only the root body may have a free joint", file=path, field=f"joint '{name}'")
            continue
        if jtype not in JOINT_DOFS:
            raise UserInputError(f"joint type {jtype.name} is not supported", file=path, field=f"joint '{name}'",
                                 fix="use ball or hinge joints")
        if not name:
            raise UserInputError("every joint needs a name", file=path,
                                 field=f"joint #{j} in body '{model.body(model.jnt_bodyid[j]).name}'",
                                 fix='add name="..." to the joint')
        k_native = float(model.jnt_stiffness[j])
        k = np.asarray(meta.stiffness.get(name, [k_native] * JOINT_DOFS[jtype]), dtype=float)
        if JOINT_DOFS[jtype] == 1:
            k = k[:1]
        if np.any(k <= 0):
            raise UserInputError("joint has no stiffness", file=path, field=f"joint '{name}' stiffness",
                                 fix='give it stiffness="..." (N·m/rad) in the MJCF or in the sidecar')
        joints.append(name)
        dofs[name] = JOINT_DOFS[jtype]
        stiffness[name] = k
    if not joints:
        raise UserInputError("the model has no internal joints", file=path, fix="add ball or hinge joints")

    _check_metadata(meta, path, side, joints, {model.site(i).name for i in range(model.nsite)})
    return Character(name=path.stem, path=path, meta=meta, joints=joints, joint_dofs=dofs, stiffness=stiffness)


def _check_metadata(meta: CharacterMetadata, path: Path, side: Path, joints: list[str], sites: set[str]) -> None:
    if not meta.feet:
        meta.feet = {s[: -len("_toe")]: Foot(toe=s, heel=(s[:-4] + "_heel") if s[:-4] + "_heel" in sites else None)
                     for s in sorted(sites) if s.endswith("_toe")}
    for foot, f in meta.feet.items():
        for point in (f.toe, f.heel):
            if point is not None and point not in sites:
                raise UserInputError(f"foot '{foot}' names site '{point}', which is not in the MJCF", file=side,
                                     field=f"feet.{foot}", fix=f"add <site name=\"{point}\"/> or fix the name")
    if not meta.gait_order:
        meta.gait_order = list(meta.feet)
    for foot in meta.gait_order:
        if foot not in meta.feet:
            raise UserInputError(f"gait_order names unknown foot '{foot}'", file=side, field="gait_order")
    if meta.mirror:
        for a, b in meta.mirror.pairs.items():
            for j in (a, b):
                if j not in joints:
                    raise UserInputError(f"mirror pair names unknown joint '{j}'", file=side, field="mirror.pairs")
    for j in meta.stiffness:
        if j not in joints:
            raise UserInputError(f"stiffness given for unknown joint '{j}'", file=side, field="stiffness")
    for pose, rot in meta.relax_poses.items():
        for j in rot:
            if j not in joints:
                raise UserInputError(f"relax pose '{pose}' names unknown joint '{j}'", file=side,
                                     field=f"relax_poses.{pose}")
