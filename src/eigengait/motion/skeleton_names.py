"""Find a BVH skeleton's body parts by joint name (MotionBuilder `Hips/LeftUpLeg/LeftLeg/LeftFoot`,
Daz `hip/lThigh/ lShin/lFoot`, and the same names with a namespace such as `mixamorig:` or with
`_`/`-`/spaces).

A name is normalised (text after the last `:` or `|`, lower case, without `_ - . ` and spaces) and
compared with each role's aliases in order; the first alias present wins (e.g. the torso is
`Spine1`, else `chest`, else `Spine2`, else `Spine`). Roles are the body parts the built-in
characters can follow.
"""

from __future__ import annotations

import re

from eigengait.motion.bvh import BvhClip

_LEFT = {
    "upper_arm": ("leftarm", "lshldr", "leftupperarm", "lupperarm"),
    "forearm": ("leftforearm", "lforearm", "leftlowerarm", "llowerarm"),
    "thigh": ("leftupleg", "lthigh", "leftupperleg", "lupperleg", "leftthigh"),
    "shin": ("leftleg", "lshin", "leftlowerleg", "llowerleg", "leftshin"),
    "foot": ("leftfoot", "lfoot", "leftankle"),
}
ROLE_ALIASES: dict[str, tuple[str, ...]] = {
    "root": ("hips", "hip", "pelvis"),
    "torso": ("spine1", "chest", "spine2", "spine", "upperchest"),
    "head": ("head",),
    **{f"left_{part}": names for part, names in _LEFT.items()},
    **{
        f"right_{part}": tuple(
            "right" + n[4:] if n.startswith("left") else "r" + n[1:] for n in names
        )
        for part, names in _LEFT.items()
    },
}
LEG_ROLES = ("root", "left_thigh", "left_foot", "right_thigh", "right_foot")


def normalise(name: str) -> str:
    """'mixamorig:Left_Up-Leg' → 'leftupleg'."""
    return re.sub(r"[\s_.\-]", "", re.split(r"[:|]", name)[-1]).lower()


def find_roles(clip: BvhClip) -> dict[str, str]:
    """Role → BVH joint name for every role whose alias the clip has; the root role falls back to
    the BVH root."""
    by_name = {normalise(j.name): j.name for j in clip.joints}
    found = {}
    for role, aliases in ROLE_ALIASES.items():
        name = next((by_name[a] for a in aliases if a in by_name), None)
        if name is not None:
            found[role] = name
    found.setdefault("root", clip.joints[0].name)
    return found
