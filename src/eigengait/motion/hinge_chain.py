"""Angles of a body's chain of hinge joints that turn it closest to a wanted rotation.

A body on several hinges (a hip as hip_x, hip_z, hip_y; dm_control's humanoids) turns relative to
its parent frame by R(θ) = Π_i exp(θ_i [a_i]×), the hinges applied in the model's order, each axis
a_i in the body frame (MuJoCo's composition). Given wanted relative rotations (F, 3, 3), the angles
are found per frame by damped Gauss-Newton on the rotation error log(R(θ)ᵀ R_wanted), starting from
zero: exact for three independent axes away from gimbal lock, the least-squares turn for fewer.
"""

from __future__ import annotations

import numpy as np

from eigengait.geometry import mat_to_quat, quat_exp, quat_log, quat_to_mat

ITERATIONS = 30
DAMPING = 1e-6  # on the normal equations, for axes that line up (gimbal lock)


def hinge_angles(wanted: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """Angles (F, k) in rad of the hinges with unit `axes` (k, 3; body frame, in the model's
    order) whose composed turn is nearest each wanted rotation (F, 3, 3)."""
    wanted = np.asarray(wanted, float)
    axes = np.asarray(axes, float)
    k = len(axes)
    theta = np.zeros((len(wanted), k))
    for _ in range(ITERATIONS):
        turns = [quat_to_mat(quat_exp(theta[:, [i]] * axes[i])) for i in range(k)]
        after = np.broadcast_to(np.eye(3), wanted.shape).copy()  # Π_{j>i} R_j, built backward
        columns = [None] * k
        for i in reversed(range(k)):
            columns[i] = np.einsum("fji,j->fi", after, axes[i])  # a_i in the end frame
            after = turns[i] @ after
        chain = after  # Π_i R_i
        error = quat_log(mat_to_quat(np.swapaxes(chain, -1, -2) @ wanted))  # (F, 3), end frame
        jac = np.stack(columns, axis=-1)  # (F, 3, k)
        normal = np.swapaxes(jac, -1, -2) @ jac + DAMPING * np.eye(k)
        step = np.linalg.solve(normal, np.einsum("fik,fi->fk", jac, error)[..., None])[..., 0]
        theta += step
        if np.abs(step).max() < 1e-10:
            break
    return theta
