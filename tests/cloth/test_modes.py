"""Vibration modes against the analytic taut string and membrane."""

import numpy as np
import pytest

from eigengait.cloth.model import script_model
from eigengait.cloth.modes import (
    draw_palette,
    equilibrium,
    membrane,
    out_of_plane_fraction,
    string,
    vibration_modes,
)
from eigengait.cloth.library import example_path
from eigengait.cloth.par import read_par


def test_taut_string_transverse_modes():
    points, k, r, m, s = 60, 100.0, 1.0, 0.01, 1.1
    modes = vibration_modes(string(points, spacing=r, mass=m, stiffness=k, stretch=s), count=12)
    transverse = modes.frequencies[
        out_of_plane_fraction(modes, (0, 0, 1)) + out_of_plane_fraction(modes, (0, 1, 0)) > 0.99
    ]
    tension, spacing = k * r * (s - 1), r * s
    length = (points - 1) * spacing
    analytic = np.arange(1, 6) / (2 * length) * np.sqrt(tension / (m / spacing))
    # two polarizations per frequency
    np.testing.assert_allclose(transverse[0:10:2], analytic, rtol=0.01)
    np.testing.assert_allclose(transverse[1:10:2], analytic, rtol=0.01)


def test_membrane_modes_match_f_mn():
    rows = cols = 25
    k, r, m, s = 100.0, 1.0, 0.01, 1.05
    modes = vibration_modes(
        membrane(rows, cols, spacing=r, mass=m, stiffness=k, stretch=s), count=8
    )
    assert modes.zero_modes == 0
    assert (out_of_plane_fraction(modes) > 0.99).all()
    spacing = r * s
    a = b = (cols - 1) * spacing
    # Out-of-plane: straight springs give T l ∂² per axis, the two diagonal families 2 T_d l/√2 ∇²
    # ⇒ c² = 3 k r (s-1) l / m.
    c = np.sqrt(3 * k * r * (s - 1) * spacing / m)
    analytic = sorted(c / 2 * np.hypot(p / a, q / b) for p in range(1, 5) for q in range(1, 5))[:8]
    np.testing.assert_allclose(modes.frequencies, analytic, rtol=0.02)
    shape = modes.shapes[0][:, 2].reshape(rows, cols)
    # mode 1 has no interior node line
    assert (shape[1:-1, 1:-1] * np.sign(shape[12, 12]) > 0).all()


def test_mass_normalized_shapes():
    model = membrane(6, 7)
    modes = vibration_modes(model, count=5)
    gram = np.einsum("kni,n,lni->kl", modes.shapes, model.mass, modes.shapes)
    np.testing.assert_allclose(gram, np.eye(5), atol=1e-8)


def test_hanging_curtain_modes_and_palette(tmp_path):
    model = script_model(read_par(example_path("curtain")))
    x = equilibrium(model)
    assert np.abs(model.applied_forces(x)[model.free]).max() < 1e-3
    modes = vibration_modes(model, x, count=4)
    pendulum = np.sqrt(9.81 / np.ptp(x[:, 2])) / (2 * np.pi)
    # swings like a pendulum of its length
    assert 0.5 * pendulum < modes.frequencies[0] < 2.0 * pendulum
    draw_palette(model, modes, tmp_path / "p.png")
    assert (tmp_path / "p.png").stat().st_size > 10_000


def test_free_surface_has_no_equilibrium():
    from eigengait.errors import UserInputError

    model = script_model(read_par(example_path("tablecloth")))
    with pytest.raises(UserInputError, match="no fixed point"):
        equilibrium(model)
