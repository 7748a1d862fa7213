"""How much of a played gait is still its sketch: where the active torque goes among the sketch's
modes, and how the optimized activations ψ compare with the sketch's.

Energy is the thesis's E_energia measure (Eq. 4.6), Σ over steps of Σ_j τ_j² (N·m)², over the
torques actually applied (pulses, balance feedback and lookahead offsets, clipped). Each step's
torque is split by orthogonal projection in the torque space of the state being played (its phase,
and its stance foot; a symmetric gait's second-foot states are mirrored back onto the first foot's):
first onto the span of the sketch's priority modes, then what is left onto the span of its priority
and allowed modes together; the rest is excluded. The three shares sum to 1; the pulses alone put
nothing in the excluded modes, so an excluded share is feedback or lookahead. The state of each step
is read from the clock's schedule (every lookahead gait runs on the clock).
"""

from __future__ import annotations

import numpy as np

from eigengait.control.activations import mode_indices, sparse_to_dense
from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.control.sketch import PhaseSketch

# phase ("air", "ground") -> the sketch's priority/allowed/excluded modes
SketchModes = dict[str, PhaseSketch]


def _span(basis: np.ndarray, modes: list[int]) -> np.ndarray:
    """Orthonormal columns (n × r) spanning the torque columns of the 1-based `modes` of `basis`."""
    if not modes:
        return np.zeros((basis.shape[0], 0))
    q, r = np.linalg.qr(basis[:, mode_indices(modes)])
    return q[:, np.abs(np.diag(r)) > 1e-10 * max(1.0, np.abs(r).max())]


def _groups(
    system: GaitSystem, sketch: SketchModes
) -> dict[tuple[str, str], tuple[np.ndarray, np.ndarray]]:
    """(active foot, phase) -> orthonormal spans of the priority modes and of priority + allowed."""
    out = {}
    for foot in system.active_feet:
        for phase in ("air", "ground"):
            basis = system.basis_matrix(foot, phase)
            chosen = sketch[phase]
            out[(foot, phase)] = (
                _span(basis, sorted(chosen.priority)),
                _span(basis, chosen.optimized_modes(basis.shape[1])),
            )
    return out


def state_of_steps(system: GaitSystem, p: GaitParameters, steps: int) -> np.ndarray:
    """Index into `system.states(p)` of the state each physics step plays (the clock's schedule,
    mid-step)."""
    starts = np.array([s.start for s in system.states(p)])
    t = (np.arange(steps) + 0.5) * system.world.model.opt.timestep
    return np.searchsorted(starts, np.mod(t, p.period), side="right") - 1


def energy_split(
    system: GaitSystem, p: GaitParameters, sketch: SketchModes, torques: np.ndarray
) -> dict:
    """Shares of Σ‖τ‖² in the priority, allowed and excluded modes of `torques` (steps × n_internal,
    N·m)."""
    states = system.states(p)
    groups = _groups(system, sketch)
    which = state_of_steps(system, p, len(torques))
    total = prio = chosen = 0.0
    for k, s in enumerate(states):
        tau = torques[which == k]
        foot = s.foot
        if (foot, s.phase) not in groups:  # the mirrored foot of a symmetric gait
            tau, foot = system.mirror.dofs(tau), system.active_feet[0]
        p_span, c_span = groups[(foot, s.phase)]
        total += float(np.sum(tau**2))
        prio += float(np.sum((tau @ p_span) ** 2))
        chosen += float(np.sum((tau @ c_span) ** 2))
    if total == 0:
        return {"priority": None, "allowed": None, "excluded": None}
    return {
        "priority": round(prio / total, 4),
        "allowed": round((chosen - prio) / total, 4),
        "excluded": round(max(0.0, 1 - chosen / total), 4),
    }


def psi_comparison(system: GaitSystem, p: GaitParameters, sketch: SketchModes) -> dict:
    """`psi_cosine`: cosine between the sketch's ψ (its priority values, 0 elsewhere) and the
    optimized ψ over every (active foot, phase); `psi_priority_share`: Σ|ψ| of the priority modes
    over Σ|ψ| (the quantity of the thesis's E_modos_prior, Eq. 4.15, which asks it to dominate)."""
    drawn, optimized, weight = [], [], []
    for foot in system.active_feet:
        for phase in ("air", "ground"):
            psi = p.activations[(foot, phase)]
            target = sparse_to_dense(sketch[phase].priority, len(psi))
            drawn.append(target)
            optimized.append(psi)
            weight.append(target != 0)
    a, b, is_priority = np.concatenate(drawn), np.concatenate(optimized), np.concatenate(weight)
    norm = np.linalg.norm(a) * np.linalg.norm(b)
    magnitude = np.abs(b).sum()
    return {
        "psi_cosine": round(float(a @ b / norm), 4) if norm > 0 else None,
        "psi_priority_share": round(float(np.abs(b[is_priority]).sum() / magnitude), 4)
        if magnitude > 0
        else None,
    }


def sketch_character(
    system: GaitSystem, p: GaitParameters, sketch: SketchModes, torques: np.ndarray
) -> dict:
    """JSON-ready: the played torques' `energy_split`, the pulses' own split over one cycle
    (`pulse_energy_split`) and `psi_comparison`."""
    pulses = system.controls(p, cycles=1)[:, : system.world.nmotor]
    return {
        "energy_split": energy_split(system, p, sketch, torques),
        "pulse_energy_split": energy_split(system, p, sketch, pulses),
        **psi_comparison(system, p, sketch),
    }
