"""Regenerate the built-in character library (MJCF + sidecar YAML) in
src/eigengait/data/characters/.

Every creature is a tree of boxes (water density, 1000 kg/m³) joined by ball joints at the child
body's origin, in MuJoCo's z-up world, facing +x with its left side at +y. Feet carry `<site>`s
named `<foot>_toe` and `<foot>_heel`; the world turns them into contact spheres. Run:
`python scripts/make_characters.py`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import yaml

OUT = Path(__file__).resolve().parents[1] / "src" / "eigengait" / "data" / "characters"
SKIN = "0.85 0.62 0.45 1"
CLOTH = "0.25 0.45 0.75 1"


@dataclass
class Box:
    """A box geom: half sizes (m) and centre in the body frame (m)."""

    half: tuple[float, float, float]
    centre: tuple[float, float, float]
    rgba: str = CLOTH


@dataclass
class Limb:
    """A body with a ball joint at its origin (unless it is the root)."""

    name: str
    pos: tuple[float, float, float]  # origin in the parent frame (m)
    boxes: list[Box]
    stiffness: float = 0.0  # N·m/rad, isotropic
    range_deg: float = 90.0  # ball-joint cone limit
    children: list["Limb"] = field(default_factory=list)
    sites: dict[str, tuple[float, float, float]] = field(default_factory=dict)


def fmt(v) -> str:
    return " ".join(f"{x:g}" for x in v)


def body_xml(limb: Limb, depth: int, root: bool) -> list[str]:
    pad = "  " * depth
    lines = [f'{pad}<body name="{limb.name}" pos="{fmt(limb.pos)}">']
    if root:
        lines.append(f'{pad}  <freejoint name="root"/>')
    else:
        lines.append(
            f'{pad}  <joint name="{limb.name}" type="ball" stiffness="{limb.stiffness:g}" '
            f'range="0 {limb.range_deg:g}"/>'
        )
    for i, box in enumerate(limb.boxes):
        suffix = "" if i == 0 else f"_{i}"
        lines.append(
            f'{pad}  <geom name="{limb.name}{suffix}" type="box" size="{fmt(box.half)}" '
            f'pos="{fmt(box.centre)}" rgba="{box.rgba}"/>'
        )
    for name, p in limb.sites.items():
        lines.append(f'{pad}  <site name="{name}" pos="{fmt(p)}" size="0.02"/>')
    for child in limb.children:
        lines += body_xml(child, depth + 1, root=False)
    lines.append(f"{pad}</body>")
    return lines


def write(name: str, root: Limb, meta: dict, comment: str) -> None:
    lines = [
        f"<!-- eigengait built-in character '{name}': {comment} -->",
        f'<mujoco model="{name}">',
        '  <compiler angle="degree"/>',
        '  <option timestep="0.0005"/>',
        '  <default><geom density="1000" contype="1" conaffinity="0" friction="1 0.005 0.0001"/>'
        '<joint limited="true"/></default>',
        "  <worldbody>",
    ]
    lines += body_xml(root, 2, root=True)
    lines += ["  </worldbody>", "</mujoco>", ""]
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / f"{name}.xml").write_text("\n".join(lines))
    (OUT / f"{name}.eigengait.yaml").write_text(
        yaml.safe_dump({"eigengait": 1, **meta}, sort_keys=False)
    )


# ---------------------------------------------------------------- shared limbs


def arm(side: str, y: float, z: float, k_shoulder: float, k_elbow: float, tag: str = "") -> Limb:
    s = 1 if side == "left" else -1
    return Limb(
        f"{side}{tag}_upper_arm",
        (0, s * y, z),
        [Box((0.04, 0.04, 0.14), (0, s * 0.045, -0.14))],
        k_shoulder,
        120,
        children=[
            Limb(
                f"{side}{tag}_forearm",
                (0, s * 0.045, -0.28),
                [Box((0.035, 0.035, 0.13), (0, 0, -0.13), SKIN)],
                k_elbow,
                110,
            )
        ],
    )


def leg(side: str, y: float, k_hip: float, k_knee: float) -> Limb:
    s = 1 if side == "left" else -1
    return Limb(
        f"{side}_thigh",
        (0, s * y, -0.08),
        [Box((0.065, 0.065, 0.21), (0, 0, -0.21))],
        k_hip,
        100,
        children=[
            Limb(
                f"{side}_shin",
                (0, 0, -0.42),
                [
                    Box((0.05, 0.05, 0.20), (0, 0, -0.20)),
                    Box((0.11, 0.05, 0.03), (0.06, 0, -0.44), SKIN),
                ],
                k_knee,
                110,
                sites={f"{side}_toe": (0.15, 0, -0.48), f"{side}_heel": (-0.03, 0, -0.48)},
            )
        ],
    )


LR_PAIRS = {
    "left_thigh": "right_thigh",
    "left_shin": "right_shin",
    "left_upper_arm": "right_upper_arm",
    "left_forearm": "right_forearm",
}
BIPED_FEET = {
    "left": {"toe": "left_toe", "heel": "left_heel"},
    "right": {"toe": "right_toe", "heel": "right_heel"},
}


def humanoid_torso(extra_arms: bool) -> Limb:
    arms = [arm("left", 0.16, 0.32, 60, 40), arm("right", 0.16, 0.32, 60, 40)]
    if extra_arms:
        arms += [
            arm("left", 0.16, 0.14, 60, 40, "_second"),
            arm("right", 0.16, 0.14, 60, 40, "_second"),
        ]
    return Limb(
        "torso",
        (0, 0, 0.08),
        [Box((0.10, 0.16, 0.18), (0, 0, 0.18))],
        500,
        60,
        children=[
            Limb("head", (0, 0, 0.36), [Box((0.09, 0.08, 0.11), (0, 0, 0.12), SKIN)], 60, 60),
            *arms,
        ],
    )


def biped(extra_arms: bool) -> Limb:
    return Limb(
        "pelvis",
        (0, 0, 1.0),
        [Box((0.10, 0.15, 0.08), (0, 0, 0))],
        children=[
            humanoid_torso(extra_arms),
            leg("left", 0.09, 400, 300),
            leg("right", 0.09, 400, 300),
        ],
    )


def humanoid() -> None:
    poses = {
        "crouched": {
            "left_thigh": [0, -35, 0],
            "right_thigh": [0, -35, 0],
            "left_shin": [0, 35, 0],
            "right_shin": [0, 35, 0],
            "torso": [0, 15, 0],
        },
        "legs-apart": {"left_thigh": [-12, 0, 0], "right_thigh": [12, 0, 0]},
        "one-leg": {"right_thigh": [0, -50, 0], "right_shin": [0, 80, 0]},
    }
    write(
        "humanoid",
        biped(False),
        {
            "feet": BIPED_FEET,
            "gait_order": ["left", "right"],
            "mirror": {"axis": "y", "pairs": LR_PAIRS},
            "relax_poses": poses,
        },
        "11 boxes, 10 ball joints, 30 internal DOF",
    )


def monster() -> None:
    pairs = dict(
        LR_PAIRS,
        left_second_upper_arm="right_second_upper_arm",
        left_second_forearm="right_second_forearm",
    )
    write(
        "monster",
        biped(True),
        {
            "feet": BIPED_FEET,
            "gait_order": ["left", "right"],
            "mirror": {"axis": "y", "pairs": pairs},
        },
        "a four-armed biped, 14 ball joints, 42 internal DOF",
    )


def kangaroo() -> None:
    foot = Limb(
        "foot",
        (0, 0, -0.36),
        [Box((0.13, 0.09, 0.025), (0.09, 0, -0.03), SKIN)],
        250,
        80,
        sites={"foot_toe": (0.20, 0, -0.035), "foot_heel": (-0.02, 0, -0.035)},
    )
    shin = Limb(
        "shin", (0, 0, -0.38), [Box((0.06, 0.10, 0.18), (0, 0, -0.18))], 350, 110, children=[foot]
    )
    thigh = Limb(
        "thigh",
        (0.02, 0, -0.06),
        [Box((0.08, 0.12, 0.19), (0, 0, -0.19))],
        450,
        100,
        children=[shin],
    )
    tail2 = Limb("tail_tip", (-0.30, 0, 0), [Box((0.15, 0.03, 0.03), (-0.15, 0, 0))], 40, 60)
    tail1 = Limb(
        "tail",
        (-0.10, 0, -0.02),
        [Box((0.15, 0.05, 0.05), (-0.15, 0, 0))],
        120,
        60,
        children=[tail2],
    )
    head = Limb("head", (0, 0, 0.12), [Box((0.10, 0.06, 0.06), (0.05, 0, 0.04), SKIN)], 30, 60)
    neck = Limb(
        "neck", (0.06, 0, 0.34), [Box((0.04, 0.04, 0.06), (0, 0, 0.06))], 60, 50, children=[head]
    )
    torso = Limb(
        "torso",
        (0, 0, 0.07),
        [Box((0.10, 0.13, 0.17), (0.03, 0, 0.17))],
        450,
        60,
        children=[neck, arm("left", 0.13, 0.28, 25, 15), arm("right", 0.13, 0.28, 25, 15)],
    )
    for limb in torso.children[1:]:  # a kangaroo's arms are short
        limb.boxes = [Box((0.03, 0.03, 0.09), (0, limb.boxes[0].centre[1], -0.09))]
        limb.children[0].pos = (0, limb.children[0].pos[1], -0.18)
        limb.children[0].boxes = [Box((0.025, 0.025, 0.08), (0, 0, -0.08), SKIN)]
    root = Limb(
        "pelvis", (0, 0, 0.92), [Box((0.10, 0.13, 0.07), (0, 0, 0))], children=[torso, tail1, thigh]
    )
    write(
        "kangaroo",
        root,
        {
            "feet": {"foot": {"toe": "foot_toe", "heel": "foot_heel"}},
            "gait_order": ["foot"],
            "mirror": {
                "axis": "y",
                "pairs": {"left_upper_arm": "right_upper_arm", "left_forearm": "right_forearm"},
            },
        },
        "a one-legged hopper, 12 ball joints, 36 internal DOF",
    )


def dog() -> None:
    def dog_leg(name: str, x: float, y: float) -> Limb:
        paw = Limb(
            f"{name}_paw",
            (0, 0, -0.20),
            [Box((0.05, 0.03, 0.015), (0.02, 0, -0.015), SKIN)],
            40,
            70,
            sites={f"{name}_toe": (0.06, 0, -0.02), f"{name}_heel": (-0.02, 0, -0.02)},
        )
        lower = Limb(
            f"{name}_lower",
            (0, 0, -0.20),
            [Box((0.025, 0.025, 0.10), (0, 0, -0.10))],
            60,
            110,
            children=[paw],
        )
        return Limb(
            f"{name}_upper",
            (x, y, -0.06),
            [Box((0.035, 0.035, 0.10), (0, 0, -0.10))],
            90,
            100,
            children=[lower],
        )

    head = Limb("head", (0.10, 0, 0.06), [Box((0.09, 0.05, 0.05), (0.07, 0, 0), SKIN)], 15, 60)
    neck = Limb(
        "neck", (0.16, 0, 0.03), [Box((0.06, 0.04, 0.04), (0.05, 0, 0.03))], 40, 60, children=[head]
    )
    tail = Limb("tail", (-0.16, 0, 0.03), [Box((0.10, 0.015, 0.015), (-0.10, 0, 0))], 3, 70)
    chest = Limb(
        "chest",
        (0.16, 0, 0),
        [Box((0.16, 0.09, 0.07), (0.16, 0, 0))],
        200,
        45,
        children=[neck, dog_leg("front_left", 0.22, 0.06), dog_leg("front_right", 0.22, -0.06)],
    )
    root = Limb(
        "hips",
        (0, 0, 0.52),
        [Box((0.16, 0.08, 0.07), (0, 0, 0))],
        children=[
            chest,
            tail,
            dog_leg("rear_left", -0.08, 0.06),
            dog_leg("rear_right", -0.08, -0.06),
        ],
    )
    feet = {
        n: {"toe": f"{n}_toe", "heel": f"{n}_heel"}
        for n in ("front_left", "front_right", "rear_left", "rear_right")
    }
    pairs = {f"front_left_{p}": f"front_right_{p}" for p in ("upper", "lower", "paw")}
    pairs |= {f"rear_left_{p}": f"rear_right_{p}" for p in ("upper", "lower", "paw")}
    write(
        "dog",
        root,
        {
            "feet": feet,
            "gait_order": ["rear_left", "front_left", "rear_right", "front_right"],
            "mirror": {"axis": "y", "pairs": pairs},
        },
        "a quadruped, 16 ball joints, 48 internal DOF",
    )


def snake() -> None:
    segment_count = 8
    body = None
    for i in reversed(range(1, segment_count)):
        children = [] if body is None else [body]
        sites = (
            {"tail_toe": (-0.36, 0, -0.02), "tail_heel": (-0.30, 0, -0.02)}
            if i == segment_count - 1
            else {}
        )
        body = Limb(
            f"segment_{i}",
            (-0.20 if i > 1 else -0.10, 0, 0),
            [Box((0.10, 0.045, 0.04), (-0.10, 0, 0))],
            25 - 2 * i,
            50,
            children=children,
            sites=sites,
        )
    head = Limb(
        "head",
        (0, 0, 0.045),
        [Box((0.10, 0.06, 0.045), (0, 0, 0), SKIN)],
        children=[body],
        sites={"head_toe": (0.08, 0, -0.025), "head_heel": (0.02, 0, -0.025)},
    )
    write(
        "snake",
        head,
        {
            "feet": {
                "head": {"toe": "head_toe", "heel": "head_heel"},
                "tail": {"toe": "tail_toe", "heel": "tail_heel"},
            },
            "gait_order": ["head", "tail"],
        },
        "a limbless creature, 8 boxes, 7 ball joints, 21 internal DOF",
    )


def walker_leg(side: str, y: float) -> Limb:
    """Thigh, shin and a foot body on a ball-joint ankle (the humanoid's leg with the foot split off
    the shin)."""
    s = 1 if side == "left" else -1
    foot = Limb(
        f"{side}_foot",
        (0, 0, -0.40),
        [Box((0.11, 0.05, 0.03), (0.06, 0, -0.04), SKIN)],
        200,
        60,
        sites={f"{side}_toe": (0.15, 0, -0.08), f"{side}_heel": (-0.03, 0, -0.08)},
    )
    shin = Limb(
        f"{side}_shin",
        (0, 0, -0.42),
        [Box((0.05, 0.05, 0.20), (0, 0, -0.20))],
        300,
        110,
        children=[foot],
    )
    return Limb(
        f"{side}_thigh",
        (0, s * y, -0.08),
        [Box((0.065, 0.065, 0.21), (0, 0, -0.21))],
        400,
        100,
        children=[shin],
    )


def walker() -> None:
    """A humanoid with ankles, for tracking motion capture (stance feet flat while the shin rolls
    over them)."""
    root = Limb(
        "pelvis",
        (0, 0, 1.0),
        [Box((0.10, 0.15, 0.08), (0, 0, 0))],
        children=[humanoid_torso(False), walker_leg("left", 0.09), walker_leg("right", 0.09)],
    )
    write(
        "walker",
        root,
        {
            "feet": BIPED_FEET,
            "gait_order": ["left", "right"],
            "mirror": {"axis": "y", "pairs": dict(LR_PAIRS, left_foot="right_foot")},
        },
        "a humanoid with ankles, 13 boxes, 12 ball joints, 36 internal DOF",
    )


if __name__ == "__main__":
    humanoid()
    monster()
    kangaroo()
    dog()
    snake()
    walker()
    print(f"wrote {sorted(p.name for p in OUT.iterdir())}")
