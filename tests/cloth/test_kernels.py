"""The compiled kernels against the NumPy/scipy reference path, on small grids."""

import dataclasses

import numpy as np
import pytest

from eigengait.cloth import kernels
from eigengait.cloth.model import surface_model
from eigengait.cloth.par import SurfaceSpec
from eigengait.cloth.simulate import Simulation
from eigengait.cloth.stiffness import StiffnessAssembler


def sheet(compiled=True, n=7, bending=(0.3, 0.2, 0.1)):
    spec = SurfaceSpec(
        "s",
        n,
        n + 1,
        0.5,
        np.zeros(3),
        np.array([0.3, -1.0, 0.2]),
        0.05,
        (40.0, 30.0, 20.0),
        bending,
        fixed=[(0, 0), (0, n)],
    )
    model = surface_model(
        [spec], gravity=(0, 0, -9.81), external_force=(0.1, 0.0, 0.0), friction=0.4
    )
    return dataclasses.replace(model, compiled=compiled)


def shaken(model, seed=0):
    rng = np.random.default_rng(seed)
    return model.rest_positions + 0.1 * rng.standard_normal(model.rest_positions.shape)


def test_internal_forces_match_the_numpy_reference():
    model = sheet()
    x = shaken(model)
    np.testing.assert_allclose(
        model.internal_forces(x), model.internal_forces_reference(x), rtol=1e-12, atol=1e-12
    )


@pytest.mark.parametrize("clamp", [True, False])
def test_jacobian_blocks_act_like_the_assembled_sparse_matrix(clamp):
    model = sheet()
    x, v = shaken(model, 1), shaken(model, 2) - model.rest_positions
    blocks = np.zeros((len(model.springs), 3, 3))
    kernels.spring_blocks(x, model.springs, model.spring_rest, model.spring_k, clamp, blocks)
    out = np.zeros_like(v)
    kernels.jacobian_times(v, model.springs, blocks, model.bend, model.bend_k / 4.0, out)
    K = StiffnessAssembler(model).matrix(x, clamp=clamp)
    np.testing.assert_allclose(out.ravel(), K @ v.ravel(), rtol=1e-10, atol=1e-10)
    diagonal = np.zeros_like(v)
    kernels.jacobian_diagonal(model.springs, blocks, model.bend, model.bend_k / 4.0, diagonal)
    np.testing.assert_allclose(diagonal.ravel(), K.diagonal(), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize(
    "integrator, h", [("euler", 0.002), ("symplectic", 0.002), ("rk4", 0.002), ("implicit", 1 / 60)]
)
def test_compiled_steps_match_the_reference_steps(integrator, h):
    runs = []
    for compiled in (True, False):
        sim = Simulation(sheet(compiled), h, integrator, strain_limit=None)
        sim.advance(60)
        runs.append(sim.x)
    assert np.abs(runs[0]).max() > 0.5
    np.testing.assert_allclose(runs[0], runs[1], atol=1e-6 if integrator == "implicit" else 1e-10)


def test_compiled_self_collision_matches_the_numpy_pass():
    from eigengait.cloth.contact import collide_self as compiled_self
    from eigengait.cloth.collision import collide_self as numpy_self
    from eigengait.cloth.simulate import TriangleGrid

    floor = SurfaceSpec(
        "floor", 3, 3, 1.0, np.zeros(3), np.array([0.0, 0.0, 1.0]), 1.0, (10.0,) * 3, (0, 0, 0)
    )
    dot = SurfaceSpec(
        "dot",
        1,
        2,
        3.0,
        np.array([1.7, 0.3, 0.05]),
        np.array([0.0, 0.0, 1.0]),
        0.5,
        (0.0,) * 3,
        (0, 0, 0),
    )
    model = surface_model([floor, dot])
    x0 = model.rest_positions.copy()
    x0[9:, 2] = 0.05
    x1 = x0.copy()
    # one dot over the floor's interior comes within the 0.04 m gap, the other is off the sheet
    x1[9:, 2] = 0.01
    v = np.zeros_like(x0)
    v[9:, 2] = -2.0
    results = []
    for collide in ("compiled", "numpy"):
        x, vel = x1.copy(), v.copy()
        if collide == "compiled":
            grid = TriangleGrid(model.triangles, 1.0).build(x, 0.04)
            count = compiled_self(
                x0, x, vel, model.mass, model.free, model.triangles, *grid, 0.04, 1.0
            )
        else:
            count = numpy_self(
                x0, x, vel, model.mass, model.triangles, model.free, thickness=0.04, restitution=1.0
            )
        results.append((count, x, vel))
    assert results[0][0] == results[1][0] == 1
    np.testing.assert_allclose(results[0][1], results[1][1], atol=1e-12)
    np.testing.assert_allclose(results[0][2], results[1][2], atol=1e-12)
    assert results[0][2][9:, 2].max() > 0  # elastic: the dot bounces


@pytest.mark.parametrize("integrator", ["euler", "symplectic"])
@pytest.mark.parametrize("pinned", [True, False])
def test_fused_steps_with_strain_limiting_match_the_reference_steps(integrator, pinned):
    """The compiled multi-step loop (SIMD spring runs, flagged strain sweep) against the NumPy step
    and sweep."""
    runs = []
    for compiled, bound in ((True, 0.02), (False, 0.02), (True, None)):
        model = sheet(compiled)
        if not pinned:
            model = dataclasses.replace(model, fixed=np.zeros_like(model.fixed))
        sim = Simulation(model, 0.002, integrator, strain_limit=bound)
        sim.x = np.where(model.fixed[:, None], model.rest_positions, shaken(model, 4))
        sim.advance(60)
        runs.append((sim.x, sim.v))
    runs, free = runs[:2], runs[2]
    assert np.abs(runs[0][0] - free[0]).max() > 1e-3  # the limiter acted
    np.testing.assert_allclose(runs[0][0], runs[1][0], rtol=0, atol=1e-10)
    np.testing.assert_allclose(runs[0][1], runs[1][1], rtol=0, atol=1e-10)


def test_spring_runs_cover_every_spring_once():
    model = sheet()
    springs = model.springs[np.random.default_rng(3).permutation(len(model.springs))]
    runs = kernels.SpringRuns(springs, model.size)
    rebuilt = np.concatenate(
        [np.stack([a + np.arange(n), b + np.arange(n)], axis=1) for _, a, b, n in runs.runs]
    )
    np.testing.assert_array_equal(rebuilt, springs)
    for p in range(model.size):
        at = runs.touching[runs.touch_start[p] : runs.touch_start[p + 1]]
        np.testing.assert_array_equal(np.sort(at), np.flatnonzero((springs == p).any(axis=1)))
