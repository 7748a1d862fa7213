"""Integrators: Table 4.1 exactly, energy behaviour, implicit stability, the step-size warning."""

import math
import warnings

import numpy as np
import pytest

from eigengait.cloth.integrators import forward_euler, make_stepper
from eigengait.cloth.model import surface_model
from eigengait.cloth.par import SurfaceSpec
from eigengait.cloth.simulate import Simulation
from eigengait.cloth.stability import StepSizeWarning, check_step, stable_step

# Nedel (1993) Table 4.1: spring fixed at 0, rest 2, k = m = 1, x(0) = 4, v(0) = 0; P at t = 0..10.
TABLE_4_1 = {
    1.0: [4.0, 4.0, 2.0, -2.0, -6.0, -6.0, 2.0, 18.0, 34.0, 34.0, 2.0],
    0.5: [4.0, 3.5, 1.125, -1.6562, -2.1171, 1.5371, 7.7387, 11.3314, 7.0303, -5.0348, -16.4121],
    0.05: [4.0, 3.1093, 1.1282, -0.1332, 0.5498, 2.6337, 4.2274, 3.8048, 1.6607, -0.2736, -0.1656],
    0.005: [4.0, 3.0833, 1.1635, 0.0051, 0.6795, 2.5743, 3.9493, 3.5345, 1.7032, 0.1363, 0.2792],
    0.0005: [4.0, 3.0808, 1.1672, 0.0185, 0.6914, 2.5680, 3.9232, 3.5104, 1.7084, 0.1736, 0.3176],
    0.00005: [4.0, 3.0806, 1.1676, 0.0198, 0.6925, 2.5673, 3.9206, 3.5080, 1.7089, 0.1773, 0.3214],
}


def truncate4(value: float) -> float:
    return math.trunc(value * 1e4) / 1e4


@pytest.mark.parametrize("h", list(TABLE_4_1))
def test_forward_euler_reproduces_table_4_1(h):
    x, v, steps = 4.0, 0.0, round(1.0 / h)
    positions = [x]
    for _ in range(10):
        for _ in range(steps):
            x, v = forward_euler(lambda x, v, t: -(x - 2.0), x, v, 0.0, h)
        positions.append(truncate4(x))
    assert positions == TABLE_4_1[h]


def spring_pair(k=1.0, mass=1.0, friction=0.0, stretch=2.0):
    """Two points 2 m apart at rest; point 0 fixed, point 1 pulled out to ``2·stretch`` m along
    x."""
    spec = SurfaceSpec(
        "s",
        1,
        2,
        2.0,
        np.zeros(3),
        np.array([0.0, -1.0, 0.0]),
        mass,
        (k, k, k),
        (0, 0, 0),
        fixed=[(0, 0)],
    )
    model = surface_model([spec], friction=friction)
    model.rest_positions[1, 0] = model.rest_positions[0, 0] + 2.0 * stretch
    return model


def test_cloth_model_with_forward_euler_gives_the_h005_column_while_the_spring_is_1d():
    # In 3D the spring's length is |x|, so the 1-D linear spring of the table holds only while x > 0
    # (t <= 2).
    model = spring_pair()
    sim = Simulation(model, 0.05, "euler", dissertation=True)
    origin = model.rest_positions[0, 0]
    column = [truncate4(sim.x[1, 0] - origin)]
    for _ in range(2):
        sim.advance(20)
        column.append(truncate4(sim.x[1, 0] - origin))
    assert column == TABLE_4_1[0.05][:3]


def oscillation_energy(integrator, h, friction=0.0, seconds=20.0):
    model = spring_pair(friction=friction)
    sim = Simulation(model, h, integrator, strain_limit=None)
    start = model.energy(sim.x, sim.v)
    sim.advance(round(seconds / h))
    return start, model.energy(sim.x, sim.v)


def test_forward_euler_gains_energy_without_friction_and_loses_it_with():
    start, end = oscillation_energy("euler", 0.05)
    assert end > 1.5 * start
    start, end = oscillation_energy("euler", 0.05, friction=0.5)
    assert end < 0.05 * start


@pytest.mark.parametrize("integrator", ["symplectic", "rk4", "implicit"])
def test_friction_dissipates_for_every_integrator(integrator):
    start, end = oscillation_energy(integrator, 0.01, friction=0.3)
    assert end < 0.05 * start


def test_rk4_and_symplectic_keep_undamped_energy_bounded():
    for integrator in ("symplectic", "rk4"):
        start, end = oscillation_energy(integrator, 0.01)
        assert abs(end - start) < 0.01 * start


def stiff_sheet():
    spec = SurfaceSpec(
        "sheet",
        8,
        8,
        1.0,
        np.zeros(3),
        np.array([0.0, -1.0, 0.0]),
        0.01,
        (1000.0,) * 3,
        (0, 0, 0),
        fixed=[(0, j) for j in range(8)],
    )
    return surface_model([spec], gravity=(0, 0, -9.81), friction=0.2)


def test_implicit_is_stable_where_explicit_blows_up():
    model = stiff_sheet()
    h = 0.05  # ω_max ≈ 1000 rad/s: h ω_max ≈ 50, far beyond every explicit limit
    assert h > 20 * stable_step(model, "symplectic", 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        explicit = Simulation(model, h, "symplectic", strain_limit=None)
        explicit.advance(40)
        assert not np.isfinite(explicit.x).all() or np.abs(explicit.x).max() > 1e3
    implicit = Simulation(model, h, "implicit")
    implicit.advance(200)
    assert np.isfinite(implicit.x).all()
    assert np.abs(implicit.v).max() < 0.05  # settled: hanging at rest
    assert implicit.x[:, 2].min() > -9.0  # 8 rows of 1 m, barely stretched by its weight


def test_step_size_warning_before_an_explicit_blow_up():
    model = stiff_sheet()
    with pytest.warns(StepSizeWarning, match="stable step"):
        check_step(model, "euler", 0.01, 5.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_step(model, "implicit", 0.05, 5.0)
        check_step(model, "symplectic", 0.0005, 5.0)


def test_stable_step_matches_the_euler_blow_up_of_table_4_1():
    # Table 4.1 diverges at h = 1 (×16) and is usable at h = 0.05; the Gershgorin bound (ω² ≤ 2k/m)
    # is safe.
    model = spring_pair()
    limit = stable_step(model, "euler", 10.0)
    assert 0.05 < limit < 1.0


def test_make_stepper_rejects_unknown_names():
    with pytest.raises(KeyError):
        make_stepper("verlet", spring_pair(), 0.01)
