"""Damped least-squares IK of one leg: move the joints between the root and a foot body so that the
foot body reaches a world pose, the root and every other joint held.

Per iteration: 6D error e = (p* − p, log(R* Rᵀ)) (world, m and rad), Jacobian J of the foot body's
origin from MuJoCo's `mj_jacBody` restricted to the leg's dofs, step dq = J⁺ e with
J⁺ = Jᵀ (J Jᵀ + λ² I)⁻¹, integrated on the joints' manifold (`mj_integratePos`). Stops when
‖e‖ < TOLERANCE or after MAX_ITERATIONS.

A leg has more dofs than the six of a foot pose (the walker's: three ball joints), so many leg poses
reach one target. Given a preferred pose, each step also moves the leg toward it within the
redundancy, (I − J⁺ J) · POSTURE_GAIN · (q_preferred − q). With the damped J⁺ this projection lets a
little of each such step into the foot's pose, so the iterations settle on a compromise: the foot
within a few millimetres of its target (the cleaned CMU 07_06 walk: a held foot 5 mm into the floor
at worst) and the leg near the preferred pose, also where a target is out of reach, where the plain
steps straighten the knee at once. Solved frame by frame from the previous frame's solution with the
retargeted pose preferred, a sequence of targets gives a continuous leg motion. Solved from the
retargeted pose each time, the damped steps landed in different solutions from one frame to the
next (a cleaned Bandai Namco walk turned its thigh 25° and back within three frames, 8 800°/s at the
shin, where its retargeted legs never pass 1 000°/s); with an exact projection (from the SVD of J)
the foot met its target but the knee still snapped straight at the reach limit (07_06: 1 543°/s)
and the corpus tracked worse (docs/balance.md).
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.geometry import mat_to_quat, quat_log

DAMPING = 0.05  # λ (m or rad)
TOLERANCE = 1e-4
MAX_ITERATIONS = 30
ORIENTATION_WEIGHT = 0.3  # m per rad: how much an orientation error counts against a position error
POSTURE_GAIN = (
    0.5  # share of the distance to the preferred pose taken per step, within the redundancy
)
POSTURE_TOLERANCE = 1e-3  # rad: a smaller step toward the preferred pose ends the iterations


def solve_leg(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    foot_body: int,
    dofs: np.ndarray,
    target_pos: np.ndarray,
    target_rot: np.ndarray,
    preferred: np.ndarray | None = None,
) -> float:
    """Move data.qpos toward the foot body pose (m, world rotation matrix), within the leg's
    redundancy toward the `preferred` pose (nq) if given; returns the final position error (m)."""
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    step, toward = np.zeros(model.nv), np.zeros(model.nv)
    weight = np.array([1.0, 1.0, 1.0] + [ORIENTATION_WEIGHT] * 3)
    for _ in range(MAX_ITERATIONS):
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        rot = data.xmat[foot_body].reshape(3, 3)
        error = np.concatenate(
            [target_pos - data.xpos[foot_body], quat_log(mat_to_quat(target_rot @ rot.T))]
        )
        error *= weight
        mujoco.mj_jacBody(model, data, jacp, jacr, foot_body)
        jac = np.concatenate([jacp[:, dofs], jacr[:, dofs]]) * weight[:, None]
        pseudo_inverse = jac.T @ np.linalg.inv(jac @ jac.T + DAMPING**2 * np.eye(6))
        step[:] = 0.0
        if preferred is not None:
            mujoco.mj_differentiatePos(model, toward, 1.0, data.qpos, preferred)
            free = np.eye(len(dofs)) - pseudo_inverse @ jac
            step[dofs] = free @ (POSTURE_GAIN * toward[dofs])
        if np.linalg.norm(error) < TOLERANCE and np.linalg.norm(step) < POSTURE_TOLERANCE:
            break
        step[dofs] += pseudo_inverse @ error
        mujoco.mj_integratePos(model, data.qpos, step, 1.0)
    mujoco.mj_kinematics(model, data)
    return float(np.linalg.norm(target_pos - data.xpos[foot_body]))
