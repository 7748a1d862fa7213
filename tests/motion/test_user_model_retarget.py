"""A clip retargeted onto a user's model that faces elsewhere and stands on hinged, guessed feet:
dm_control's CMU humanoid (root turned 90° about x, facing −y, each foot on two hinges)."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.motion.bvh import read_bvh
from eigengait.motion.foot_level import still_frames
from eigengait.motion.retarget import builtin_mapping, facing_turn, retarget
from eigengait.motion.soles import sole_points
from eigengait.sim.feet import sole_up
from eigengait.sim.world import build_world
from shared_data import DM_CONTROL, MOCAP


@pytest.fixture(scope="module")
def cmu():
    world = build_world(load_character(DM_CONTROL / "suite/humanoid_CMU.xml", stiffness="auto"))
    clip = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    return world, retarget(clip, world, builtin_mapping(world.character.name, clip, world))


def test_the_model_is_turned_to_face_where_the_clip_walks(cmu):
    world, poses = cmu
    data = mujoco.MjData(world.model)
    mujoco.mj_kinematics(world.model, data)
    turn = facing_turn(world, data)
    np.testing.assert_allclose(turn @ [0.0, -1.0, 0.0], [1.0, 0.0, 0.0], atol=0.05)
    # walking where it faces, its stance feet stay under its legs: the root path needs about the
    # factor the walker's does on this clip (0.89); walked sideways, the fit hit its 0.5 floor
    assert 0.85 < poses.root_factor < 1.05
    travel = poses.qpos[-1, :2] - poses.qpos[0, :2]
    assert travel[0] > 2.0 and abs(travel[1]) < 0.3 * travel[0]


def test_hinged_feet_are_levelled_to_their_soles(cmu):
    world, poses = cmu
    assert set(poses.foot_level_deg) == set(world.character.feet)
    model, data = world.model, mujoco.MjData(world.model)
    soles = sole_points(world, poses.qpos)
    for foot, spheres in world.foot_spheres.items():
        body = int(model.geom_bodyid[spheres[0]])
        ups = []
        for i in np.flatnonzero(still_frames(soles[foot], poses.frame_time)):
            data.qpos[:] = poses.qpos[i]
            mujoco.mj_kinematics(model, data)
            ups.append(data.xmat[body].reshape(3, 3) @ sole_up(world, foot))
        mean = np.mean(ups, axis=0)
        assert np.degrees(np.arccos(mean[2] / np.linalg.norm(mean))) < 3.0
