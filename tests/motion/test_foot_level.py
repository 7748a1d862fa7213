"""Levelling and joint ranges on retargeted CMU clips: feet that stand still stand flat, no joint
past its limit."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.motion.bvh import read_bvh
from eigengait.motion.foot_level import level_feet, still_frames
from eigengait.motion.retarget import builtin_mapping, retarget
from eigengait.motion.soles import sole_points
from eigengait.sim.world import build_world
from shared_data import MOCAP


@pytest.fixture(scope="module")
def world():
    return build_world(load_character("walker"))


def _still_tilt_deg(world, qpos, frame_time):
    """Per foot: the tilt (degrees) of the world up direction averaged in the foot's frame over its
    still frames (a constant error in the foot's rest orientation shows as such a mean tilt)."""
    model, data = world.model, mujoco.MjData(world.model)
    soles = sole_points(world, qpos)
    out = {}
    for foot, geoms in world.foot_spheres.items():
        body = int(model.geom_bodyid[geoms[0]])
        ups = []
        for i in np.flatnonzero(still_frames(soles[foot], frame_time)):
            data.qpos[:] = qpos[i]
            mujoco.mj_kinematics(model, data)
            ups.append(data.xmat[body].reshape(3, 3).T @ [0.0, 0.0, 1.0])
        mean = np.mean(ups, axis=0)
        out[foot] = float(np.degrees(np.arccos(mean[2] / np.linalg.norm(mean))))
    return out


def test_levelled_feet_stand_flat_on_average_when_still(world):
    # Measured on the MotionBuilder walk: its still feet stand rolled about 23° before levelling
    # (the foot bone's rest twist), and the mean tilt is below 1° after.
    clip = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    poses = retarget(clip, world, builtin_mapping("walker", clip))
    assert min(poses.foot_level_deg.values()) > 10.0
    assert max(_still_tilt_deg(world, poses.qpos, poses.frame_time).values()) < 2.0
    again, angles = level_feet(world, poses.qpos, poses.frame_time)
    assert max(angles.values()) < 2.0 and np.abs(again - poses.qpos).max() < 0.05


def test_no_joint_is_past_its_range(world):
    # The Daz walk 05_01's head is turned 60-91° in the clip, past the walker's 60° limit.
    clip = read_bvh(MOCAP / "cmu_05_01_walk_daz.bvh")
    poses = retarget(clip, world, builtin_mapping("walker", clip), start_frame=4)
    model = world.model
    for j in np.flatnonzero(model.jnt_limited & (model.jnt_type == mujoco.mjtJoint.mjJNT_BALL)):
        adr = model.jnt_qposadr[j]
        angle = 2 * np.arccos(np.clip(np.abs(poses.qpos[:, adr]), 0, 1))
        assert angle.max() <= model.jnt_range[j, 1] + 1e-6, model.joint(j).name
    # the scale fitted to the legs: about three quarters of the thighs'-height scale for the Daz
    # exports, whose root travels further than their legs carry it (measured 0.761)
    assert 0.65 < poses.root_factor < 0.85
