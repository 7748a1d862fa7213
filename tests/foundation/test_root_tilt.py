"""`RootLayout.tilt_deg`: the root's pitch and roll, the one reading gait metrics use."""

import mujoco
import numpy as np
import pytest

from eigengait.sim.root import RootLayout

FREE = RootLayout("free", (0, 1, 2), 0, 0, 2, 2, quat_qpos=3)


def free_qpos(axis, degrees, yaw_degrees=0.0):
    """qpos (7,) of a free root at the origin turned by `degrees` about `axis` after a yaw about
    world z."""
    tilt, yaw, q = np.zeros(4), np.zeros(4), np.zeros(4)
    mujoco.mju_axisAngle2Quat(tilt, np.asarray(axis, float), np.deg2rad(degrees))
    mujoco.mju_axisAngle2Quat(yaw, np.array([0.0, 0.0, 1.0]), np.deg2rad(yaw_degrees))
    mujoco.mju_mulQuat(q, yaw, tilt)
    return np.concatenate([np.zeros(3), q])


def test_a_turn_about_y_is_pitch_nose_down_positive():
    pitch, roll = FREE.tilt_deg(free_qpos([0, 1, 0], 30))
    assert pitch == pytest.approx(30.0) and roll == pytest.approx(0.0, abs=1e-12)


def test_a_turn_about_x_is_roll():
    pitch, roll = FREE.tilt_deg(free_qpos([1, 0, 0], -20))
    assert roll == pytest.approx(-20.0) and pitch == pytest.approx(0.0, abs=1e-12)


def test_the_heading_does_not_change_the_tilt_and_rows_are_read_at_once():
    rows = np.array([free_qpos([0, 1, 0], 30, yaw) for yaw in (0, 45, 170, -90)])
    rows[:, 3:] *= 2.0  # an unnormalised quaternion reads the same
    pitch, roll = FREE.tilt_deg(rows)
    assert pitch.shape == roll.shape == (4,)
    np.testing.assert_allclose(pitch, 30.0)
    np.testing.assert_allclose(roll, 0.0, atol=1e-12)


def test_a_planar_root_reads_its_pitch_hinge_with_its_sign():
    qpos = np.array([[0.1, 0.9, np.deg2rad(15)], [0.2, 0.8, np.deg2rad(-5)]])
    for sign in (1.0, -1.0):
        planar = RootLayout("planar", (0, 1), 0, 0, 1, 1, pitch_qpos=2, pitch_sign=sign)
        pitch, roll = planar.tilt_deg(qpos)
        np.testing.assert_allclose(pitch, sign * np.array([15.0, -5.0]))
        assert (roll == 0).all()
    no_hinge = RootLayout("planar", (0, 1), 0, 0, 1, 1)
    assert np.isnan(no_hinge.tilt_deg(qpos)).all()
