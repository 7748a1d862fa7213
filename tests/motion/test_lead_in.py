"""A clip's lead-in (a synthetic first pose and the blend out of it) is skipped; a clip's own motion
is not. The reference starts on its first supported pose."""

import numpy as np

from eigengait.motion.bvh import read_bvh
from eigengait.motion.foot_metrics import CONTACT_M
from eigengait.motion.lead_in import (
    LEAD_IN_MAX_S,
    first_frame_after_lead_in,
    first_supported_pose,
    largest_bone_turns_deg,
)
from eigengait.motion.soles import sole_points
from eigengait.motion.tracking import reference_poses
from shared_data import MOCAP

FRAME_TIME = 1 / 120


def write_clip(tmp_path, angles_deg) -> object:
    """A two-bone clip whose child bone turns about z through `angles_deg` (one per frame)."""
    lines = [
        "HIERARCHY",
        "ROOT hips",
        "{",
        "OFFSET 0 0 0",
        "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        "JOINT arm",
        "{",
        "OFFSET 0 1 0",
        "CHANNELS 3 Zrotation Xrotation Yrotation",
        "End Site",
        "{",
        "OFFSET 0 1 0",
        "}",
        "}",
        "}",
        "MOTION",
        f"Frames: {len(angles_deg)}",
        f"Frame Time: {FRAME_TIME}",
    ]
    lines += [f"0 90 0 0 0 0 {a:.6f} 0 0" for a in angles_deg]
    path = tmp_path / "clip.bvh"
    path.write_text("\n".join(lines) + "\n")
    return read_bvh(path)


def swing(n, start=0.0):
    """An arm swing of ±20° at 1 Hz, from phase `start` (rad): about 1° per frame at most."""
    t = np.arange(n) * FRAME_TIME
    return 20 * np.sin(2 * np.pi * t + start)


def test_bone_turns_are_the_frame_to_frame_rotation_angles(tmp_path):
    clip = write_clip(tmp_path, [0, 10, 25, 25])
    np.testing.assert_allclose(largest_bone_turns_deg(clip), [10, 15, 0], atol=1e-6)


def test_a_t_pose_and_a_blend_out_of_it_are_skipped(tmp_path):
    motion = swing(240, start=1.0)
    t_pose = 90.0
    # ~20° per frame, as Daz exports do
    blend = [t_pose + (motion[0] - t_pose) * k / 4 for k in range(1, 4)]
    clip = write_clip(tmp_path, [t_pose, *blend, *motion])
    assert first_frame_after_lead_in(clip, 0) == 4  # the first frame of the clip's own motion
    assert first_frame_after_lead_in(clip, 1) == 4


def test_a_clip_that_starts_in_its_motion_keeps_its_start(tmp_path):
    clip = write_clip(tmp_path, swing(240))
    assert first_frame_after_lead_in(clip, 0) == 0
    assert first_frame_after_lead_in(clip, 7) == 7
    # outside the clip: left for retarget to refuse
    assert first_frame_after_lead_in(clip, -5) == -5


def test_fast_motion_longer_than_a_lead_in_is_kept(tmp_path):
    fast = int(2 * LEAD_IN_MAX_S / FRAME_TIME)  # 0.2 s of 15° per frame, then a slow swing
    clip = write_clip(tmp_path, [*(15.0 * np.arange(fast) % 360), *swing(240)])
    assert first_frame_after_lead_in(clip, 0) == 0


def _feet(left_heights, right_heights) -> dict:
    """Sole points (F, 2, 3) per foot whose lower point is at the given heights (m)."""
    feet = {}
    for name, heights in (("left", left_heights), ("right", right_heights)):
        points = np.zeros((len(heights), 2, 3))
        points[:, 0, 2] = heights
        points[:, 1, 2] = np.asarray(heights) + 0.04  # the other point of a tilted foot
        feet[name] = points
    return feet


def test_the_first_supported_pose_is_the_first_with_a_foot_within_the_contact_band():
    above = CONTACT_M + 0.03
    assert first_supported_pose(_feet([above, above, 0.0], [above, CONTACT_M, 0.1])) == 1
    assert first_supported_pose(_feet([0.0, above], [above, above])) == 0
    assert first_supported_pose(_feet([above] * 3, [above] * 3)) == 0  # never supported: unchanged


def test_a_run_started_in_flight_is_referenced_from_its_landing():
    # The CMU run's reference is in the air at clip frames 72-82 (measured: lowest sole point up to
    # 6 cm); asked to start at 74, it starts where a foot is down again, within that flight.
    ref = reference_poses(MOCAP / "cmu_16_36_run_daz.bvh", "walker", None, start_frame=74)
    soles = sole_points(ref["world"], ref["qpos"])
    lowest = min(points[0, :, 2].min() for points in soles.values())
    assert lowest <= CONTACT_M
    assert 74 < ref["first_frame"] <= 74 + round(0.1 / FRAME_TIME)
