"""A loaded foot's ankle tracks the leg's world orientation, not its own joint angle.

The floor, not the reference, sets a stance foot's orientation: a reference foot may stand on its
heel or toe, or a few degrees off level, where the simulated foot stands flat. Tracked by joint
angle, the ankle then tilts the whole body above it by that difference (measured on the CMU walks:
the pelvis 5-13° off the reference while every joint is within 2°, so the swing foot lands early or
late and the walk turns into hops). So for a foot carrying load the ankle's PD target is the joint
rotation that puts its parent body (the shin) at the reference's world orientation over the foot
laid flat (`levelled`: the foot's actual orientation with its tilt removed and its heading kept; a
stance foot belongs flat on the floor, and one tipped onto an edge is turned back rather than held
there): with R_foot = R_shin · B · Q (B the foot body's fixed frame in the shin), Q* = Bᵀ
R_shin,refᵀ R_foot,flat.

Only the tilt is taken from Q*: the ankle's turn about the vertical (which the floor does not fix)
stays the reference's, so the target is Q_ref ⊗ swing(Q_ref⁻¹ ⊗ Q*), the swing part about the world
vertical seen in the foot's frame. The reference's shin is first turned about the vertical by the
difference between the two pelvises' headings, so a character walking a few degrees off the
reference's course is not asked to lean sideways. The correction is bounded to MAX_CORRECTION, and
the target is blended from the reference's own ankle rotation to it as the foot's normal force grows
to FULL_LOAD of the body weight.

Only a reference foot standing about flat is laid flat: one pitched well off level stands on its
heel or toe on purpose (a heel strike, a push-off, a runner's forefoot stance), and laying it flat
would undo the motion (measured on the CMU run: the push-off ankle held 15° short of the
reference's, the body sank 4 cm and the next swing foot struck the floor). The blend is further
weighted by `flatness`: 1 while the reference foot's tilt from its standing orientation is at most
FLAT_TILT, falling linearly to 0 at TIPPED_TILT.
"""

from __future__ import annotations

import numpy as np

from eigengait.geometry import (
    mat_to_quat,
    min_arc,
    quat_conj,
    quat_exp,
    quat_log,
    quat_mul,
    quat_to_mat,
)

# share of the body weight from which a foot's ankle fully tracks the leg's world orientation
FULL_LOAD = 0.25
MAX_CORRECTION = np.radians(15.0)  # largest departure of an ankle target from the reference's (rad)
FLAT_TILT = np.radians(20.0)  # reference foot tilt (rad) up to which it counts as standing flat
TIPPED_TILT = np.radians(40.0)  # tilt (rad) from which it stands on its heel or toe: no correction
UP = np.array([0.0, 0.0, 1.0])


def levelled(foot_quat: np.ndarray, rest_up: np.ndarray) -> np.ndarray:
    """The foot orientation (unit quaternion) turned by the smallest rotation that brings its rest
    up axis `rest_up` (foot frame; its up in the relax pose) to the world vertical: the foot laid
    flat, heading kept."""
    tilt = min_arc(quat_to_mat(foot_quat) @ rest_up, UP)
    return quat_mul(mat_to_quat(tilt), foot_quat)


def flatness(foot_quat: np.ndarray, rest_up: np.ndarray) -> float:
    """How flat a foot orientation (unit quaternion, world) stands, in [0, 1]: 1 while its rest up
    axis `rest_up` (foot frame) is within FLAT_TILT of the world vertical, 0 from TIPPED_TILT,
    linear in the tilt angle between."""
    cos_tilt = float(np.clip((quat_to_mat(foot_quat) @ rest_up) @ UP, -1.0, 1.0))
    tilt = float(np.arccos(cos_tilt))
    return float(np.clip((TIPPED_TILT - tilt) / (TIPPED_TILT - FLAT_TILT), 0.0, 1.0))


def heading_turn(quat_from: np.ndarray, quat_to: np.ndarray) -> np.ndarray:
    """The turn about the world vertical (unit quaternion) from one body orientation's heading
    (its x axis seen from above) to another's."""
    a, b = quat_to_mat(quat_from)[:2, 0], quat_to_mat(quat_to)[:2, 0]
    angle = np.arctan2(a[0] * b[1] - a[1] * b[0], a @ b)
    return np.array([np.cos(angle / 2), 0.0, 0.0, np.sin(angle / 2)])


def _swing(quat: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """The swing part of `quat` = swing ⊗ twist, the twist being its rotation about the unit
    `axis`."""
    twist = np.concatenate([[quat[0]], (quat[1:] @ axis) * axis])
    size = np.linalg.norm(twist)
    if size < 1e-12:
        return quat
    return quat_mul(quat, quat_conj(twist / size))


def stance_ankle_targets(
    body_quat: np.ndarray,
    parent_quat_ref: dict[str, np.ndarray],
    foot_quat: dict[str, np.ndarray],
    ankle_ref: dict[str, np.ndarray],
    load: dict[str, float],
    flat: dict[str, float] | None = None,
) -> dict[str, np.ndarray]:
    """Ankle target rotations (unit quaternions, w x y z) per foot from the foot body's fixed frame
    in its parent `body_quat[foot]`, the parent's reference world orientation, the foot's actual
    world orientation (laid flat, `levelled`), the reference's ankle rotation, the foot's load
    (normal force over body weight) and the reference foot's `flatness` (default 1)."""
    out = {}
    for foot, ref in ankle_ref.items():
        weight = float(np.clip(load.get(foot, 0.0) / FULL_LOAD, 0.0, 1.0))
        weight *= 1.0 if flat is None else float(flat.get(foot, 1.0))
        if weight == 0.0:
            out[foot] = ref
            continue
        level = quat_mul(
            quat_conj(body_quat[foot]), quat_mul(quat_conj(parent_quat_ref[foot]), foot_quat[foot])
        )
        tilt = quat_log(
            _swing(quat_mul(quat_conj(ref), level), quat_to_mat(foot_quat[foot]).T @ UP)
        )
        tilt *= min(1.0, MAX_CORRECTION / max(float(np.linalg.norm(tilt)), 1e-12))
        tilted = quat_mul(ref, quat_exp(tilt))
        if np.dot(tilted, ref) < 0.0:
            tilted = -tilted
        blend = (1.0 - weight) * ref + weight * tilted
        out[foot] = blend / np.linalg.norm(blend)
    return out
