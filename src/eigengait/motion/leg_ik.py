"""Damped least-squares IK of one leg: move the joints between the root and a foot body so that the
foot body reaches a world pose, the root and every other joint held.

Per iteration: 6D error e = (p* − p, log(R* Rᵀ)) (world, m and rad), Jacobian J of the foot body's
origin from MuJoCo's `mj_jacBody` restricted to the leg's dofs, step dq = Jᵀ (J Jᵀ + λ² I)⁻¹ e,
integrated on the joints' manifold (`mj_integratePos`). Stops when ‖e‖ < TOLERANCE or after
MAX_ITERATIONS.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.geometry import mat_to_quat, quat_log

DAMPING = 0.05  # λ (m or rad)
TOLERANCE = 1e-4
MAX_ITERATIONS = 30
ORIENTATION_WEIGHT = 0.3  # m per rad: how much an orientation error counts against a position error


def leg_dofs(model: mujoco.MjModel, foot_body: int, root_body: int) -> np.ndarray:
    """Dof indices of the joints on the chain from `root_body` (excluded) down to `foot_body`
    (included)."""
    dofs, body = [], foot_body
    while body != root_body and body > 0:
        dofs += [d for d in range(model.nv) if model.dof_bodyid[d] == body]
        body = int(model.body_parentid[body])
    return np.array(sorted(dofs), int)


def solve_leg(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    foot_body: int,
    dofs: np.ndarray,
    target_pos: np.ndarray,
    target_rot: np.ndarray,
) -> float:
    """Move data.qpos toward the foot body pose (m, world rotation matrix); returns the final
    position error (m)."""
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    step = np.zeros(model.nv)
    weight = np.array([1.0, 1.0, 1.0] + [ORIENTATION_WEIGHT] * 3)
    for _ in range(MAX_ITERATIONS):
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        rot = data.xmat[foot_body].reshape(3, 3)
        error = np.concatenate(
            [target_pos - data.xpos[foot_body], quat_log(mat_to_quat(target_rot @ rot.T))]
        )
        error *= weight
        if np.linalg.norm(error) < TOLERANCE:
            break
        mujoco.mj_jacBody(model, data, jacp, jacr, foot_body)
        jac = np.concatenate([jacp[:, dofs], jacr[:, dofs]]) * weight[:, None]
        step[:] = 0.0
        step[dofs] = jac.T @ np.linalg.solve(jac @ jac.T + DAMPING**2 * np.eye(6), error)
        mujoco.mj_integratePos(model, data.qpos, step, 1.0)
    mujoco.mj_kinematics(model, data)
    return float(np.linalg.norm(target_pos - data.xpos[foot_body]))
