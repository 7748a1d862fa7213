import mujoco
import numpy as np
import pytest

from eigengait.errors import UserInputError
from eigengait.modal.shape_kinematics import equal_energy_amplitudes, joint_rotations
from eigengait.motion.modal_mix import (
    ModalMix,
    ModeTerm,
    build_mix,
    common_period,
    mix_trajectory,
    parse_mix,
)


def test_single_mode_reaches_its_amplitude_at_a_quarter_period(humanoid):
    world, modes = humanoid
    mix = build_mix(world, modes, [ModeTerm(mode=3, amplitude=1.0)])
    quarter = 1 / (4 * modes.frequencies_hz[2])
    _, qpos = mix_trajectory(world, mix, seconds=quarter, fps=1 / quarter)
    expected = world.model.qpos0.copy()
    mujoco.mj_integratePos(world.model, expected, modes.shapes[:, 2] * mix.amplitudes[0], 1.0)
    np.testing.assert_allclose(qpos[0], world.model.qpos0, atol=1e-12)
    np.testing.assert_allclose(qpos[1], expected, atol=1e-9)
    assert np.abs(qpos[1] - qpos[0]).max() > 0.01


def test_equal_energy_defaults_favour_low_modes_and_cap_the_rotation(humanoid):
    world, modes = humanoid
    amplitudes = equal_energy_amplitudes(world, modes, max_rotation_deg=25.0)
    omega = 2 * np.pi * modes.frequencies_hz
    energy = 0.5 * omega**2 * amplitudes**2
    np.testing.assert_allclose(energy, energy[0], rtol=1e-12)
    assert np.all(np.diff(amplitudes) <= 0)
    peaks = np.rad2deg(joint_rotations(world, modes.shapes * amplitudes).max(axis=0))
    assert peaks.max() == pytest.approx(25.0)
    assert 0 < peaks.min() < 25.0


def test_mix_repeats_after_its_lowest_common_period_only():
    rng = np.random.default_rng(1)
    mix = ModalMix(
        shapes=rng.normal(size=(8, 2)),
        amplitudes=np.array([0.3, 0.2]),
        frequencies_hz=np.array([1.5, 2.0]),
        phases_rad=np.array([0.0, 1.0]),
    )
    assert mix.period() == pytest.approx(2.0)
    t = np.linspace(0, 2, 57)
    np.testing.assert_allclose(mix.displacement(t + 2.0), mix.displacement(t), atol=1e-12)
    assert np.abs(mix.displacement(t + 1.0) - mix.displacement(t)).max() > 0.1
    assert common_period(np.array([1.0, np.sqrt(2)])) is None


def test_harmonic_snapping_makes_a_real_mix_loop(humanoid):
    world, modes = humanoid
    mix = build_mix(world, modes, parse_mix("1:1,4:0.5@90,9:0.3"), base_hz=0.5)
    period = mix.period()
    assert period is not None and period <= 2.0
    _, qpos = mix_trajectory(world, mix, seconds=period, fps=60)
    np.testing.assert_allclose(qpos[-1], qpos[0], atol=1e-9)


def test_parse_mix_reads_amplitudes_and_phases():
    assert parse_mix("1:0.5, 3:0.3@90") == [ModeTerm(1, 0.5, 0.0), ModeTerm(3, 0.3, 90.0)]
    for bad in ("", "1", "a:1", "1:x", "2:1@y"):
        with pytest.raises(UserInputError):
            parse_mix(bad)


def test_unknown_mode_number_is_refused(humanoid):
    world, modes = humanoid
    with pytest.raises(UserInputError, match="mode 99"):
        build_mix(world, modes, [ModeTerm(99, 1.0)])
    with pytest.raises(UserInputError):
        build_mix(world, modes, [ModeTerm(0, 1.0)])
