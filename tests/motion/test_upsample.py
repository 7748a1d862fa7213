"""A low-rate clip's poses brought to 120 frames/s by cubic interpolation, against analytic
motions."""

import mujoco
import numpy as np

from eigengait.geometry import quat_angle, quat_exp
from eigengait.motion.upsample import upsampled

MODEL = mujoco.MjModel.from_xml_string(
    """<mujoco><worldbody><body><freejoint/><geom size="0.1"/>
    <body pos="0 0 -0.3"><joint type="hinge" axis="0 1 0"/><geom size="0.05"/>
    <body pos="0 0 -0.3"><joint type="ball"/><geom size="0.05"/></body></body></body>
    </worldbody></mujoco>"""
)


def poses(times: np.ndarray) -> np.ndarray:
    """A free root moving on a parabola and turning at 1.5 rad/s about a tilted axis, a hinge
    swinging at 1 Hz, a ball joint turning at 3 rad/s about another axis."""
    axis_a = np.array([0.3, 0.2, 1.0]) / np.linalg.norm([0.3, 0.2, 1.0])
    axis_b = np.array([1.0, -0.5, 0.2]) / np.linalg.norm([1.0, -0.5, 0.2])
    q = np.zeros((len(times), MODEL.nq))
    q[:, 0], q[:, 2] = 1.2 * times, 1.0 + 0.2 * times - 0.5 * times**2
    q[:, 3:7] = quat_exp(1.5 * times[:, None] * axis_a)
    q[:, 7] = 0.6 * np.sin(2 * np.pi * times)
    q[:, 8:12] = quat_exp(3.0 * times[:, None] * axis_b)
    return q


def test_a_30_hz_clip_comes_to_120_hz_on_the_motion():
    coarse = poses(np.arange(31) / 30)
    fine, frame_time = upsampled(MODEL, coarse, 1 / 30)
    truth = poses(np.arange(len(fine)) / 120)
    assert frame_time == 1 / 120 and len(fine) == 121
    np.testing.assert_allclose(fine[:, [0, 2]], truth[:, [0, 2]], atol=1e-9)  # cubic: exact
    assert np.abs(fine[:, 7] - truth[:, 7]).max() < 1e-4  # rad; 3.3e-3 linearly
    for a in (3, 8):
        assert np.degrees(quat_angle(fine[:, a : a + 4], truth[:, a : a + 4])).max() < 1e-3
    np.testing.assert_allclose(fine[::4], coarse, atol=1e-9)  # through the clip's own frames


def test_a_clip_at_120_hz_or_faster_is_left_as_it_is():
    clip = poses(np.arange(50) / 240)
    same, frame_time = upsampled(MODEL, clip, 1 / 240)
    assert same is clip and frame_time == 1 / 240
