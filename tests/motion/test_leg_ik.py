"""Leg IK: the foot reaches its target, and among the leg poses that reach it the one nearest a
preferred pose is found (the walker's leg: three ball joints, nine dofs for a six-dof foot pose)."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.body_tree import limb_dofs
from eigengait.motion.leg_ik import solve_leg
from eigengait.sim.world import build_world


@pytest.fixture(scope="module")
def leg():
    world = build_world(load_character("walker"))
    model = world.model
    foot, other = (int(model.geom_bodyid[world.foot_spheres[f][0]]) for f in ("left", "right"))
    return model, foot, np.array(limb_dofs(model, foot, [other]), int)


def _foot_pose(model, qpos, foot):
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(model, data)
    return data.xpos[foot].copy(), data.xmat[foot].reshape(3, 3).copy()


def _bent(model, dofs, seed):
    """The rest pose with the leg's dofs turned by up to 0.3 rad (seeded)."""
    qpos = model.qpos0.copy()
    turn = np.zeros(model.nv)
    turn[dofs] = np.random.default_rng(seed).uniform(-0.3, 0.3, len(dofs))
    mujoco.mj_integratePos(model, qpos, turn, 1.0)
    return qpos


def test_the_foot_reaches_a_reachable_pose(leg):
    model, foot, dofs = leg
    goal = _bent(model, dofs, 1)
    data = mujoco.MjData(model)
    data.qpos[:] = model.qpos0
    error = solve_leg(model, data, foot, dofs, *_foot_pose(model, goal, foot), preferred=goal)
    position, rotation = _foot_pose(model, data.qpos, foot)
    assert error < 1e-4
    assert np.linalg.norm(position - _foot_pose(model, goal, foot)[0]) < 1e-4
    assert np.allclose(rotation, _foot_pose(model, goal, foot)[1], atol=1e-3)


def test_among_the_poses_that_reach_the_target_the_preferred_one_is_found(leg):
    # Started from another leg pose, with the foot's pose at the preferred one as the target: the
    # redundancy is resolved toward the preferred pose, which plain damped steps do not do.
    model, foot, dofs = leg
    preferred, start = _bent(model, dofs, 2), _bent(model, dofs, 3)
    target = _foot_pose(model, preferred, foot)
    distance = {}
    for name, prefer in (("preferred", preferred), ("plain", None)):
        data = mujoco.MjData(model)
        data.qpos[:] = start
        assert solve_leg(model, data, foot, dofs, *target, preferred=prefer) < 1e-3
        gap = np.zeros(model.nv)
        mujoco.mj_differentiatePos(model, gap, 1.0, data.qpos, preferred)
        distance[name] = np.linalg.norm(gap[dofs])
    assert distance["preferred"] < 0.01 and distance["plain"] > 0.3
