"""The geometry helpers against MuJoCo's own quaternion functions (w, x, y, z) on random inputs."""

import mujoco
import numpy as np

from eigengait.geometry import quat_exp, quat_to_mat


def test_quat_to_mat_is_mujocos_rotation_matrix():
    rng = np.random.default_rng(0)
    quats = rng.normal(size=(200, 4))
    quats /= np.linalg.norm(quats, axis=1, keepdims=True)
    for q, mat in zip(quats, quat_to_mat(quats)):
        expected = np.zeros(9)
        mujoco.mju_quat2Mat(expected, q)
        np.testing.assert_allclose(mat, expected.reshape(3, 3), atol=1e-15)
    np.testing.assert_array_equal(quat_to_mat(np.array([1.0, 0, 0, 0])), np.eye(3))


def test_quat_exp_is_mujocos_axis_angle_quaternion():
    rng = np.random.default_rng(1)
    rotvecs = rng.normal(size=(200, 3)) * 10 ** rng.uniform(-6, 1, size=(200, 1))
    for rotvec, q in zip(rotvecs, quat_exp(rotvecs)):
        angle = np.linalg.norm(rotvec)
        expected = np.zeros(4)
        mujoco.mju_axisAngle2Quat(expected, rotvec / angle, angle)
        np.testing.assert_allclose(q, expected, atol=1e-14)
    np.testing.assert_array_equal(quat_exp(np.zeros(3)), [1.0, 0, 0, 0])
    np.testing.assert_allclose(
        quat_exp(np.array([0, 0, np.pi / 2])), [np.sqrt(0.5), 0, 0, np.sqrt(0.5)]
    )
