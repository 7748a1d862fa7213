"""Force laws of the surface model, constraints and collisions."""

import numpy as np

from eigengait.cloth.model import grid_bending, grid_springs, surface_model
from eigengait.cloth.obt import Mesh
from eigengait.cloth.par import SurfaceSpec
from eigengait.cloth.simulate import Simulation
from eigengait.cloth.stiffness import StiffnessAssembler


def spec(rows=3, cols=3, **kw):
    base = dict(
        name="s",
        rows=rows,
        cols=cols,
        spacing=1.0,
        position=np.zeros(3),
        normal=np.array([0.0, 0.0, 1.0]),
        mass=0.1,
        stiffness=(10.0, 20.0, 30.0),
        bending=(0, 0, 0),
    )
    base.update(kw)
    return SurfaceSpec(**base)


def test_spring_classes_and_rest_lengths():
    pairs, rest, k = grid_springs(3, 3, 0, 2.0, (10.0, 20.0, 30.0))
    assert len(pairs) == 6 + 6 + 4 + 4  # horizontal, vertical, two diagonal families
    assert set(np.round(rest, 6)) == {2.0, round(2 * np.sqrt(2), 6)}
    assert (k[rest == 2.0] != 30).all() and (k[rest > 2] == 30).all()


def test_spring_force_is_hooke_along_the_spring():
    model = surface_model([spec(1, 2)])
    x = model.rest_positions.copy()
    d = np.array([0.3, -0.2, 1.1])
    x[1] = x[0] + d
    f = model.internal_forces(x)
    expected = 10.0 * (np.linalg.norm(d) - 1.0) * d / np.linalg.norm(d)
    np.testing.assert_allclose(f[0], expected)
    np.testing.assert_allclose(f[1], -expected)


def test_angular_spring_pulls_the_centre_towards_the_midpoint():
    model = surface_model([spec(1, 3, bending=(4.0, 4.0, 4.0))])
    x = model.rest_positions.copy()
    x[1, 2] += 0.5  # lift the middle point out of the straight line
    f = model.internal_forces(x) - surface_model([spec(1, 3)]).internal_forces(x)
    ua, ub = x[0] - x[1], x[2] - x[1]
    expected = 4.0 * 0.5 * (ua / np.linalg.norm(ua) + ub / np.linalg.norm(ub))
    np.testing.assert_allclose(f[1], expected)
    np.testing.assert_allclose(f[[0, 2]], 0.0)
    assert len(grid_bending(3, 3, 0, (1, 1, 1))[0]) == 3 + 3 + 1 + 1


def test_straight_angular_springs_exert_no_force():
    model = surface_model([spec(4, 4, bending=(5.0, 5.0, 5.0))])
    np.testing.assert_allclose(model.internal_forces(model.rest_positions), 0.0, atol=1e-12)


def test_stiffness_matrix_matches_finite_differences():
    model = surface_model([spec(3, 3, bending=(0, 0, 0))])
    rng = np.random.default_rng(0)
    x = model.rest_positions + 0.1 * rng.standard_normal(model.rest_positions.shape)
    K = StiffnessAssembler(model).matrix(x, clamp=False).toarray()
    eps = 1e-6
    numeric = np.zeros_like(K)
    for col in range(K.shape[1]):
        dx = np.zeros(x.size)
        dx[col] = eps
        fp = model.internal_forces(x + dx.reshape(x.shape)).ravel()
        fm = model.internal_forces(x - dx.reshape(x.shape)).ravel()
        numeric[:, col] = (fp - fm) / (2 * eps)
    np.testing.assert_allclose(K, numeric, atol=1e-5)


def test_translation_moves_fixed_points_per_frame():
    from eigengait.cloth.par import Translation

    moving = spec(
        2, 2, fixed=[(0, 0), (0, 1)], translations=[Translation(np.array([0.5, 0, 0]), 1.0, 3.0)]
    )
    model = surface_model([moving], frames_per_second=2.0)
    sim = Simulation(model, 0.01, "symplectic")
    sim.advance(400)  # 4 s: moved 0.5 m per frame × 2 frames/s × 2 s
    np.testing.assert_allclose(sim.x[:2] - model.rest_positions[:2], [[2.0, 0, 0]] * 2, atol=1e-9)


def box(lo, hi) -> Mesh:
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = np.array(
        [
            [x0, y0, z0],
            [x1, y0, z0],
            [x1, y1, z0],
            [x0, y1, z0],
            [x0, y0, z1],
            [x1, y0, z1],
            [x1, y1, z1],
            [x0, y1, z1],
        ],
        float,
    )
    faces = [[0, 1, 2, 3], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    return Mesh("box", v, faces)


def test_collisions_keep_every_point_above_the_table_top():
    cloth = spec(10, 10, position=np.array([0.0, 0.0, 1.0]), stiffness=(50.0, 50.0, 50.0))
    table = box((-2, -2, -1), (2, 2, 0))
    model = surface_model([cloth], gravity=(0, 0, -9.81), friction=0.3, obstacles=[table])
    sim = Simulation(model, 0.002, "symplectic")
    for _ in range(150):
        sim.advance(10)
        inside = (np.abs(sim.x[:, 0]) < 1.99) & (np.abs(sim.x[:, 1]) < 1.99) & (sim.x[:, 2] > -0.99)
        # nothing inside the table: over its footprint, above its top
        assert (sim.x[inside, 2] >= 0.0).all()
    assert sim.contacts > 0
    on_top = (np.abs(sim.x[:, 0]) < 1.9) & (np.abs(sim.x[:, 1]) < 1.9)
    # lying on the top at exactly the contact gap
    resting = np.abs(sim.x[on_top, 2] - sim.thickness) < 1e-6
    assert resting.sum() >= 4 and (sim.x[on_top, 2] >= sim.thickness - 1e-9).all()


def test_restitution_one_reflects_the_normal_velocity():
    dot = spec(1, 2, stiffness=(0.0, 0.0, 0.0), position=np.array([0.0, 0.0, 0.05]))
    floor = box((-5, -5, -1), (5, 5, 0))
    model = surface_model([dot], gravity=(0, 0, -9.81), obstacles=[floor])
    sim = Simulation(model, 0.001, "symplectic", restitution=1.0, thickness=0.02)
    sim.advance(150)  # contact after a 3 cm fall (0.08 s), then rising for 0.08 s
    assert sim.contacts == 2
    assert (sim.v[:, 2] > 0).all()


def test_self_collision_stops_a_sheet_passing_through_another():
    upper = spec(6, 6, position=np.array([0.0, 0.0, 0.5]), stiffness=(50.0,) * 3, mass=0.1)
    lower = spec(
        6,
        6,
        name="low",
        position=np.array([0.2, 0.3, 0.0]),
        stiffness=(50.0,) * 3,
        fixed=[(i, j) for i in range(6) for j in range(6)],
    )
    model = surface_model([upper, lower], gravity=(0, 0, -9.81), friction=0.3)
    free = Simulation(model, 0.002, "symplectic")
    free.advance(300)
    assert free.x[:36, 2].min() < -0.5  # without self-collision it falls through
    guarded = Simulation(model, 0.002, "symplectic", self_collision=True, thickness=0.05)
    guarded.advance(300)
    inside = (np.abs(guarded.x[:36, 0] - 0.2) < 2.3) & (np.abs(guarded.x[:36, 1] - 0.3) < 2.3)
    assert guarded.x[:36][inside, 2].min() > -0.01
