"""Detect a BVH clip's up axis, facing and length unit; BVH files state none of them.

* Up: the file axis closest to the mean direction from the feet to the root over all frames (world
  vertical, so a file whose rest pose lies on its side but whose frames stand up is read correctly).
* Facing: the rest pose's left direction (left hip − right hip, all rotations zero) made
  perpendicular to up and snapped to a file axis; forward = left × up. The retarget maps the root's
  rest orientation onto the character's with no offset, so the rest pose, not the first frame, fixes
  the facing. A rest pose that does not stand (`rest_stands`: Bandai Namco's lies along one line)
  fixes nothing: the first frame's hips give the facing, and the retarget takes its rest offsets
  from the motion (`rest_offsets`).
* Unit: the rest pose's (or first frame's) hip height h (root above its lowest point along the leg
  direction; rotation-invariant) is compared with an adult hip height of 0.9 m; the unit
  of UNITS that brings h closest to it (in ratio) wins.
* Channel order: read per joint from the file (reported, not detected).
Result: the proper rotation C with world = C · file (world: x forward, y left, z up).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from eigengait.motion.bvh import BvhClip, frame_points

UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "CMU": 0.0254 / 0.45}  # metres per unit
ADULT_HIP_HEIGHT_M = 0.9
STANDING_TILT_DEG = 45.0  # a rest pose whose legs lean further from up does not stand
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
    rest_stands: bool = True

    def summary(self) -> dict:
        return {
            "up_axis": self.up,
            "forward_axis": self.forward,
            "unit": self.unit,
            "metres_per_unit": round(self.metres_per_unit, 6),
            "hip_height_m": round(self.hip_height * self.metres_per_unit, 4),
            "rotation_orders": self.rotation_orders,
            "rest_pose_stands": self.rest_stands,
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


def rest_stands(clip: BvhClip, roles: dict[str, str], up: np.ndarray) -> bool:
    """Whether the clip's rest pose (`BvhClip.rest`) stands: its legs (root to the feet's mean)
    within STANDING_TILT_DEG of `up` (file axes) and its thighs side by side across it. CMU's rest
    T-poses stand; Bandai Namco's lays every bone along its joint's x axis, legs and spine in one
    line."""
    index = {role: clip.joint_index(name) for role, name in roles.items()}
    rest, _ = frame_points(clip, clip.rest().frames)
    leg = rest[0, index["root"]] - rest[0, [index["left_foot"], index["right_foot"]]].mean(axis=0)
    across = rest[0, index["left_thigh"]] - rest[0, index["right_thigh"]]
    upright = leg @ up >= np.cos(np.radians(STANDING_TILT_DEG)) * np.linalg.norm(leg)
    level = np.linalg.norm(across - (across @ up) * up)
    return bool(upright and level >= 0.5 * np.linalg.norm(across))


def detect_conventions(clip: BvhClip, roles: dict[str, str], start_frame: int = 1) -> Conventions:
    """Conventions of a clip whose roles (from `skeleton_names.find_roles`) include root, thighs and
    feet. A rest pose that does not stand (`rest_stands`) gives way to the clip's first frame for
    the facing and the hip height."""
    index = {role: clip.joint_index(name) for role, name in roles.items()}
    root, feet = index["root"], [index["left_foot"], index["right_foot"]]
    pos, pos_all = frame_points(clip, clip.frames[start_frame:])
    up = _snap((pos[:, root] - pos[:, feet].mean(axis=1)).mean(axis=0))
    stands = rest_stands(clip, roles, up)
    if stands:
        shape, shape_all = frame_points(clip, clip.rest().frames)
    else:
        shape, shape_all = pos[:1], pos_all[:1]
    left = shape[0, index["left_thigh"]] - shape[0, index["right_thigh"]]
    left = _snap(left - (left @ up) * up)
    forward = np.cross(left, up)
    leg = shape[0, root] - shape[0, feet].mean(axis=0)
    leg /= np.linalg.norm(leg)
    hip_height = float(np.max((shape[0, root] - shape_all[0]) @ leg))
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
        rest_stands=stands,
    )
