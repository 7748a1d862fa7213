"""Skate removal by leg IK on a Daz-skeleton walk: the cleaned reference's feet hold still, the upper body is kept."""

from pathlib import Path

import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.motion.bvh import read_bvh
from eigengait.motion.foot_cleanup import clean_feet
from eigengait.motion.foot_metrics import foot_report
from eigengait.motion.retarget import builtin_mapping, retarget
from eigengait.motion.soles import sole_points
from eigengait.sim.world import build_world

MOCAP = Path(__file__).resolve().parents[3] / "shared" / "data" / "mocap"  # shared/ beside the repo
SKATE_BOUND_M = 0.03


@pytest.fixture(scope="module")
def cleaned():
    world = build_world(load_character("walker"))
    clip = read_bvh(MOCAP / "cmu_07_06_walk_daz.bvh")
    poses = retarget(clip, world, builtin_mapping("walker", clip))
    return world, poses, clean_feet(world, poses.qpos, poses.frame_time)


def test_cleaned_skate_is_below_the_bound_where_the_raw_one_is_above(cleaned):
    # Measured: raw 0.079 m per stance, cleaned 0.006 m.
    world, poses, result = cleaned
    raw = foot_report(sole_points(world, poses.qpos), poses.frame_time)
    clean = foot_report(sole_points(world, result.qpos), poses.frame_time)
    assert raw.foot_skate_m > SKATE_BOUND_M > clean.foot_skate_m
    assert clean.stances >= 4 and clean.floor_penetration_m < 0.005
    assert result.ik_error_m < 0.06


def test_only_the_legs_move(cleaned):
    world, poses, result = cleaned
    model = world.model
    leg = [j for j in range(model.njnt) if any(s in model.joint(j).name for s in ("thigh", "shin", "foot"))]
    legs = np.concatenate([model.jnt_qposadr[j] + np.arange(4) for j in leg])
    others = np.setdiff1d(np.arange(model.nq), legs)
    np.testing.assert_array_equal(result.qpos[:, others], poses.qpos[:, others])
    assert np.abs(result.qpos[:, legs] - poses.qpos[:, legs]).max() > 0.01
