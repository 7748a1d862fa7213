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
# 1 400 N sideways for 0.1 s (2 N·s/kg on the 70 kg walker) at 1 s: measured, the walk at
# robustness 0.5 falls at 2.13 s; 1 300 N it survives
PUSH = BodyPush((0.0, 1400.0, 0.0), 1.0)


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
    # Up to the earliest state a recovery can rewind to, both runs are the same simulation.
    alone, recovered = pushed_walk
    earliest = alone.fall_time_s - max(REWINDS_S) - MARK_S
    frames = int(earliest / alone.frame_time)
    np.testing.assert_array_equal(recovered.qpos[:frames], alone.qpos[:frames])
    assert not np.array_equal(recovered.qpos[: len(alone.qpos)], alone.qpos)
