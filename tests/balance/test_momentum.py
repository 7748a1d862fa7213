"""The momentum Jacobian (E3–E17) against MuJoCo's own centroidal quantities on random poses."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.control.balance.momentum import (
    centroidal_inertia,
    centroidal_momentum_matrix,
    foot_rooted_momentum_matrix,
    momentum_jacobian,
)
from eigengait.sim.world import build_world


@pytest.fixture(scope="module")
def world():
    return build_world(load_character("humanoid"))


def _random_state(world, seed):
    model = world.model
    data = mujoco.MjData(model)
    rng = np.random.default_rng(seed)
    data.qpos[:] = model.qpos0
    data.qpos[:3] = rng.normal(size=3)
    for j in range(model.njnt):
        if model.jnt_type[j] in (mujoco.mjtJoint.mjJNT_BALL, mujoco.mjtJoint.mjJNT_FREE):
            adr = model.jnt_qposadr[j] + (
                3 if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE else 0
            )
            q = rng.normal(size=4)
            data.qpos[adr : adr + 4] = q / np.linalg.norm(q)
    data.qvel[:] = rng.normal(size=model.nv)
    mujoco.mj_forward(model, data)
    mujoco.mj_subtreeVel(model, data)
    return model, data


@pytest.mark.parametrize("seed", range(5))
def test_centroidal_momentum_matches_engine(world, seed):
    model, data = _random_state(world, seed)
    root = world.root_body
    momentum = centroidal_momentum_matrix(model, data, root)
    mass = model.body_subtreemass[root]
    jac_com = np.zeros((3, model.nv))
    mujoco.mj_jacSubtreeCom(model, data, jac_com, root)
    np.testing.assert_allclose(momentum[3:] / mass, jac_com, atol=1e-10)
    np.testing.assert_allclose(
        momentum[:3] @ data.qvel, data.subtree_angmom[root], rtol=1e-9, atol=1e-9
    )
    np.testing.assert_allclose(
        momentum[3:] @ data.qvel, mass * data.subtree_linvel[root], rtol=1e-9, atol=1e-9
    )


def test_centroidal_inertia_gives_momentum_of_rigid_rotation(world):
    model, data = _random_state(world, 11)
    root = world.root_body
    omega = np.array([0.3, -1.2, 0.7])
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    mujoco.mj_jacBody(model, data, jacp, jacr, root)
    # Spin the whole body rigidly about its COM: root angular velocity ω (local), joints still.
    qvel = np.zeros(model.nv)
    rot = data.xmat[root].reshape(3, 3)
    qvel[3:6] = rot.T @ omega
    qvel[:3] = np.cross(omega, data.xpos[root] - data.subtree_com[root])
    inertia = centroidal_inertia(model, data, root)
    momentum = centroidal_momentum_matrix(model, data, root)
    np.testing.assert_allclose(
        momentum @ qvel, inertia @ np.concatenate([omega, np.zeros(3)]), atol=1e-9
    )


@pytest.mark.parametrize("seed", range(3))
def test_foot_rooted_jacobian_keeps_the_foot_still(world, seed):
    model, data = _random_state(world, 20 + seed)
    root = world.root_body
    foot = model.body("left_shin").id
    root_dofs = np.arange(6)
    joints = np.asarray(world.internal_qvel)
    theta_dot = np.random.default_rng(seed).normal(size=len(joints))
    momentum = centroidal_momentum_matrix(model, data, root)
    rooted = foot_rooted_momentum_matrix(model, data, momentum, foot, root_dofs, joints)
    # Recover the root velocity implied by the fixed foot and check with the engine.
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    mujoco.mj_jacBody(model, data, jacp, jacr, foot)
    jac = np.vstack([jacr, jacp])
    qvel = np.zeros(model.nv)
    qvel[joints] = theta_dot
    qvel[root_dofs] = -np.linalg.solve(jac[:, root_dofs], jac[:, joints] @ theta_dot)
    np.testing.assert_allclose(jac @ qvel, 0.0, atol=1e-9)
    data.qvel[:] = qvel
    mujoco.mj_forward(model, data)
    mujoco.mj_subtreeVel(model, data)
    expected = np.concatenate(
        [data.subtree_angmom[root], model.body_subtreemass[root] * data.subtree_linvel[root]]
    )
    np.testing.assert_allclose(rooted @ theta_dot, expected, rtol=1e-8, atol=1e-8)
    full = momentum_jacobian(model, data, root, foot, root_dofs, joints)
    np.testing.assert_allclose(
        centroidal_inertia(model, data, root) @ full @ theta_dot, expected, atol=1e-8
    )


def test_shared_momentum_and_inertia_give_the_same_jacobian(world):
    model, data = _random_state(world, 31)
    root, foot = world.root_body, model.body("right_shin").id
    joints = np.asarray(world.internal_qvel)
    shared = momentum_jacobian(
        model,
        data,
        root,
        foot,
        np.arange(6),
        joints,
        momentum=centroidal_momentum_matrix(model, data, root),
        inertia=centroidal_inertia(model, data, root),
    )
    np.testing.assert_array_equal(
        shared, momentum_jacobian(model, data, root, foot, np.arange(6), joints)
    )
