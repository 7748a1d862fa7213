"""Detect a BVH clip's up axis, facing and length unit; BVH files state none of them.

* Up: the file axis closest to the mean direction from the feet to the root over all frames (world
  vertical, so a file whose rest pose lies on its side but whose frames stand up is read correctly).
* Facing: the rest pose's left direction (left hip − right hip, all rotations zero) made
  perpendicular to up and snapped to a file axis; forward = left × up. The retarget maps the root's
  rest orientation onto the character's with no offset, so the rest pose, not the first frame, fixes
  the facing.
* Unit: the rest-pose hip height h (root above its lowest point along the leg direction;
  rotation-invariant) is compared with an adult hip height of 0.9 m; the unit of UNITS that brings h
  closest to it (in ratio) wins.
* Channel order: read per joint from the file (reported, not detected).
Result: the proper rotation C with world = C · file (world: x forward, y left, z up).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from eigengait.motion.bvh import BvhClip, end_site_positions, global_transforms

UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "CMU": 0.0254 / 0.45}  # metres per unit
ADULT_HIP_HEIGHT_M = 0.9
_NAMES = "xyz"


@dataclass(frozen=True)
class Conventions:
    """File axes and unit: `axes` (world = axes @ file), up/forward as signed file axes ('+y'), unit
    name, metres per unit, rest hip height (file units), rotation channel orders ('ZXY' → joint
    count)."""

    axes: np.ndarray
    up: str
    forward: str
    unit: str
    metres_per_unit: float
    hip_height: float
    rotation_orders: dict[str, int]

    def summary(self) -> dict:
        return {
            "up_axis": self.up,
            "forward_axis": self.forward,
            "unit": self.unit,
            "metres_per_unit": round(self.metres_per_unit, 6),
            "hip_height_m": round(self.hip_height * self.metres_per_unit, 4),
            "rotation_orders": self.rotation_orders,
        }


def _snap(vector: np.ndarray) -> np.ndarray:
    """Signed unit file axis nearest to `vector`."""
    axis = np.zeros(3)
    k = int(np.argmax(np.abs(vector)))
    axis[k] = np.sign(vector[k]) or 1.0
    return axis


def _label(axis: np.ndarray) -> str:
    k = int(np.argmax(np.abs(axis)))
    return ("+" if axis[k] > 0 else "-") + _NAMES[k]


def _points(clip: BvhClip, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Joint positions (F, J, 3) and joints plus End Sites (F, J + E, 3) of the given raw frames,
    file units."""
    one = BvhClip(clip.joints, clip.frame_time, frames)
    rot, pos = global_transforms(one)
    ends = list(end_site_positions(one, rot, pos).values())
    return pos, np.concatenate([pos] + [e[:, None] for e in ends], axis=1)


def detect_conventions(clip: BvhClip, roles: dict[str, str], start_frame: int = 1) -> Conventions:
    """Conventions of a clip whose roles (from `skeleton_names.find_roles`) include root, thighs and
    feet."""
    index = {role: clip.joint_index(name) for role, name in roles.items()}
    root, feet = index["root"], [index["left_foot"], index["right_foot"]]
    pos, _ = _points(clip, clip.frames[start_frame:])
    up = _snap((pos[:, root] - pos[:, feet].mean(axis=1)).mean(axis=0))
    rest, rest_all = _points(clip, np.zeros((1, clip.frames.shape[1])))
    left = rest[0, index["left_thigh"]] - rest[0, index["right_thigh"]]
    left = _snap(left - (left @ up) * up)
    forward = np.cross(left, up)
    leg = rest[0, root] - rest[0, feet].mean(axis=0)
    leg /= np.linalg.norm(leg)
    hip_height = float(np.max((rest[0, root] - rest_all[0]) @ leg))
    unit = min(
        UNITS, key=lambda u: abs(np.log(max(hip_height, 1e-9) * UNITS[u] / ADULT_HIP_HEIGHT_M))
    )
    orders = Counter(
        "".join(c[0] for c in j.channels if c.endswith("rotation")) for j in clip.joints
    )
    return Conventions(
        axes=np.array([forward, left, up]),
        up=_label(up),
        forward=_label(forward),
        unit=unit,
        metres_per_unit=UNITS[unit],
        hip_height=hip_height,
        rotation_orders={k: v for k, v in sorted(orders.items()) if k},
    )
