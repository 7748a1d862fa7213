"""Modal analysis in maximal coordinates with joint constraints (Kry et al. 2009; thesis Eqs.
2.19–2.37).

Every body has a twist (ω; v) in its inertial frame at its COM. The relative twist of joint j in the
joint frame (anchored at the joint, oriented as the child body) is v_j = Ad(j←child) V_child
− Ad(j←parent) V_parent (stacked: Θ). Ball joints forbid relative linear velocity (G rows); hinges
also forbid rotation off their axis. A pinned point p on a body adds v − [p] ω = 0 (the erratum's
sign). Then
(Nᵀ Θᵀ jK Θ N) x = λ (Nᵀ cM N) x with N the null space of G, and Θ N x gives per-joint relative
motion.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.modal.eigen import constrained_modes
from eigengait.modal.spatial import relative_adjoint, spatial_inertia
from eigengait.geometry import skew
from eigengait.sim.world import World


def maximal_modes(world: World, pin_site: str | None = None):
    """(eigenvalues, joint-space shapes Θ N x as columns, rigid count) for the free or pinned
    character."""
    model, data = world.model, world.new_data()
    bodies = [b for b in range(1, model.nbody)]
    col = {b: 6 * i for i, b in enumerate(bodies)}
    n = 6 * len(bodies)
    frames = {b: (data.ximat[b].reshape(3, 3), data.xipos[b]) for b in bodies}

    cM = np.zeros((n, n))
    for b in bodies:
        cM[col[b] : col[b] + 6, col[b] : col[b] + 6] = spatial_inertia(
            model.body_mass[b], model.body_inertia[b]
        )

    theta_rows, k_diag, g_rows = [], [], []
    for name in world.character.joints:
        j = model.joint(name).id
        child = int(model.jnt_bodyid[j])
        parent = int(model.body_parentid[child])
        R_j, p_j = data.xmat[child].reshape(3, 3), data.xanchor[j]
        rel = np.zeros((6, n))
        rel[:, col[child] : col[child] + 6] = relative_adjoint(R_j, p_j, *frames[child])
        if parent != 0:
            rel[:, col[parent] : col[parent] + 6] -= relative_adjoint(R_j, p_j, *frames[parent])
        k = world.character.stiffness[name]
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL:
            theta_rows.append(rel[:3])
            g_rows.append(rel[3:])
        else:
            axis = model.jnt_axis[j]
            others = np.linalg.svd(axis[None, :])[2][1:]
            theta_rows.append(axis[None, :] @ rel[:3])
            g_rows += [others @ rel[:3], rel[3:]]
        k_diag.append(k)

    if pin_site is not None:
        s = model.site(pin_site).id
        b = int(model.site_bodyid[s])
        R_b, p_b = frames[b]
        p_local = R_b.T @ (data.site_xpos[s] - p_b)
        pin = np.zeros((3, n))
        pin[:, col[b] : col[b] + 3] = -skew(p_local)
        pin[:, col[b] + 3 : col[b] + 6] = np.eye(3)
        g_rows.append(pin)

    Theta = np.vstack(theta_rows)
    jK = np.diag(np.concatenate(k_diag))
    G = np.vstack(g_rows)
    lam, shapes, rigid = constrained_modes(Theta.T @ jK @ Theta, cM, G)
    return lam, Theta @ shapes, rigid
