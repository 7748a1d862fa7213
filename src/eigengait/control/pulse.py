"""The thesis's cyclic pulse state machine (§4.3, Fig. 4.2).

A cycle visits the feet of `feet` in order; each foot has an **air** state then a **ground** state.
A cycle of period T splits evenly among the feet; each foot's share is air for α·T/n_feet then
ground for (1−α)·T/n_feet. Each state applies one rectangular pulse: the constant torque τ = Φ ψ for
δ seconds from the state's start, then zero. Φ is the torque basis of that state's phase (air modes,
or the ground modes of that state's stance foot), unit-norm columns, so ψ is in N·m. With
`symmetric`, the second foot's states use the first foot's torques mirrored. Torques are clipped per
dof to ±torque_limit (a scalar or one limit per dof).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class State:
    foot: str
    phase: str  # "air" or "ground"
    start: float  # s from the cycle start
    duration: float  # s
    pulse: float  # s, ≤ duration


def schedule(
    feet: list[str], period: float, air_ratio: float, pulse_air: float, pulse_ground: float
) -> list[State]:
    """The states of one cycle, in order."""
    share = period / len(feet)
    states, t = [], 0.0
    for foot in feet:
        for phase, duration, pulse in (
            ("air", air_ratio * share, pulse_air),
            ("ground", (1 - air_ratio) * share, pulse_ground),
        ):
            states.append(State(foot, phase, t, duration, min(pulse, duration)))
            t += duration
    return states


def state_torques(
    bases: dict[tuple[str, str], np.ndarray],
    activations: dict[tuple[str, str], np.ndarray],
    states: list[State],
    mirror=None,
    torque_limit: float | np.ndarray = np.inf,
) -> list[np.ndarray]:
    """Pulse torque (n_internal,) of each state. Keys are (foot, phase); missing feet are
    mirrored."""
    torques = []
    first_foot = states[0].foot
    for s in states:
        key = (s.foot, s.phase)
        if key in activations:
            tau = bases[key] @ activations[key]
        else:
            tau = mirror.dofs(bases[(first_foot, s.phase)] @ activations[(first_foot, s.phase)])
        torques.append(np.clip(tau, -torque_limit, torque_limit))
    return torques


def control_sequence(
    states: list[State],
    torques: list[np.ndarray],
    timestep: float,
    cycles: int = 1,
    span: float | None = None,
) -> np.ndarray:
    """Piecewise-constant controls (nstep × n_internal) for `cycles` cycles (or the first `span`
    seconds)."""
    period = sum(s.duration for s in states)
    total = span if span is not None else cycles * period
    n = int(round(total / timestep))
    t = (np.arange(n) + 0.5) * timestep
    phase_t = np.mod(t, period)
    u = np.zeros((n, len(torques[0])))
    for s, tau in zip(states, torques):
        on = (phase_t >= s.start) & (phase_t < s.start + s.pulse)
        u[on] = tau
    return u
