"""E19–E29: the virtual wrench at the COM (force and torque, world axes, N and N·m).

E19–E20: f_control = k_fs[(c_ref − s_ref) − (c − s)] + k_fd (v_ref − v), horizontal only, positions
measured from each character's own support point s (or, with ``absolute``, from the world origin:
c_ref − c). E21: f_g = m g (up). E22: f_P = k_P (P_ref − P). E23: the sum, plus the reference's
momentum rate Ṗ_ref = m a_ref as a feed-forward (not in the chapter): without it the demanded ground
force is always vertical through the COM, so in single support the stance ankle is asked to hold the
body up like a statue against the forward fall walking relies on. E24: τ_control = k_ts log(q_des ⊗
q⁻¹) + k_td (ω_des − ω) on one body's world orientation (the root body: the pelvis is the unactuated
body whose orientation the reference fixes). E26–E27: M = k_ma (L_ref − L), the sign-safe form
(E25 feeds momentum back with the wrong sign). E28: τ_virtual = τ_control + M (+ the feed-forward
L̇_ref).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from eigengait.geometry import quat_conj, quat_log, quat_mul

HORIZONTAL = np.array([1.0, 1.0, 0.0])
COM_FREQUENCY = 6.0  # rad/s, natural frequency of the COM's position feedback
COM_DAMPING = 0.8  # its damping ratio, counting E22's momentum term


@dataclass(frozen=True)
class VirtualGains:
    """Gains of the virtual wrench: k_fs N/m, k_fd N·s/m, k_P 1/s, k_ts N·m/rad, k_td N·m·s/rad,
    k_ma 1/s."""

    k_fs: float = 500.0
    k_fd: float = 150.0
    k_P: float = 2.0
    k_ts: float = 400.0
    k_td: float = 40.0
    k_ma: float = 2.0
    # weight of the reference momentum rates Ṗ_ref, L̇_ref (0: the chapter's E23/E28)
    feedforward: float = 1.0
    # COM error in world coordinates (False: E20, offsets from the support points)
    absolute: bool = True
    # weight of E21's gravity compensation (0 when other torques already carry the body)
    gravity: float = 1.0


def mass_scaled_gains(
    mass: float, frequency: float = COM_FREQUENCY, damping: float = COM_DAMPING
) -> VirtualGains:
    """Gains whose COM feedback has the same dynamics on any body: k_fs = m ω² (N/m) and k_fd = 2 ζ
    m ω − k_P m (N·s/m; E22's k_P (P_ref − P) already damps with k_P m) for mass m (kg); the other
    gains as `VirtualGains`."""
    defaults = VirtualGains()
    stiffness = mass * frequency**2
    return replace(
        defaults,
        k_fs=stiffness,
        k_fd=max(2.0 * damping * mass * frequency - defaults.k_P * mass, 0.0),
    )


def friction_bounded(com_acc: np.ndarray, friction: float, gravity: float) -> np.ndarray:
    """The reference COM acceleration (3,) m/s² with its horizontal part cut to what floor friction
    can give, μ (g + a_z) (mocap glitches and the lead-in ask for tens of m/s²; fed forward, they
    kick the character)."""
    reach = friction * max(gravity + float(com_acc[2]), 0.0)
    size = float(np.linalg.norm(com_acc[:2]))
    if size <= reach:
        return com_acc
    return np.array([*(com_acc[:2] * (reach / size)), com_acc[2]])


def virtual_force(
    com: np.ndarray,
    com_vel: np.ndarray,
    support: np.ndarray,
    com_ref: np.ndarray,
    com_vel_ref: np.ndarray,
    support_ref: np.ndarray,
    mass: float,
    gravity: float,
    gains: VirtualGains,
    com_acc_ref: np.ndarray | None = None,
) -> np.ndarray:
    """E19–E23: f_virtual (3,) N; support points are (2,) horizontal positions in m; com_acc_ref
    (3,) m/s²."""
    if gains.absolute:
        support, support_ref = np.zeros(2), np.zeros(2)
    offset = np.append(com_ref[:2] - support_ref - (com[:2] - support), 0.0)
    control = (gains.k_fs * offset + gains.k_fd * (com_vel_ref - com_vel)) * HORIZONTAL
    weight = np.array([0.0, 0.0, gains.gravity * mass * gravity])
    momentum = gains.k_P * mass * (com_vel_ref - com_vel)
    feedforward = 0.0 if com_acc_ref is None else gains.feedforward * mass * com_acc_ref
    return control + weight + momentum + feedforward


def virtual_torque(
    quat: np.ndarray,
    quat_ref: np.ndarray,
    omega: np.ndarray,
    omega_ref: np.ndarray,
    angmom: np.ndarray,
    angmom_ref: np.ndarray,
    gains: VirtualGains,
    angmom_rate_ref: np.ndarray | None = None,
) -> np.ndarray:
    """E24–E28: τ_virtual (3,) N·m from a body's world orientation/angular velocity and the momentum
    about the COM."""
    control = gains.k_ts * quat_log(quat_mul(quat_ref, quat_conj(quat))) + gains.k_td * (
        omega_ref - omega
    )
    feedforward = 0.0 if angmom_rate_ref is None else gains.feedforward * angmom_rate_ref
    return control + gains.k_ma * (angmom_ref - angmom) + feedforward
