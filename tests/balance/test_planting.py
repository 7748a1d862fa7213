"""Planting: lightly loaded feet that the reference has down are damped horizontally through the
leg; the torque is checked against MuJoCo's own mapping of a point force (`mj_applyFT`)."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.control.balance.planting import (
    DAMPING_PER_KG,
    LIGHT_LOAD,
    planting_torque,
    sliding_force,
    transition_windows,
)
from eigengait.control.balance.standing import standing_reference
from eigengait.control.balance.tracker import Tracker
from eigengait.sim.world import GRAVITY, build_world


@pytest.fixture(scope="module")
def walker():
    """The walker standing on the floor, gliding forward at 0.4 m/s and sideways at 0.1 m/s."""
    world = build_world(load_character("walker"))
    tracker = Tracker(world, standing_reference(world, 0.5), robustness=0.5)
    model, data, rig = tracker.model, tracker.data, tracker.rig
    data.qvel[rig.root_dofs[:2]] = [0.4, 0.1]
    mujoco.mj_forward(model, data)
    return model, data, rig


def _torque(walker, planting, normals, data=None):
    """`planting_torque` on the walker's state (or `data`), the reference feet at rest."""
    model, walker_data, rig = walker
    data = walker_data if data is None else data
    return planting_torque(
        model,
        data,
        np.asarray(planting),
        np.zeros((2, 2)),
        normals,
        rig.foot_bodies,
        rig.foot_spheres,
        rig.leg_dofs,
        rig.mass,
        GRAVITY,
    )


def test_the_sliding_force_opposes_the_horizontal_velocity_only():
    force = sliding_force(np.array([0.4, -0.1, 2.0]), np.array([0.1, 0.0]), 700.0)
    np.testing.assert_allclose(force, [-210, 70, 0])


def test_an_unloaded_planted_foot_is_damped_as_a_point_force_on_its_leg(walker):
    model, data, rig = walker
    feet = list(rig.foot_bodies)
    tau = _torque(walker, [True, True], {f: 0.0 for f in feet})
    for foot in feet:
        spheres = rig.foot_spheres[foot]
        point = data.geom_xpos[spheres].mean(axis=0)
        force = -DAMPING_PER_KG * rig.mass * np.array([0.4, 0.1, 0.0])  # the body glides
        expected = np.zeros(model.nv)
        mujoco.mj_applyFT(model, data, force, np.zeros(3), point, rig.foot_bodies[foot], expected)
        chain = rig.leg_dofs[foot]
        np.testing.assert_allclose(tau[chain], expected[chain], rtol=1e-9, atol=1e-9)
    legs = sorted(set().union(*(set(rig.leg_dofs[f]) for f in feet)))
    assert np.abs(tau[legs]).max() > 1.0
    assert not np.delete(tau, legs).any()  # nothing on the root or the upper body


def test_loaded_lifted_or_mid_stance_feet_are_left_alone(walker):
    _, data, rig = walker
    left, right = rig.foot_bodies
    weight = rig.mass * GRAVITY
    loaded = _torque(walker, [True, True], {left: LIGHT_LOAD * weight, right: weight})
    outside = _torque(walker, [False, False], {left: 0.0, right: 0.0})
    assert not loaded.any() and not outside.any()
    # the simulated foot 5 cm up while the reference has it down: not damped either
    lifted_data = mujoco.MjData(walker[0])
    lifted_data.qpos[:] = data.qpos
    lifted_data.qvel[:] = data.qvel
    lifted_data.qpos[rig.root_qpos + 2] += 0.05
    mujoco.mj_forward(walker[0], lifted_data)
    lifted = _torque(walker, [True, True], {left: 0.0, right: 0.0}, lifted_data)
    assert not lifted.any()


def test_windows_surround_touchdowns_and_lift_offs_of_a_down_foot():
    # 100 frames at 0.01 s: foot 0 in the air until frame 30, down to frame 70, then up; foot 1
    # down throughout (a standing foot has no transition)
    heights = np.zeros((100, 2))
    heights[:30, 0] = heights[70:, 0] = 0.1
    windows = transition_windows(heights, 0.01, window_s=0.05)
    np.testing.assert_array_equal(np.flatnonzero(windows[:, 0]), [*range(30, 35), *range(65, 70)])
    assert not windows[:, 1].any()
