"""Planting: a foot the reference has put down stops sliding before it takes the load.

Tracked walks skated 11-17 cm per stance (docs/balance.md) although the cleaned reference's feet
stand still (0.4 cm). Most of it happened while the foot was not yet, or no longer, loaded: the
swing foot reaches the floor a little late, its heel skims the floor for 0.1 s still moving forward
at 0.3-0.5 m/s, and at push-off the toe is dragged forward before it lifts. Friction cannot stop a
foot that carries no weight, and the joint PD tracks angles, not where the foot is on the floor.

For each foot that the reference has on the floor (its lowest sole point within CONTACT_M) within
TRANSITION_S of its touchdown or lift-off (`transition_windows`), and that is itself within
CONTACT_M of the floor while it carries less than LIGHT_LOAD of the body weight, the leg's joints
get τ = J_footᵀ (−D (v_xy − v_ref), 0): a horizontal damping force toward the reference foot's own
velocity v_ref (zero for a cleaned reference's planted foot; a `--raw-feet` reference's feet slide,
and damping them to rest pulled the body 6 cm off such a walk's COM in its first second), at the
centre of the foot's contact spheres, D = DAMPING_PER_KG × body mass (on a leg of about a sixth of
the body, a time constant of about 17 ms), J_foot that point's translational Jacobian on the leg's
own joints (pelvis-rooted, as `double_support` presses a foot down). Loaded feet are left to
friction: pulling them through the leg would push the pelvis instead (measured: applying it at every
load doubled the joint error of the 07_06 walk). So are feet still in the air: a late landing foot
pulled back through the leg pitches the body (measured: the forward jump fell on landing). And so
are feet in the middle of a stance: standing after a sideways push, the unloaded foot damped through
the leg pushed the body about (COM error 1.5 -> 5.7 cm RMS, skate 3.0 -> 6.6 cm), with the window
none.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.control.balance.double_support import CONTACT_M

DAMPING_PER_KG = 10.0  # N·s/m per kg of body mass
LIGHT_LOAD = 0.25  # share of the body weight below which a foot is damped
TRANSITION_S = 0.3  # s, how long before and after a reference touchdown or lift-off


def transition_windows(
    foot_height: np.ndarray, frame_time: float, window_s: float = TRANSITION_S
) -> np.ndarray:
    """(F, n_feet) bool: the reference foot is down (lowest sole point within CONTACT_M, heights
    `foot_height` (F, n_feet) m) and within `window_s` of a frame where it touches down or lifts
    off; a foot down from the first frame or to the last has no transition there."""
    down = np.asarray(foot_height) <= CONTACT_M
    near = np.zeros_like(down)
    reach = int(round(window_s / frame_time))
    for k in range(down.shape[1]):
        for change in np.flatnonzero(np.diff(down[:, k].astype(np.int8))) + 1:
            near[max(0, change - reach) : change + reach, k] = True
    return near & down


def sliding_force(velocity: np.ndarray, reference: np.ndarray, damping: float) -> np.ndarray:
    """World force (3,) N opposing a foot point's horizontal velocity (3,) m/s relative to the
    reference foot's (2,) m/s; no vertical part."""
    return np.array(
        [-damping * (velocity[0] - reference[0]), -damping * (velocity[1] - reference[1]), 0.0]
    )


def planting_torque(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    planting: np.ndarray,
    reference_velocity: np.ndarray,
    normals: dict[str, float],
    foot_bodies: dict[str, int],
    foot_spheres: dict[str, list[int]],
    leg_dofs: dict[str, list[int]],
    mass: float,
    gravity: float,
) -> np.ndarray:
    """Leg torques (nv, N·m) damping the horizontal slide of the feet (in `foot_bodies` order, as
    `planting`, the reference's `transition_windows` at this instant, bool) that are being planted
    or lifted, toward the reference feet's horizontal velocities (`reference_velocity`, n_feet × 2,
    m/s), whose contact spheres reach within CONTACT_M of the floor (z = 0) and that carry
    (`normals`, N) less than LIGHT_LOAD of the weight `mass` × `gravity`."""
    tau = np.zeros(model.nv)
    jacp = np.zeros((3, model.nv))
    damping = DAMPING_PER_KG * mass
    for foot, planted, v_ref in zip(foot_bodies, planting, reference_velocity):
        if not planted or normals[foot] >= LIGHT_LOAD * mass * gravity:
            continue
        spheres = foot_spheres[foot]
        lowest = float(np.min(data.geom_xpos[spheres, 2] - model.geom_size[spheres, 0]))
        if lowest > CONTACT_M:
            continue
        point = data.geom_xpos[spheres].mean(axis=0)
        mujoco.mj_jac(model, data, jacp, None, point, foot_bodies[foot])
        chain = leg_dofs[foot]
        tau[chain] += jacp[:, chain].T @ sliding_force(jacp @ data.qvel, v_ref, damping)
    return tau
