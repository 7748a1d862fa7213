"""Objective and soft-constraint terms of the thesis (Eqs. 4.4–4.20), each a small function.

Adapted to MuJoCo's z-up world: x forward, y lateral, z vertical. Sums "over t" run over samples
every `sample_dt` seconds (not every physics step), so the penalties do not depend on the time step.
"""

from __future__ import annotations

import numpy as np

SOFT_HEIGHT = 1.0  # h: the step every violated soft constraint adds
OBJECTIVE_WEIGHT = 1e-5  # w_p
SOFT_WEIGHT = 1e5  # w_r (= 1e10 w_p)


def q_upper(d, eps, h: float = SOFT_HEIGHT):
    """Q_u(d, ε) = (ε − d)² + h if d < ε else 0 (Eq. 4.10): penalizes d below ε."""
    d = np.asarray(d, dtype=float)
    return np.where(d < eps, (eps - d) ** 2 + h, 0.0)


def q_both(d, eps, h: float = SOFT_HEIGHT):
    """Q_b(d, ε) = Q_u(−d, −ε) + Q_u(d, −ε): penalizes |d| above ε."""
    return q_upper(-np.asarray(d, dtype=float), -eps, h) + q_upper(d, -eps, h)


def speed_objective(mean_forward_speed: float) -> float:
    """E_vel_loc = 1 / v_x² (Eq. 4.4), with v_x floored at 1 cm/s."""
    return 1.0 / max(mean_forward_speed, 0.01) ** 2


def energy_objective(torques: np.ndarray) -> float:
    """E_energia = (1/n) Σ_t Σ_j (τ_j^t)² over the n physics steps, active torque only (Eq. 4.6),
    (N·m)²."""
    return float(np.mean(np.sum(torques**2, axis=-1)))


def min_speed_term(com_forward_speed: np.ndarray, min_speed: float) -> float:
    """E_vel_min = Σ_t Q_u(Ċ_x, v_min) (Eq. 4.11)."""
    return float(q_upper(com_forward_speed, min_speed).sum())


def mean_speed_term(
    mean_velocity: np.ndarray, mean_speed: float, lateral: float, vertical: float
) -> float:
    """E_vels_med = Q_u(v_x, v̄) + Q_b(v_y, ε_y) + Q_b(v_z, ε_z) (Eq. 4.12)."""
    vx, vy, vz = mean_velocity
    return float(q_upper(vx, mean_speed) + q_both(vy, lateral) + q_both(vz, vertical))


def joint_speed_term(joint_speeds: np.ndarray, limit: float) -> float:
    """E_vels_ang = Σ_t Σ_j Q_b(θ̇_j, ω_max) (Eq. 4.13)."""
    return float(q_both(joint_speeds, limit).sum())


def energy_limit_term(energy: float, limit: float) -> float:
    """E_energia_max = Q_u(−E, −E_max) (Eq. 4.14)."""
    return float(q_upper(-energy, -limit))


def priority_term(state_activations: list[tuple[np.ndarray, np.ndarray]]) -> float:
    """E_modos_prior = Σ_states Q_u(Σ_p |ψ_p| − Σ_o |ψ_o|, 0) (Eq. 4.15): priority modes
    dominate."""
    return float(sum(q_upper(np.abs(p).sum() - np.abs(o).sum(), 0.0) for p, o in state_activations))


def upright_term(root_up_z: np.ndarray) -> float:
    """E_post_vert, z-up form: Σ_t Q_u(u_z, 0) with u_z the vertical component of the root's up axis
    (the thesis asks the torso to stay above the COM: no upside-down poses)."""
    return float(q_upper(root_up_z, 0.0).sum())


def stance_contact_term(toe_clearance: np.ndarray, tolerance: float = 0.001) -> float:
    """E_pe_apoio = Q_u(−d_min, −1 mm) over the first δc/2 of a ground state (Eq. 4.17): the stance
    toe touches the ground. `toe_clearance` is the toe sphere's height above the floor (m) in that
    window."""
    if toe_clearance.size == 0:
        return 0.0
    return float(q_upper(-toe_clearance.min(), -tolerance))


def push_off_rise(com_vz: np.ndarray, toe_z: np.ndarray, heel_z: np.ndarray, dt: float) -> float:
    """δ_pe (Eq. 4.18, z up): the stance toe's summed rise (m) over the steps where the COM has been
    falling since the window started and now rises (Ċ_z > 0), the toe does not rise more than
    0.1 m/s faster than the COM (Ċ_z − ṗ_toe,z > −0.1), the heel is above the toe and the toe is
    rising. Arrays are per step of `dt` s over the window from the foot's air state to its
    lift-off."""
    if toe_z.size < 2:
        return 0.0
    rise = np.diff(toe_z)
    vz = com_vz[1:]
    fell_before = np.maximum.accumulate(com_vz < 0)[:-1]
    ok = fell_before & (vz > 0) & (vz - rise / dt > -0.1) & (heel_z[1:] > toe_z[1:]) & (rise > 0)
    return float(rise[ok].sum())


def stance_rise_term(push_off: float, minimum: float = 0.02) -> float:
    """E_altura_pe_apoio = Q_u(δ_pe, 2 cm) (Eq. 4.19): the push-off must lift the stance toe at
    least 2 cm."""
    return float(q_upper(push_off, minimum))


def anti_stumble_term(stance_toe_to_hip: np.ndarray, other_toe_to_hip: np.ndarray) -> float:
    """E_evit_trop = Σ_t Q_u(d_apoio − d_outro, 0) (Eq. 4.20) from touchdown to lift-off: the stance
    toe stays farther from its hip than the other toe from its own, so the swing foot is tucked and
    does not stumble."""
    return float(q_upper(np.asarray(stance_toe_to_hip) - np.asarray(other_toe_to_hip), 0.0).sum())


def stance_slip_term(slips: np.ndarray, limit: float) -> float:
    """E_deslize = Σ_stances Q_u(−s, −s_max): each stance whose foot slides more than s_max (m) is
    charged (not in the thesis; the closed-loop gait target of ≤ 3 cm, measured as `play` measures
    `stance_slip_m`)."""
    return float(q_upper(-np.asarray(slips, dtype=float), -limit).sum())


def paired_contact_term(mismatch: np.ndarray, tolerance: float) -> float:
    """Σ over cycles of Q_u(−m, −ε): m the share of a cycle in which one foot of a pair touches the
    ground and the other does not (not in the thesis; a footfall pattern such as a trot's diagonal
    pairs, `targets.paired_feet`)."""
    return float(q_upper(-np.asarray(mismatch, dtype=float), -tolerance).sum())
