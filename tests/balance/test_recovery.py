"""Recovery: a tracked walk knocked over by a push is searched past by rewinding and replaying with
sampled balance targets; the played motion stays one continuous simulation."""

import numpy as np
import pytest

from eigengait.control.balance.reference import kinematic_replay
from eigengait.control.balance.tracker import (
    MARK_S,
    REWINDS_S,
    BodyPush,
    TrackerSettings,
    track,
)
from eigengait.motion.tracking import reference_poses
from shared_data import MOCAP

DURATION_S = 2.2
# 2 000 N sideways for 0.1 s (2.9 N·s/kg on the 70 kg walker) at 1 s: measured, the walk at
# robustness 0.5 falls at 2.02 s; 1 800 N and 2 200 N it survives within DURATION_S (which
# pushes knock it over is chaotic)
PUSH = BodyPush((0.0, 2000.0, 0.0), 1.0)


@pytest.fixture(scope="module")
def pushed_walk():
    ref = reference_poses(MOCAP / "cmu_02_01_walk.bvh", "walker", None, 1)
    reference = kinematic_replay(ref["world"], ref["qpos"], ref["frame_time"])

    def run(recoveries):
        settings = TrackerSettings(recoveries=recoveries, recovery_samples=4)
        return track(ref["world"], reference, 0.5, settings, DURATION_S, (PUSH,))

    return run(0), run(1)


def test_a_fall_is_searched_past_and_the_played_motion_stays_whole(pushed_walk):
    alone, recovered = pushed_walk
    assert alone.fell and alone.recoveries == 0 and alone.recovery_simulations == 0
    assert not recovered.fell and recovered.duration_s == pytest.approx(DURATION_S, abs=0.01)
    assert recovered.recoveries == 1 and recovered.recovery_simulations >= 1
    # one pose per reference frame over the whole clip: the rewound branches left nothing behind
    assert len(recovered.qpos) == int(round(DURATION_S / recovered.frame_time)) + 1
    root_steps = np.linalg.norm(np.diff(recovered.qpos[:, :3], axis=0), axis=1)
    alone_steps = np.linalg.norm(np.diff(alone.qpos[:, :3], axis=0), axis=1)
    assert root_steps.max() < 1.5 * alone_steps.max()  # no jump where a branch was cut


def test_the_motion_before_the_rewind_is_the_controllers_own(pushed_walk):
    # Both runs are the same simulation up to the mark the recovery rewound to (a multiple of
    # MARK_S, at most the last rewind before the fall), and differ after it.
    alone, recovered = pushed_walk
    n = min(len(alone.qpos), len(recovered.qpos))
    differs = np.flatnonzero(np.any(recovered.qpos[:n] != alone.qpos[:n], axis=1))
    assert differs.size
    diverged = differs[0] * alone.frame_time
    mark = np.floor(diverged / MARK_S + 1e-9) * MARK_S
    assert diverged - mark <= alone.frame_time + 1e-9  # within a frame after a mark
    assert alone.fall_time_s - max(REWINDS_S) - MARK_S <= mark < alone.fall_time_s
    assert mark >= PUSH.time_s  # here the first rewind held: 0.3 s back, after the push


def test_a_fall_early_in_the_clip_rewinds_to_its_start_once_then_plays_as_without():
    # 5 000 N at 0.1 s: the walk falls at 0.36 s, before any rewind of REWINDS_S fits; every
    # rewind reaches the first mark, which is tried once (one sample each here).
    ref = reference_poses(MOCAP / "cmu_02_01_walk.bvh", "walker", None, 1)
    reference = kinematic_replay(ref["world"], ref["qpos"], ref["frame_time"])
    shove = (BodyPush((0.0, 5000.0, 0.0), 0.1),)
    settings = TrackerSettings(recoveries=1, recovery_samples=1)
    result = track(ref["world"], reference, 0.5, settings, 1.5, shove)
    assert result.fell and result.fall_time_s < REWINDS_S[0] + MARK_S
    assert result.recoveries == 0 and result.recovery_simulations == 1
    # none kept: the clip is the controller's alone, pose for pose and error for error
    alone = track(ref["world"], reference, 0.5, TrackerSettings(), 1.5, shove)
    np.testing.assert_array_equal(result.qpos, alone.qpos)
    assert result.joint_rms_deg == alone.joint_rms_deg and result.com_error_m == alone.com_error_m
