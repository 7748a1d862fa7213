"""Named reads of recorded states and sensors (`sim/recording.py`) against MuJoCo's own data
fields."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.sim import WorldOptions, build_world
from eigengait.sim.contacts import CONTACT_TOLERANCE
from eigengait.sim.falls import STATE_LIMIT, failed_steps, fallen
from eigengait.sim.stepping import MAX_SPEED


@pytest.fixture(scope="module")
def world():
    return build_world(load_character("humanoid"), options=WorldOptions(activation_time=0.02))


def full_state(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    state = np.empty(mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_FULLPHYSICS))
    mujoco.mj_getState(model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    return state


def moving(world, seed: int = 0) -> mujoco.MjData:
    """The world's data in a generic state: bent joints, random speeds and activations, forward
    computed."""
    model, data = world.model, world.new_data()
    rng = np.random.default_rng(seed)
    data.qvel[:] = rng.normal(0.0, 0.5, model.nv)
    mujoco.mj_integratePos(model, data.qpos, rng.normal(0.0, 0.3, model.nv), 1.0)
    data.act[:] = rng.normal(0.0, 5.0, model.na)
    data.time = 0.25
    mujoco.mj_forward(model, data)
    return data


def test_states_are_read_as_mujoco_lays_them_out(world):
    model, data, view = world.model, moving(world), world.view
    state = full_state(model, data)
    assert view.time(state) == 0.25
    np.testing.assert_array_equal(view.qpos(state), data.qpos)
    np.testing.assert_array_equal(view.qvel(state), data.qvel)
    np.testing.assert_array_equal(view.act(state), data.act)
    np.testing.assert_array_equal(view.up_z(state), world.root.up_z(data.qpos))
    batch = np.broadcast_to(state, (2, 3, state.size))  # any leading shape
    assert view.qpos(batch).shape == (2, 3, model.nq) and view.time(batch).shape == (2, 3)
    np.testing.assert_array_equal(view.qvel(batch)[1, 2], data.qvel)
    np.testing.assert_array_equal(
        world.applied_motor_torques(batch, None)[0, 1], data.act[: world.nmotor]
    )


def test_the_com_and_the_foot_points_are_read_from_the_sensors(world):
    model, data, view = world.model, moving(world, seed=1), world.view
    sensors = data.sensordata.copy()
    np.testing.assert_allclose(
        view.com(sensors), data.subtree_com[world.root_body], rtol=0, atol=1e-12
    )
    np.testing.assert_allclose(
        view.com_velocity(sensors), data.subtree_linvel[world.root_body], rtol=0, atol=1e-12
    )
    for foot, points in world.character.feet.items():
        sites = [model.site(name).id for name in (points.toe, points.heel) if name]
        np.testing.assert_allclose(
            view.foot_points(sensors, foot), data.site_xpos[sites], rtol=0, atol=1e-12
        )
        np.testing.assert_array_equal(view.toe(sensors, foot), view.foot_points(sensors, foot)[0])
        assert view.has_heel(foot) == (points.heel is not None)
        if view.has_heel(foot):
            np.testing.assert_array_equal(
                view.heel(sensors, foot), view.foot_points(sensors, foot)[1]
            )
    batch = np.stack([sensors, 2 * sensors])
    foot = next(iter(world.character.feet))
    assert view.foot_points(batch, foot).shape == (2, len(view.foot_points_at[foot]), 3)
    np.testing.assert_array_equal(view.com(batch)[1], 2 * view.com(sensors))


def test_feet_touch_when_one_of_their_collision_spheres_reaches_the_floor(world):
    model, view = world.model, world.view
    standing, lifted = world.new_data(), world.new_data()
    world.root.lift_and_pitch(lifted.qpos, 0.05, 0.0)
    mujoco.mj_forward(model, lifted)
    for data, any_down in ((standing, True), (lifted, False)):
        touching = view.feet_touching(data.sensordata)
        expected = {}
        for foot, geoms in world.foot_spheres.items():
            # the collision spheres themselves
            bottom = data.geom_xpos[geoms, 2] - model.geom_size[geoms, 0]
            expected[foot] = bool((bottom <= CONTACT_TOLERANCE).any())
        assert {foot: bool(on) for foot, on in touching.items()} == expected
        assert any(expected.values()) == any_down
    both = view.feet_touching(np.stack([standing.sensordata, lifted.sensordata]))
    for foot, on in both.items():
        assert on.shape == (2,) and not on[1]


def test_a_rollout_row_falls_by_the_shared_rule_or_a_runaway_state(world):
    model, data, view = world.model, world.new_data(), world.view
    standing = world.standing_com_height
    state, sensors = full_state(model, data), data.sensordata.copy()
    states, readings = np.tile(state, (5, 1)), np.tile(sensors, (5, 1))
    states[1, 1 + 2] = STATE_LIMIT  # a position at the limit
    states[2, -1] = np.nan  # an activation
    view.com(readings[3])[2] = 0.4 * standing  # COM below half the standing height
    # a runaway speed: a blow-up, which `fallen` alone does not see
    states[4, 1 + model.nq] = 2 * MAX_SPEED
    np.testing.assert_array_equal(
        fallen(view, states, readings, standing), [False, True, True, True, False]
    )
    states[:, 0] = model.opt.timestep * np.arange(1, 6)
    bad, blown, qvel = failed_steps(
        view, states[None], readings[None], np.zeros((1, 1)), standing, model.opt.timestep
    )
    np.testing.assert_array_equal(bad[0], [False, True, True, True, True])
    np.testing.assert_array_equal(blown[0], [False, False, False, False, True])
    assert qvel.shape == (1, 5, model.nv)
