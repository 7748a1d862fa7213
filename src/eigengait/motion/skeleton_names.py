"""Find a BVH skeleton's body parts by joint name, across the common naming conventions of motion
capture and game rigs:

| convention | left thigh / shin / foot |
|---|---|
| MotionBuilder, Mixamo (`mixamorig:`) | `LeftUpLeg` / `LeftLeg` / `LeftFoot` |
| Daz (CMU's Daz-friendly files) | `lThigh` / `lShin` / `lFoot` |
| Unity humanoid, Bandai Namco | `UpperLeg_L` / `LowerLeg_L` / `Foot_L` |
| Unreal | `thigh_l` / `calf_l` / `foot_l` |
| Blender rigs | `thigh.L` / `shin.L` / `foot.L` |
| SMPL | `L_Hip` / `L_Knee` / `L_Ankle` |
| CMU's ASF skeleton (dm_control's CMU humanoid's bodies) | `lfemur` / `ltibia` / `lfoot` |

A name is normalised (text after the last `:` or `|`, lower case, without `_ - . ` and spaces),
then read as a side (`left`/`l` or `right`/`r`, before or after the rest) and a part name. A role
takes the first of its part aliases that the clip has on that side (e.g. the upper arm is `arm`,
else `upperarm`, else `shoulder`: Mixamo's and Bandai Namco's `Shoulder` is the collar bone, beside
an `Arm`/`UpperArm`; SMPL's is the upper arm, beside a `Collar`). Unsided roles (root, torso, head)
match the whole name. Roles are the body parts the built-in characters can follow; a user's MJCF
model's body names are read the same way (`roles_of_names`).
"""

from __future__ import annotations

import re

from eigengait.motion.bvh import BvhClip

SIDES = {"left": ("left", "l"), "right": ("right", "r")}
PART_ALIASES: dict[str, tuple[str, ...]] = {
    "upper_arm": ("arm", "upperarm", "shldr", "shoulder", "humerus"),
    "forearm": ("forearm", "lowerarm", "elbow", "radius"),
    "thigh": ("upleg", "thigh", "upperleg", "hip", "femur"),
    "shin": ("leg", "shin", "lowerleg", "calf", "knee", "tibia"),
    "foot": ("foot", "ankle"),
}
UNSIDED_ALIASES: dict[str, tuple[str, ...]] = {
    "root": ("hips", "hip", "pelvis"),
    "torso": ("spine1", "chest", "spine2", "spine", "upperchest", "thorax"),
    "head": ("head",),
}
LEG_ROLES = ("root", "left_thigh", "left_foot", "right_thigh", "right_foot")
_PARTS = frozenset(alias for aliases in PART_ALIASES.values() for alias in aliases)


def normalise(name: str) -> str:
    """'mixamorig:Left_Up-Leg' → 'leftupleg'."""
    return re.sub(r"[\s_.\-]", "", re.split(r"[:|]", name)[-1]).lower()


def sided_parts(name: str) -> set[tuple[str, str]]:
    """Every (side, part name) reading of a joint name whose part is a known alias: 'UpperLeg_L' →
    {('left', 'upperleg')}, 'lShin' → {('left', 'shin')}, 'LeftLeg' → {('left', 'leg')}."""
    flat = normalise(name)
    readings = set()
    for side, tokens in SIDES.items():
        for token in tokens:
            for rest in (flat.removeprefix(token), flat.removesuffix(token)):
                if rest != flat and rest in _PARTS:
                    readings.add((side, rest))
    return readings


def find_roles(clip: BvhClip) -> dict[str, str]:
    """Role → BVH joint name for every role whose alias the clip has; the root role falls back to
    the BVH root."""
    found = roles_of_names([j.name for j in clip.joints])
    found.setdefault("root", clip.joints[0].name)
    return found


def roles_of_names(names: list[str]) -> dict[str, str]:
    """Role → name for every role whose alias is among `names` (joint or body names, the first
    match of the role's first alias that any has)."""
    whole = {normalise(name): name for name in names}  # a repeated name: its last
    sided: dict[tuple[str, str], str] = {}
    for name in names:
        for reading in sided_parts(name):
            sided.setdefault(reading, name)
    found = {}
    for role, aliases in UNSIDED_ALIASES.items():
        name = next((whole[a] for a in aliases if a in whole), None)
        if name is not None:
            found[role] = name
    for side in SIDES:
        for part, aliases in PART_ALIASES.items():
            name = next((sided[side, a] for a in aliases if (side, a) in sided), None)
            if name is not None:
                found[f"{side}_{part}"] = name
    return found
