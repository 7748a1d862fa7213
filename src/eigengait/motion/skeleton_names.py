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

A name is normalised (text after the last `:` or `|`, lower case, without `_ - . ` and spaces),
then read as a side (`left`/`l` or `right`/`r`, before or after the rest) and a part name. A role
takes the first of its part aliases that the clip has on that side (e.g. the upper arm is `arm`,
else `upperarm`, else `shoulder`: Mixamo's and Bandai Namco's `Shoulder` is the collar bone, beside
an `Arm`/`UpperArm`; SMPL's is the upper arm, beside a `Collar`). Unsided roles (root, torso, head)
match the whole name. Roles are the body parts the built-in characters can follow.
"""

from __future__ import annotations

import re

from eigengait.motion.bvh import BvhClip

SIDES = {"left": ("left", "l"), "right": ("right", "r")}
PART_ALIASES: dict[str, tuple[str, ...]] = {
    "upper_arm": ("arm", "upperarm", "shldr", "shoulder"),
    "forearm": ("forearm", "lowerarm", "elbow"),
    "thigh": ("upleg", "thigh", "upperleg", "hip"),
    "shin": ("leg", "shin", "lowerleg", "calf", "knee"),
    "foot": ("foot", "ankle"),
}
UNSIDED_ALIASES: dict[str, tuple[str, ...]] = {
    "root": ("hips", "hip", "pelvis"),
    "torso": ("spine1", "chest", "spine2", "spine", "upperchest"),
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
    whole = {normalise(j.name): j.name for j in clip.joints}
    sided: dict[tuple[str, str], str] = {}
    for joint in clip.joints:
        for reading in sided_parts(joint.name):
            sided.setdefault(reading, joint.name)
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
    found.setdefault("root", clip.joints[0].name)
    return found
