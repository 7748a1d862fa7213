"""A joint that flips faster than a human joint can (a capture glitch) is interpolated over; fast
motion a body can make, and every clip of the shared corpus, is left as it is."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from eigengait.motion.bvh import BvhClip, BvhJoint, local_transforms, read_bvh
from eigengait.motion.capture_glitches import (
    MAX_BODY_SPEED_DEG_S,
    MAX_LIMB_SPEED_DEG_S,
    joint_speeds_deg_s,
    repair_glitches,
    speed_bounds_deg_s,
)
from eigengait.motion.lead_in import first_frame_after_lead_in
from shared_data import MOCAP

FRAME_TIME = 1 / 120
ROT = ["Zrotation", "Xrotation", "Yrotation"]


def _leg_clip(knee_deg: np.ndarray, arm_deg: np.ndarray) -> BvhClip:
    """Hips → LeftUpLeg → LeftLeg (knee bending about x by `knee_deg`) and Hips → LeftArm
    (turning about z by `arm_deg`), one value per frame, file units cm."""
    joints = [
        BvhJoint("Hips", -1, np.zeros(3), ["Xposition", "Yposition", "Zposition", *ROT]),
        BvhJoint("LeftUpLeg", 0, np.array([10.0, 0, 0]), list(ROT)),
        BvhJoint("LeftLeg", 1, np.array([0, -45.0, 0]), list(ROT), np.array([0, -45.0, 0])),
        BvhJoint("LeftArm", 0, np.array([15.0, 50, 0]), list(ROT), np.array([30.0, 0, 0])),
    ]
    n = len(knee_deg)
    frames = np.zeros((n, 6 + 3 * 3))
    frames[:, 1] = 95.0
    frames[:, 6 + 3 + 1] = knee_deg  # LeftLeg X
    frames[:, 6 + 6 + 0] = arm_deg  # LeftArm Z
    return BvhClip(joints, FRAME_TIME, frames)


def _kick(n: int = 240) -> np.ndarray:
    """A knee swinging 0-120° at 2.5 Hz: at most 940°/s, a fast kick's pace."""
    t = np.arange(n) * FRAME_TIME
    return 60.0 - 60.0 * np.cos(2 * np.pi * 2.5 * t)


def test_a_flipped_thigh_is_interpolated_back_onto_the_motion():
    # The thigh turns 150° about its own axis for 5 frames and back (a marker swap): 18 000°/s.
    knee = _kick()
    clean = _leg_clip(knee, np.zeros_like(knee))
    glitched = _leg_clip(knee, np.zeros_like(knee))
    flipped = slice(100, 105)
    glitched.frames[flipped, 6 + 2] = 150.0  # LeftUpLeg Y
    repaired, glitches = repair_glitches(glitched)
    assert [g.joint for g in glitches] == ["LeftUpLeg"]
    span = glitches[0]
    assert span.start_s <= 100 * FRAME_TIME and span.end_s >= 105 * FRAME_TIME
    assert span.end_s - span.start_s < 0.1
    clean_rot, _ = local_transforms(clean)
    fixed_rot, _ = local_transforms(repaired)
    error = Rotation.from_matrix(clean_rot[:, 1]).inv() * Rotation.from_matrix(fixed_rot[:, 1])
    assert np.degrees(error.magnitude()).max() < 1e-6  # the thigh did not otherwise turn
    inside = slice(int(round(span.start_s / FRAME_TIME)), int(round(span.end_s / FRAME_TIME)))
    untouched = np.ones(len(knee), bool)
    untouched[inside] = False
    np.testing.assert_array_equal(repaired.frames[untouched], glitched.frames[untouched])
    np.testing.assert_array_equal(repaired.frames[:, 6 + 3 :], glitched.frames[:, 6 + 3 :])


def test_a_flip_of_a_moving_knee_is_filled_along_its_motion():
    # The knee mid-swing (900°/s) flips 160° about its axis for 4 frames: the repaired knee angle
    # is within 1° of the unglitched swing.
    knee = _kick()
    clip = _leg_clip(knee, np.zeros_like(knee))
    clip.frames[170:174, 6 + 3 + 2] = 160.0  # LeftLeg Y
    repaired, glitches = repair_glitches(clip)
    assert [g.joint for g in glitches] == ["LeftLeg"]
    fixed, _ = local_transforms(repaired)
    swing, _ = local_transforms(_leg_clip(knee, np.zeros_like(knee)))
    error = Rotation.from_matrix(swing[:, 2]).inv() * Rotation.from_matrix(fixed[:, 2])
    assert np.degrees(error.magnitude()).max() < 1.0


def test_a_kick_and_a_throw_are_motion_not_glitches():
    # The knee at 940°/s and an arm whipping at 6 000°/s (under a pitch's 7 000-7 500°/s).
    knee = _kick()
    t = np.arange(len(knee)) * FRAME_TIME
    arm = 6000.0 / (2 * np.pi * 4) * np.sin(2 * np.pi * 4 * t)
    clip = _leg_clip(knee, arm)
    speeds = joint_speeds_deg_s(clip)
    assert speeds[:, 2].max() == pytest.approx(942.5, rel=0.01)
    assert speeds[:, 3].max() == pytest.approx(6000, rel=0.01)
    np.testing.assert_array_equal(
        speed_bounds_deg_s(clip),
        [MAX_BODY_SPEED_DEG_S, MAX_BODY_SPEED_DEG_S, MAX_BODY_SPEED_DEG_S, MAX_LIMB_SPEED_DEG_S],
    )
    repaired, glitches = repair_glitches(clip)
    assert glitches == []
    np.testing.assert_array_equal(repaired.frames, clip.frames)


def test_a_glitch_at_the_clip_end_holds_the_last_good_pose():
    knee = _kick()
    clip = _leg_clip(knee, np.zeros_like(knee))
    clip.frames[-3:, 6 + 2] = 170.0
    repaired, glitches = repair_glitches(clip)
    assert len(glitches) == 1 and glitches[0].end_s == pytest.approx(len(knee) * FRAME_TIME)
    first_bad = int(round(glitches[0].start_s / FRAME_TIME))
    rot, _ = local_transforms(repaired)
    np.testing.assert_allclose(
        rot[first_bad:, 1],
        np.broadcast_to(rot[first_bad - 1, 1], rot[first_bad:, 1].shape),
        atol=1e-9,
    )


@pytest.mark.parametrize("name", sorted(p.name for p in MOCAP.glob("*.bvh")))
def test_the_corpus_has_no_glitch(name):
    # The fastest leg or trunk joint of the six clips turns at 1 100°/s (the run's hips).
    clip = read_bvh(MOCAP / name)
    start = first_frame_after_lead_in(clip, 1)
    repaired, glitches = repair_glitches(clip, start)
    assert glitches == []
    np.testing.assert_array_equal(repaired.frames, clip.frames)
