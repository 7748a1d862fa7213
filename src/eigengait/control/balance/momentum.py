"""E3–E17: the 6D momentum Jacobian, every body an end effector weighted by its mass.

Rows are (angular; linear): angular momentum L about the whole-body COM and linear momentum P, world
axes. E10–E12 give the centroidal momentum matrix A = Σ_b Ad_bᵀ M_b J_b: body b contributes
[I_b J_ω,b + m_b (x_b − c) × J_v,b ; m_b J_v,b] with J at the body's COM x_b and I_b its world-frame
inertia. E13–E15: M_total = Σ_b Ad_bᵀ M_b Ad_b = diag(I_c, m·1) (centroidal inertia). E16: J
= M_total⁻¹ A.

The Jacobian is rooted at the stance foot (E6) by eliminating the free-joint velocity with the
constraint that the foot's 6D velocity is zero: v_root = −J_f,root⁻¹ J_f,int θ̇. The joint
coordinates stay the model's own (pelvis-rooted) ones, so Jᵀ w (E17) is directly a vector of motor
torques; no sign mapping between the two hierarchies is needed.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.geometry import skew


def subtree_bodies(model: mujoco.MjModel, root_body: int) -> np.ndarray:
    """Ids of the bodies in the subtree of root_body (with mass)."""
    ids = [b for b in range(1, model.nbody) if model.body_rootid[b] == model.body_rootid[root_body]]
    return np.array([b for b in ids if model.body_mass[b] > 0], dtype=int)


def centroidal_momentum_matrix(
    model: mujoco.MjModel, data: mujoco.MjData, root_body: int
) -> np.ndarray:
    """A (6, nv): (L about the COM; P) = A qvel. Needs positions computed (mj_kinematics +
    mj_comPos)."""
    bodies = subtree_bodies(model, root_body)
    com = data.subtree_com[root_body]
    jacp = np.zeros((len(bodies), 3, model.nv))
    jacr = np.zeros((len(bodies), 3, model.nv))
    for k, b in enumerate(bodies):
        mujoco.mj_jacBodyCom(model, data, jacp[k], jacr[k], b)
    mass = model.body_mass[bodies]
    rot = data.ximat[bodies].reshape(-1, 3, 3)
    inertia = rot * model.body_inertia[bodies][:, None, :] @ np.swapaxes(rot, -1, -2)
    arm = skew(data.xipos[bodies] - com)
    angular = np.einsum("bij,bjn->in", inertia, jacr) + np.einsum("b,bij,bjn->in", mass, arm, jacp)
    linear = np.einsum("b,bjn->jn", mass, jacp)
    return np.vstack([angular, linear])


def centroidal_inertia(model: mujoco.MjModel, data: mujoco.MjData, root_body: int) -> np.ndarray:
    """M_total (6, 6) = diag(I_c, m·1): rotational inertia about the COM (world axes) and total
    mass."""
    bodies = subtree_bodies(model, root_body)
    com = data.subtree_com[root_body]
    mass = model.body_mass[bodies]
    rot = data.ximat[bodies].reshape(-1, 3, 3)
    inertia = rot * model.body_inertia[bodies][:, None, :] @ np.swapaxes(rot, -1, -2)
    r = data.xipos[bodies] - com
    parallel = mass[:, None, None] * (
        np.einsum("bi,bi->b", r, r)[:, None, None] * np.eye(3) - np.einsum("bi,bj->bij", r, r)
    )
    out = np.zeros((6, 6))
    out[:3, :3] = (inertia + parallel).sum(axis=0)
    out[3:, 3:] = np.eye(3) * mass.sum()
    return out


def foot_rooted_momentum_matrix(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    momentum: np.ndarray,
    foot_body: int,
    root_dofs: np.ndarray,
    joint_dofs: np.ndarray,
) -> np.ndarray:
    """(6, n_joint_dofs): momentum per joint velocity with the foot held still (free-joint velocity
    eliminated)."""
    jacp = np.zeros((3, model.nv))
    jacr = np.zeros((3, model.nv))
    mujoco.mj_jacBody(model, data, jacp, jacr, foot_body)
    foot = np.vstack([jacr, jacp])
    root_velocity = -np.linalg.solve(foot[:, root_dofs], foot[:, joint_dofs])
    return momentum[:, joint_dofs] + momentum[:, root_dofs] @ root_velocity


def momentum_jacobian(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    root_body: int,
    foot_body: int,
    root_dofs: np.ndarray,
    joint_dofs: np.ndarray,
    momentum: np.ndarray | None = None,
    inertia: np.ndarray | None = None,
) -> np.ndarray:
    """E16: J (6, n_joint_dofs) = M_total⁻¹ A_foot, mapping joint velocities to (ω_avg; v_com) about
    the COM.

    `momentum` (A) and `inertia` (M_total) of the current state may be given to share them between
    feet.
    """
    if momentum is None:
        momentum = centroidal_momentum_matrix(model, data, root_body)
    if inertia is None:
        inertia = centroidal_inertia(model, data, root_body)
    rooted = foot_rooted_momentum_matrix(model, data, momentum, foot_body, root_dofs, joint_dofs)
    return np.linalg.solve(inertia, rooted)
