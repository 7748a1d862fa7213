"""The clip's own flat feet: found from the ankle and toe heights alone, and the character's foot
tilt measured in them."""

import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.geometry import quat_exp, quat_mul
from eigengait.motion import retarget as retarget_module
from eigengait.motion.bvh import read_bvh
from eigengait.motion.flat_feet import flat_tilt_deg, source_flat_frames
from eigengait.motion.retarget import builtin_mapping, retarget
from eigengait.sim.world import build_world
from shared_data import MOCAP


@pytest.fixture(scope="module")
def world():
    return build_world(load_character("walker"))


def _strides(frame_time: float, strides: int, drift_per_s: float):
    """Ankle and toe paths (F, 3) (cm, z up) of a foot striding every 1 s: heel strike (toe 4 cm
    up), flat, push-off (ankle rising 6 cm), swing (both 10 cm up); the floor drifting
    `drift_per_s` upwards. Returns them and the frames (F,) of the flat phase."""
    t = np.arange(0.0, strides, frame_time)
    phase = t % 1.0
    strike, flat, push = phase < 0.1, (phase >= 0.1) & (phase < 0.4), (phase >= 0.4) & (phase < 0.5)
    swing = phase >= 0.5
    ankle = np.zeros((len(t), 3))
    toe = np.zeros((len(t), 3))
    ankle[:, 0] = 100 * t
    toe[:, 0] = ankle[:, 0] + 12.0
    ankle[:, 2] = 8.0 + 60.0 * np.where(push, phase - 0.4, 0.0) + 10.0 * swing
    toe[:, 2] = 4.0 * strike + 10.0 * swing
    floor = drift_per_s * t
    ankle[:, 2] += floor
    toe[:, 2] += floor
    return ankle, toe, flat


def test_flat_frames_are_the_frames_with_ankle_and_toe_both_down():
    # The band is 12 % of the 12-14 cm bone (about 1.5 cm): a toe 4 cm up (heel strike) or an
    # ankle rising at push-off is out, the flat phase in; a floor drifting 2 cm over the clip
    # does not hide the last strides' flat phases.
    ankle, toe, flat = _strides(1 / 120, 6, drift_per_s=0.35)
    found = source_flat_frames(ankle, toe, 1 / 120)
    # the push-off's first 0.02 s rise less than the band
    assert found[flat].all()
    assert (found & ~flat).sum() * (1 / 120) <= 6 * 0.03


def test_tilt_is_the_angle_the_foot_is_turned_from_level(world):
    # The relax pose stands its feet level; turning the left ankle 20° about its pitch axis and
    # the right 7° about its roll axis tilts them by exactly those angles.
    model = world.model
    pose = model.qpos0.copy()
    for name, axis, degrees in (("left_foot", [0, 1, 0], 20.0), ("right_foot", [1, 0, 0], 7.0)):
        adr = model.jnt_qposadr[model.joint(name).id]
        turn = quat_exp(np.radians(degrees) * np.array(axis, float))
        pose[adr : adr + 4] = quat_mul(pose[adr : adr + 4], turn)
    poses = np.stack([model.qpos0, pose])
    tilt = flat_tilt_deg(
        world, poses, {"left": np.array([False, True]), "right": np.array([False, True])}
    )
    assert tilt["left"] == pytest.approx(20.0, abs=1e-6)
    assert tilt["right"] == pytest.approx(7.0, abs=1e-6)
    level = flat_tilt_deg(world, poses, {"left": np.array([True, False])})
    assert set(level) == {"left"} and level["left"] == pytest.approx(0.0, abs=1e-6)


def test_the_tilt_sees_a_foot_the_levelling_did_not_correct(world, monkeypatch):
    # The MotionBuilder walk's feet stand rolled about 23° before levelling (`test_foot_level`):
    # measured where the clip's own feet are flat, the levelled feet stand within 4-5° of level
    # and the unlevelled ones over 15° off.
    clip = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    levelled = retarget(clip, world, builtin_mapping("walker", clip))
    assert set(levelled.flat_frames) == {"left", "right"}
    # CMU's feet stand flat in 5-17 % of the frames by this measure (Bandai Namco's 16-63 %)
    assert all(f.sum() * clip.frame_time >= 0.1 for f in levelled.flat_frames.values())
    tilt = flat_tilt_deg(world, levelled.qpos, levelled.flat_frames)
    assert max(tilt.values()) < 8.0
    monkeypatch.setattr(retarget_module, "level_feet", lambda w, qpos, ft, frames: (qpos, {}))
    raw = retarget(clip, world, builtin_mapping("walker", clip))
    assert min(flat_tilt_deg(world, raw.qpos, raw.flat_frames).values()) > 15.0
