"""Load and validate a character: an MJCF creature with stiff ball/hinge joints, plus metadata.

CHARACTER is a built-in name, an MJCF path, or a sidecar `NAME.eigengait.yaml` whose `model:` names
the MJCF. The scene is prepared by the rules of `scene.py` (creature choice, root, actuators,
reserved names); missing feet are guessed by `guess.py`; a joint's stiffness comes from the sidecar,
else the MJCF, else — only when asked for with `stiffness="auto"` — from the sag rule of
`stiffness.py`.

The loaded :class:`Character` can produce a fresh `mujoco.MjSpec` at any relax pose (see
`relax.py`): the springs rest at the relax pose, joint frames and limits are measured from it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np

from eigengait.character.guess import FOOT_SITE_PREFIX, FootPoint, find_feet, foot_at
from eigengait.character.library import resolve_character
from eigengait.character.metadata import (
    CharacterMetadata,
    Foot,
    is_sidecar,
    load_metadata,
    sidecar_path,
)
from eigengait.character.scene import Scene, compile_spec, prepare
from eigengait.character.stiffness import SAG_DEG, auto_stiffness
from eigengait.errors import UserInputError

JOINT_DOFS = {mujoco.mjtJoint.mjJNT_BALL: 3, mujoco.mjtJoint.mjJNT_HINGE: 1}
STIFFNESS_CHOICES = ("auto",)


@dataclass
class Character:
    """A validated character. `path` is its MJCF file; `joints` lists the internal joints in model
    order."""

    name: str
    path: Path
    meta: CharacterMetadata
    joints: list[str]
    joint_dofs: dict[str, int]
    # joint -> (3,) or (1,) N·m/rad, joint frame
    stiffness: dict[str, np.ndarray] = field(repr=False)
    scene: Scene = None
    guessed_feet: list[FootPoint] = field(default_factory=list)
    # joint -> "sidecar", "mjcf" or "auto"
    stiffness_source: dict[str, str] = field(default_factory=dict)
    sidecar: Path | None = None

    @property
    def reference(self) -> Path:
        """What to pass as CHARACTER to load this character again: the sidecar if it names the
        model."""
        return self.sidecar if self.sidecar is not None and self.meta.model else self.path

    @property
    def internal_dofs(self) -> int:
        return sum(self.joint_dofs.values())

    @property
    def feet(self) -> dict[str, Foot]:
        return self.meta.feet

    @property
    def root_joints(self) -> list[str]:
        """The planar root's slide/hinge joints (rigid degrees of freedom); empty for a free
        root."""
        return self.scene.root_joints

    def raw_spec(self) -> mujoco.MjSpec:
        """The user's MJCF as a fresh spec, prepared (`scene.py`) and with the guessed foot
        sites."""
        spec = _parse(self.path)
        prepare(spec, self.path, self.scene.root)
        _add_foot_sites(spec, self.guessed_feet)
        return spec


def _parse(path: Path) -> mujoco.MjSpec:
    try:
        return mujoco.MjSpec.from_file(str(path))
    except Exception as exc:  # MuJoCo raises ValueError with its own parser message
        msg = str(exc).strip().replace("\n", " ")
        raise UserInputError(
            f"malformed MJCF: {msg}", file=path, fix="fix the XML so MuJoCo can load it"
        ) from None


def _add_foot_sites(spec: mujoco.MjSpec, feet: list[FootPoint]) -> None:
    for f in feet:
        spec.body(f.body).add_site(
            name=f.site, pos=list(f.pos), size=[f.radius, 0, 0], zaxis=list(f.up)
        )
        if f.heel is not None:
            spec.body(f.body).add_site(
                name=f.heel_site, pos=list(f.heel), size=[f.heel_radius, 0, 0]
            )


def _locate(name_or_path: str | Path) -> tuple[Path, Path, CharacterMetadata]:
    """(MJCF path, sidecar path, metadata) of a built-in name, MJCF path or standalone sidecar."""
    path = resolve_character(name_or_path)
    if is_sidecar(path):
        meta = load_metadata(path)
        if not meta.model:
            raise UserInputError(
                "this sidecar does not name its model",
                file=path,
                field="model",
                fix="add `model: path/to/creature.xml` (relative to the sidecar), or pass the MJCF",
            )
        mjcf = (path.parent / meta.model).resolve()
        if not mjcf.is_file():
            raise UserInputError(
                f"model file '{mjcf}' not found",
                file=path,
                field="model",
                fix="give the MJCF path relative to the sidecar",
            )
        return mjcf, path, meta
    side = sidecar_path(path)
    return path, side, (load_metadata(side) if side.exists() else CharacterMetadata())


def load_character(
    name_or_path: str | Path, body: str | None = None, stiffness: str | None = None
) -> Character:
    """Load a character (built-in name, MJCF path or sidecar path).

    `body` picks the creature's root body in a scene with several (default: the sidecar's, else the
    largest); `stiffness="auto"` gives joints with no stiffness one by the sag rule (also asked for
    by `stiffness: auto` in the sidecar).
    """
    if stiffness is not None and stiffness not in STIFFNESS_CHOICES:
        raise UserInputError(
            f"unknown stiffness rule '{stiffness}'", field="stiffness", fix="pass stiffness='auto'"
        )
    path, side, meta = _locate(name_or_path)
    spec = _parse(path)
    scene = prepare(spec, path, body or meta.body)
    model = compile_spec(spec, path)
    root = model.body(scene.root).id
    joints = _internal_joints(model, root, scene, path)

    sites = {model.site(i).name for i in range(model.nsite)}
    guessed = []
    named = [
        f.toe[len(FOOT_SITE_PREFIX) :]
        for f in meta.feet.values()
        if f.toe.startswith(FOOT_SITE_PREFIX) and f.toe not in sites
    ]
    if named:
        guessed = [_named_foot(model, body, side) for body in named]
        _add_foot_sites(spec, guessed)
        model = compile_spec(spec, path)
        sites |= {s for f in guessed for s in (f.site, f.heel_site) if s}
        heels = {f.site: f.heel_site for f in guessed}
        for f in meta.feet.values():
            if f.heel is None and heels.get(f.toe):
                f.heel = heels[f.toe]
    elif not meta.feet and not any(s.endswith("_toe") for s in sites):
        guessed = find_feet(model, root)
        _add_foot_sites(spec, guessed)
        model = compile_spec(spec, path)
        sites |= {s for f in guessed for s in (f.site, f.heel_site) if s}
        meta.feet = {f.body: Foot(toe=f.site, heel=f.heel_site) for f in guessed}
        if guessed:
            scene.notes.append(
                f"feet guessed from the lowest end bodies: {', '.join(f.body for f in guessed)}"
            )

    use_auto = stiffness == "auto" or meta.stiffness == "auto"
    given = {} if meta.stiffness == "auto" else meta.stiffness
    auto = auto_stiffness(model, [j for j in joints if j not in given]) if use_auto else {}
    dofs, k_of, source = {}, {}, {}
    for name in joints:
        j = model.joint(name).id
        n = JOINT_DOFS[mujoco.mjtJoint(model.jnt_type[j])]
        k_native = float(model.jnt_stiffness[j])
        if name in given:
            k, source[name] = np.atleast_1d(np.asarray(given[name], dtype=float)), "sidecar"
            k = np.repeat(k, n) if k.size == 1 else k
        elif k_native > 0:
            k, source[name] = np.full(n, k_native), "mjcf"
        elif name in auto:
            k, source[name] = np.full(n, auto[name]), "auto"
        else:
            raise UserInputError(
                "joint has no stiffness",
                file=path,
                field=f"joint '{name}' stiffness",
                fix=(
                    'give it stiffness="..." (N·m/rad) in the MJCF or in the sidecar, or pass '
                    'stiffness=\'auto\''
                ),
            )
        dofs[name], k_of[name] = n, k[:n]
    if "auto" in source.values():
        ks = [k_of[j][0] for j in joints if source[j] == "auto"]
        scene.notes.append(
            f"stiffness auto (the sag rule): {len(ks)} joint(s) given k = m·g·r/θ_sag (θ_sag = "
            f"{SAG_DEG:g}°), {min(ks):.3g} to {max(ks):.3g} N·m/rad"
        )

    _check_metadata(meta, side, joints, sites)
    return Character(
        name=(side.name[: -len(".eigengait.yaml")] if meta.model else path.stem),
        path=path,
        meta=meta,
        joints=joints,
        joint_dofs=dofs,
        stiffness=k_of,
        scene=scene,
        guessed_feet=guessed,
        stiffness_source=source,
        sidecar=side if side.exists() else None,
    )


def _named_foot(model: mujoco.MjModel, body: str, side: Path) -> FootPoint:
    if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body) < 0:
        raise UserInputError(
            f"foot site names body '{body}', which is not in the MJCF",
            file=side,
            field="feet",
            fix=f"write toe: {FOOT_SITE_PREFIX}<body> with an existing body name",
        )
    point = foot_at(model, body)
    if point is None:
        raise UserInputError(
            f"body '{body}' has no geom to stand on",
            file=side,
            field="feet",
            fix="name a body with a geom",
        )
    return point


def _internal_joints(model: mujoco.MjModel, root: int, scene: Scene, path: Path) -> list[str]:
    """The creature's non-root joints in model order; ball or hinge, named."""
    joints = []
    for j in range(model.njnt):
        b = int(model.jnt_bodyid[j])
        while b > 0 and b != root:
            b = int(model.body_parentid[b])
        name = model.joint(j).name
        if b != root or int(model.jnt_bodyid[j]) == root:
            continue
        jtype = mujoco.mjtJoint(model.jnt_type[j])
        if jtype not in JOINT_DOFS:
            raise UserInputError(
                f"joint type {jtype.name} is not supported inside the creature",
                file=path,
                field=f"joint '{name}'",
                fix="use ball or hinge joints",
            )
        if not name:
            raise UserInputError(
                "every joint needs a name",
                file=path,
                field=f"joint #{j} in body '{model.body(model.jnt_bodyid[j]).name}'",
                fix='add name="..." to the joint',
            )
        joints.append(name)
    if not joints:
        raise UserInputError(
            "the creature has no internal joints", file=path, fix="add ball or hinge joints"
        )
    return joints


def _check_metadata(
    meta: CharacterMetadata, side: Path, joints: list[str], sites: set[str]
) -> None:
    if not meta.feet:
        meta.feet = {
            s[: -len("_toe")]: Foot(
                toe=s, heel=(s[:-4] + "_heel") if s[:-4] + "_heel" in sites else None
            )
            for s in sorted(sites)
            if s.endswith("_toe")
        }
    for foot, f in meta.feet.items():
        for point in (f.toe, f.heel):
            if point is not None and point not in sites:
                raise UserInputError(
                    f"foot '{foot}' names site '{point}', which is not in the MJCF",
                    file=side,
                    field=f"feet.{foot}",
                    fix=f"add <site name=\"{point}\"/> or fix the name",
                )
    if not meta.gait_order:
        meta.gait_order = list(meta.feet)
    for foot in meta.gait_order:
        if foot not in meta.feet:
            raise UserInputError(
                f"gait_order names unknown foot '{foot}'", file=side, field="gait_order"
            )
    if meta.mirror:
        for a, b in meta.mirror.pairs.items():
            for j in (a, b):
                if j not in joints:
                    raise UserInputError(
                        f"mirror pair names unknown joint '{j}'", file=side, field="mirror.pairs"
                    )
    for j in {} if meta.stiffness == "auto" else meta.stiffness:
        if j not in joints:
            raise UserInputError(
                f"stiffness given for unknown joint '{j}'", file=side, field="stiffness"
            )
    for pose, rot in meta.relax_poses.items():
        for j in rot:
            if j not in joints:
                raise UserInputError(
                    f"relax pose '{pose}' names unknown joint '{j}'",
                    file=side,
                    field=f"relax_poses.{pose}",
                )
