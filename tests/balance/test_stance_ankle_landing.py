"""Stance ankles, the landing shift, mass-scaled gains and the friction bound, against worked
cases."""

import numpy as np
import pytest

from eigengait.control.balance.landing import EASE_S, LandingShift
from eigengait.control.balance.stance_ankle import (
    FLAT_TILT,
    FULL_LOAD,
    MAX_CORRECTION,
    TIPPED_TILT,
    flatness,
    heading_turn,
    levelled,
    stance_ankle_targets,
)
from eigengait.control.balance.virtual import VirtualGains, friction_bounded, mass_scaled_gains
from eigengait.geometry import quat_angle, quat_conj, quat_exp, quat_mul, quat_to_mat

IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


def _rot(axis, degrees):
    return quat_exp(np.radians(degrees) * np.asarray(axis, float))


def test_heading_turn_is_the_yaw_between_two_orientations():
    turn = heading_turn(_rot([0, 0, 1], 10), quat_mul(_rot([0, 0, 1], 40), _rot([0, 1, 0], 20)))
    assert np.degrees(quat_angle(turn, _rot([0, 0, 1], 30))) == pytest.approx(0.0, abs=1e-6)


def test_a_loaded_ankle_puts_the_shin_at_the_reference_tilt():
    # Reference: shin upright, ankle straight. The foot actually stands pitched 8° (on a heel, say):
    # a loaded ankle's target is then the rotation that keeps the shin upright over it, Q* = R_shinᵀ
    # R_foot (B = identity).
    foot = _rot([0, 1, 0], 8)
    targets = stance_ankle_targets(
        {"f": IDENTITY}, {"f": IDENTITY}, {"f": foot}, {"f": IDENTITY}, {"f": FULL_LOAD}
    )
    assert np.degrees(quat_angle(targets["f"], foot)) == pytest.approx(0.0, abs=1e-6)
    half = stance_ankle_targets(
        {"f": IDENTITY}, {"f": IDENTITY}, {"f": foot}, {"f": IDENTITY}, {"f": 0.0}
    )
    np.testing.assert_array_equal(half["f"], IDENTITY)  # unloaded: the reference's own ankle


def test_the_ankle_keeps_the_reference_turn_and_a_bounded_tilt():
    # The foot turned 30° about the vertical (toe-out) and tipped 40° onto an edge: the target keeps
    # the reference's ankle turn and departs from it by MAX_CORRECTION only.
    foot = quat_mul(_rot([0, 0, 1], 30), _rot([1, 0, 0], 40))
    targets = stance_ankle_targets(
        {"f": IDENTITY}, {"f": IDENTITY}, {"f": foot}, {"f": IDENTITY}, {"f": 1.0}
    )
    assert quat_angle(targets["f"], IDENTITY) == pytest.approx(MAX_CORRECTION, abs=1e-6)
    twist = quat_mul(quat_conj(IDENTITY), targets["f"])
    assert abs(twist[3]) < 1e-9  # no turn about the foot's own up axis


def test_the_landing_shift_is_the_touch_down_error_and_decays():
    dt = 0.01
    landing = LandingShift(dt)
    ref = np.zeros(3)
    landing.update(True, np.array([0.3, -0.1, 1.0]), ref)  # in flight
    landing.update(False, np.array([0.2, -0.1, 1.0]), ref)  # touch-down 0.2 m ahead, 0.1 m right
    np.testing.assert_allclose(landing.shifted(ref), [0.2, -0.1, 0.0])
    for _ in range(int(EASE_S / dt)):
        landing.update(False, np.zeros(3), ref)
    np.testing.assert_allclose(
        landing.shifted(ref), [0.2 * np.exp(-1), -0.1 * np.exp(-1), 0.0], rtol=1e-9
    )


def test_mass_scaled_gains_give_every_body_the_same_com_dynamics():
    light, heavy = mass_scaled_gains(35.0, 6.0, 0.8), mass_scaled_gains(70.0, 6.0, 0.8)
    for gains, mass in ((light, 35.0), (heavy, 70.0)):
        assert gains.k_fs / mass == pytest.approx(36.0)
        damping = gains.k_fd + gains.k_P * mass  # E19's k_fd and E22's k_P m both damp the COM
        assert damping / (2 * mass * 6.0) == pytest.approx(0.8)
    assert heavy.k_ts == VirtualGains().k_ts


def test_fed_forward_acceleration_is_bounded_by_friction():
    np.testing.assert_array_equal(
        friction_bounded(np.array([3.0, 0.0, 0.0]), 1.0, 9.81), [3.0, 0.0, 0.0]
    )
    glitch = friction_bounded(np.array([30.0, 40.0, 0.19]), 0.5, 9.81)
    assert np.linalg.norm(glitch[:2]) == pytest.approx(5.0) and glitch[2] == 0.19
    np.testing.assert_allclose(glitch[:2] / 5.0, [0.6, 0.8])


def test_a_levelled_foot_keeps_its_heading_and_loses_its_tilt():
    foot = quat_mul(_rot([0, 0, 1], 30), _rot([0, 1, 0], 8))  # toe-out 30°, pitched 8°
    flat = levelled(foot, np.array([0.0, 0.0, 1.0]))
    assert np.degrees(quat_angle(flat, _rot([0, 0, 1], 30))) == pytest.approx(0.0, abs=1e-6)


def test_flatness_is_one_on_a_flat_foot_and_zero_on_its_toe():
    up = np.array([0.0, 0.0, 1.0])
    assert flatness(_rot([0, 0, 1], 70), up) == pytest.approx(1.0)  # turned, not tilted
    assert flatness(_rot([0, 1, 0], np.degrees(FLAT_TILT) - 1), up) == pytest.approx(1.0)
    middle = np.degrees(FLAT_TILT + TIPPED_TILT) / 2  # halfway in tilt: half the correction
    assert flatness(_rot([1, 0, 0], middle), up) == pytest.approx(0.5)
    assert flatness(_rot([0, 1, 0], np.degrees(TIPPED_TILT) + 5), up) == 0.0
    # the rest up axis is the foot's own: a foot whose rest pose is pitched 30° stands flat there
    rest_up = quat_to_mat(quat_conj(_rot([0, 1, 0], 30))) @ up
    assert flatness(_rot([0, 1, 0], 30), rest_up) == pytest.approx(1.0)


def test_a_reference_foot_on_its_toe_keeps_its_own_ankle():
    # Reference foot pitched 45° (push-off), the simulated one too, fully loaded: laid flat, the
    # ankle would be turned MAX_CORRECTION off the reference's; weighted by flatness it is not.
    foot = _rot([0, 1, 0], 45)
    flat_foot = levelled(foot, np.array([0.0, 0.0, 1.0]))
    args = ({"f": IDENTITY}, {"f": IDENTITY}, {"f": flat_foot}, {"f": foot}, {"f": 1.0})
    unweighted = stance_ankle_targets(*args)
    assert quat_angle(unweighted["f"], foot) == pytest.approx(MAX_CORRECTION, abs=1e-6)
    toe = flatness(foot, np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(stance_ankle_targets(*args, {"f": toe})["f"], foot, atol=1e-12)
