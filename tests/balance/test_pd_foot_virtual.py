"""Quaternion PD (E1–E2), the virtual wrench (E19–E28) and the tunable foot model (E30–E32)."""

import numpy as np
import pytest

from eigengait.control.balance.foot import compensation, foot_model_for_robustness
from eigengait.control.balance.pd import hinge_pd_torques, joint_error, pd_torques
from eigengait.geometry import mat_to_quat, quat_exp, quat_mul, quat_to_mat
from eigengait.control.balance.virtual import VirtualGains, virtual_force, virtual_torque
from eigengait.errors import UserInputError


def test_joint_error_is_child_frame_rotation_vector():
    rng = np.random.default_rng(0)
    actual = quat_exp(rng.normal(size=(20, 3)))
    delta = rng.normal(size=(20, 3)) * 0.5
    desired = quat_mul(actual, quat_exp(delta))
    np.testing.assert_allclose(joint_error(actual, desired), delta, atol=1e-9)


def test_joint_error_takes_the_shortest_arc():
    actual = np.array([1.0, 0, 0, 0])
    desired = quat_exp(np.array([0.0, 0.0, np.radians(300.0)]))  # 300° about z is −60°
    np.testing.assert_allclose(joint_error(actual, desired), [0, 0, -np.radians(60.0)], atol=1e-9)
    np.testing.assert_allclose(joint_error(actual, -desired), [0, 0, -np.radians(60.0)], atol=1e-9)


def test_pd_torque_combines_gains_per_axis():
    actual = np.array([[1.0, 0, 0, 0]])
    desired = quat_exp(np.array([[0.1, 0.0, 0.0]]))
    tau = pd_torques(
        actual,
        desired,
        np.zeros((1, 3)),
        np.array([[0, 2.0, 0]]),
        np.array([10.0, 20, 30]),
        np.array([1.0, 2, 3]),
    )
    np.testing.assert_allclose(tau, [[1.0, 4.0, 0.0]], atol=1e-12)


def test_hinge_pd_is_the_ball_pd_about_the_hinge_axis():
    rng = np.random.default_rng(2)
    axis = np.array([0.0, 1.0, 0.0])
    actual, desired = rng.uniform(-1.5, 1.5, size=(2, 30))
    w_actual, w_desired, k_s, k_d = rng.normal(size=(4, 30))
    tau = hinge_pd_torques(actual, desired, w_actual, w_desired, k_s, k_d)
    ball = pd_torques(
        quat_exp(actual[:, None] * axis),
        quat_exp(desired[:, None] * axis),
        w_actual[:, None] * axis,
        w_desired[:, None] * axis,
        k_s[:, None],
        k_d[:, None],
    )
    np.testing.assert_allclose(ball, tau[:, None] * axis, atol=1e-9)
    np.testing.assert_array_equal(
        hinge_pd_torques(actual, desired, 0.0, w_desired, k_s, k_d),
        k_s * (desired - actual) + k_d * w_desired,
    )


def test_rotation_conversions_round_trip():
    q = quat_exp(np.random.default_rng(1).normal(size=(50, 3)) * 2)
    q = np.where(q[:, :1] < 0, -q, q)
    np.testing.assert_allclose(mat_to_quat(quat_to_mat(q)), q, atol=1e-12)


def test_virtual_force_compensates_gravity_and_pulls_toward_reference():
    gains = VirtualGains(k_fs=100, k_fd=10, k_P=0, k_ts=0, k_td=0, k_ma=0)
    f = virtual_force(
        np.array([0.0, 0, 1]),
        np.zeros(3),
        np.zeros(2),
        np.array([0.1, 0, 1.2]),
        np.zeros(3),
        np.zeros(2),
        70.0,
        9.81,
        gains,
    )
    # horizontal only: the 0.2 m height error is ignored
    np.testing.assert_allclose(f, [10.0, 0.0, 70 * 9.81])
    # E20 (absolute=False): offsets are measured from each character's own support point.
    relative = VirtualGains(k_fs=100, k_fd=10, k_P=0, k_ts=0, k_td=0, k_ma=0, absolute=False)
    f = virtual_force(
        np.array([1.0, 0, 1]),
        np.zeros(3),
        np.array([1.0, 0]),
        np.array([0.0, 0, 1]),
        np.zeros(3),
        np.zeros(2),
        70.0,
        9.81,
        relative,
    )
    np.testing.assert_allclose(f[:2], 0.0)
    # Default (absolute): the same 1 m world-frame COM error is pulled back.
    f = virtual_force(
        np.array([1.0, 0, 1]),
        np.zeros(3),
        np.array([1.0, 0]),
        np.array([0.0, 0, 1]),
        np.zeros(3),
        np.zeros(2),
        70.0,
        9.81,
        gains,
    )
    np.testing.assert_allclose(f[:2], [-100.0, 0.0])
    # Feed-forward: the reference's momentum rate m·a_ref is added (scaled by `feedforward`).
    acc = np.array([2.0, 0.0, -1.0])
    at_rest = (
        np.zeros(3),
        np.zeros(3),
        np.zeros(2),
        np.zeros(3),
        np.zeros(3),
        np.zeros(2),
        70.0,
        9.81,
    )
    f0 = virtual_force(*at_rest, gains)
    f1 = virtual_force(*at_rest, gains, acc)
    np.testing.assert_allclose(f1 - f0, 70.0 * acc)
    off = VirtualGains(k_fs=100, k_fd=10, k_P=0, k_ts=0, k_td=0, k_ma=0, feedforward=0.0)
    np.testing.assert_allclose(
        virtual_force(
            np.zeros(3),
            np.zeros(3),
            np.zeros(2),
            np.zeros(3),
            np.zeros(3),
            np.zeros(2),
            70.0,
            9.81,
            off,
            acc,
        ),
        f0,
    )


def test_virtual_torque_uses_momentum_with_the_safe_sign():
    gains = VirtualGains(k_ts=0, k_td=0, k_ma=3.0)
    q = np.array([1.0, 0, 0, 0])
    tau = virtual_torque(q, q, np.zeros(3), np.zeros(3), np.array([0, 0, 2.0]), np.zeros(3), gains)
    np.testing.assert_allclose(tau, [0, 0, -6.0])  # opposes excess angular momentum
    gains = VirtualGains(k_ts=10, k_td=0, k_ma=0)
    tau = virtual_torque(
        q,
        quat_exp(np.array([0.2, 0, 0])),
        np.zeros(3),
        np.zeros(3),
        np.zeros(3),
        np.zeros(3),
        gains,
    )
    np.testing.assert_allclose(tau, [2.0, 0, 0], atol=1e-12)


def test_foot_model_matches_cylinder_formula_and_robustness_ends():
    foot = foot_model_for_robustness(0.5, 700.0, 0.1, 0.05, friction=1.0)
    theta = np.arctan(1.0)
    assert foot.compensable_torque() == pytest.approx(
        0.05 * 700 * np.cos(theta) + 0.1 * 700 * np.sin(theta)
    )
    torque = np.array([300.0, 0.0, 10.0])
    artificial, ratio = compensation(torque, foot)
    assert ratio == pytest.approx(foot.compensable_torque() / 300.0)
    np.testing.assert_allclose(artificial, [-ratio * 300.0, 0.0, -5.0])
    none, ratio0 = compensation(torque, foot_model_for_robustness(0.0, 700.0, 0.1, 0.05))
    assert ratio0 == 0.0 and np.allclose(none, 0.0)
    full, ratio1 = compensation(torque, foot_model_for_robustness(1.0, 700.0, 0.1, 0.05))
    assert ratio1 == 1.0 and np.allclose(full, -torque)


@pytest.mark.parametrize("bad", [-0.1, 1.5, float("nan")])
def test_robustness_out_of_range_is_rejected(bad):
    with pytest.raises(UserInputError, match="robustness"):
        foot_model_for_robustness(bad, 700.0, 0.1, 0.05)
