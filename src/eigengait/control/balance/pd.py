"""E1–E2: PD torques for ball joints (quaternions) and hinges (angles), gains diagonal in joint
coordinates.

The chapter writes the error as q_d ⊗ q_a⁻¹, a rotation in the parent frame. Motor torques and
ball-joint velocities (MuJoCo qvel) live in the child frame, so the same error is taken there: e
= log(q_a⁻¹ ⊗ q_d), the shortest arc (|e| ≤ π). A hinge's error is its angle difference e = θ_d
− θ_a (rad). Torque
τ = k_s ⊙ e + k_d ⊙ (ω_d − ω_a) in N·m about the joint axes.
"""

from __future__ import annotations

import numpy as np

from eigengait.geometry import quat_conj, quat_log, quat_mul


def joint_error(q_actual: np.ndarray, q_desired: np.ndarray) -> np.ndarray:
    """Rotation vectors (n, 3), rad, child frame, taking the actual joint rotations to the desired
    ones."""
    return quat_log(quat_mul(quat_conj(q_actual), q_desired))


def pd_torques(
    q_actual: np.ndarray,
    q_desired: np.ndarray,
    w_actual: np.ndarray,
    w_desired: np.ndarray,
    k_s: np.ndarray,
    k_d: np.ndarray,
) -> np.ndarray:
    """Joint torques (n, 3), N·m, child frame; k_s in N·m/rad and k_d in N·m·s/rad, each (n, 3) or
    broadcastable."""
    return k_s * joint_error(q_actual, q_desired) + k_d * (w_desired - w_actual)


def hinge_pd_torques(
    angle_actual: np.ndarray,
    angle_desired: np.ndarray,
    w_actual: np.ndarray,
    w_desired: np.ndarray,
    k_s: np.ndarray,
    k_d: np.ndarray,
) -> np.ndarray:
    """Hinge torques (n,), N·m about each axis, for angles in rad and rates in rad/s; gains as in
    `pd_torques`."""
    return k_s * (angle_desired - angle_actual) + k_d * (w_desired - w_actual)
