"""The split of active torque among a sketch's modes, and ψ against the sketch's, on cases with
known answers."""

import numpy as np
import pytest

from eigengait.control.binding import bind_sketch
from eigengait.control.controller import sketch_modes
from eigengait.control.library import resolve
from eigengait.control.sketch import load_sketch
from eigengait.control.sketch_character import (
    energy_split,
    psi_comparison,
    sketch_character,
    state_of_steps,
)
from eigengait.control.sketch_sim import sketch_parameters


@pytest.fixture(scope="module")
def basic_run():
    """The basic-run sketch's system (symmetric biped) and its own controller: priority ψ only."""
    sketch = load_sketch(resolve("sketch", "basic-run"))
    system = bind_sketch(sketch)
    return system, sketch_parameters(sketch, system), sketch_modes(sketch), sketch


def steps_of(system, p, cycles=2):
    return int(round(cycles * p.period / system.world.model.opt.timestep))


def test_the_sketchs_own_pulses_are_all_priority(basic_run):
    system, p, modes, _ = basic_run
    pulses = system.controls(p, cycles=2)[:, : system.world.nmotor]
    # nothing clipped: the pulses are exactly Φ ψ
    assert (np.abs(pulses) < system.torque_limits).all()
    assert energy_split(system, p, modes, pulses) == pytest.approx(
        {"priority": 1.0, "allowed": 0.0, "excluded": 0.0}
    )


def test_allowed_and_excluded_torques_land_in_their_groups(basic_run):
    """Per state: a torque along an allowed mode made orthogonal to the priority modes, or a torque
    orthogonal to every priority and allowed mode, counts wholly as allowed or excluded; mixed at
    equal energy, half each."""
    system, p, modes, _ = basic_run
    states, which = system.states(p), state_of_steps(system, p, steps_of(system, p))
    rng = np.random.default_rng(3)
    allowed_tau, excluded_tau = (
        np.zeros((len(which), system.world.nmotor)),
        np.zeros((len(which), system.world.nmotor)),
    )
    for k, s in enumerate(states):
        foot = system.active_feet[0]
        basis = system.basis_matrix(foot, s.phase)
        chosen = modes[s.phase].optimized_modes(basis.shape[1])
        prio = np.linalg.qr(basis[:, np.array(sorted(modes[s.phase].priority)) - 1])[0]
        span = np.linalg.qr(basis[:, np.array(chosen) - 1])[0]
        extra = [m for m in chosen if m not in modes[s.phase].priority][0]
        a = basis[:, extra - 1] - prio @ (prio.T @ basis[:, extra - 1])
        e = rng.normal(size=basis.shape[0])
        e -= span @ (span.T @ e)
        a, e = a / np.linalg.norm(a), e / np.linalg.norm(e)
        if s.foot != foot:  # the second foot plays mirrored torques
            a, e = system.mirror.dofs(a), system.mirror.dofs(e)
        allowed_tau[which == k], excluded_tau[which == k] = a, e
    assert energy_split(system, p, modes, allowed_tau) == pytest.approx(
        {"priority": 0.0, "allowed": 1.0, "excluded": 0.0}, abs=1e-9
    )
    assert energy_split(system, p, modes, excluded_tau) == pytest.approx(
        {"priority": 0.0, "allowed": 0.0, "excluded": 1.0}, abs=1e-9
    )
    assert energy_split(system, p, modes, allowed_tau + excluded_tau) == pytest.approx(
        {"priority": 0.0, "allowed": 0.5, "excluded": 0.5}, abs=1e-4
    )


def test_psi_against_the_sketch(basic_run):
    system, p, modes, sketch = basic_run
    assert psi_comparison(system, p, modes) == {"psi_cosine": 1.0, "psi_priority_share": 1.0}
    grown = {key: 2 * psi for key, psi in p.activations.items()}
    extra = sketch.air.optimized_modes(len(grown[("left", "air")]))
    extra = [m for m in extra if m not in sketch.air.priority][0]
    a = np.abs(np.concatenate([p.activations[(f, ph)] for f, ph in p.activations])).sum()
    # one allowed mode as large as all the priority ones together
    grown[("left", "air")][extra - 1] = a
    figures = psi_comparison(system, type(p)(**{**p.__dict__, "activations": grown}), modes)
    norm = np.linalg.norm(np.concatenate([p.activations[k] for k in p.activations]))
    assert figures["psi_priority_share"] == pytest.approx(2 / 3, abs=1e-4)
    assert figures["psi_cosine"] == pytest.approx(2 * norm / np.sqrt(4 * norm**2 + a**2), abs=1e-4)


def test_a_played_sketch_reports_both_splits(basic_run):
    system, p, modes, _ = basic_run
    pulses = system.controls(p, cycles=1)[:, : system.world.nmotor]
    figures = sketch_character(system, p, modes, pulses)
    assert figures["energy_split"] == figures["pulse_energy_split"]
    assert sum(figures["energy_split"].values()) == pytest.approx(1.0, abs=1e-3)
