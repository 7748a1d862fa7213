"""The stateless balance controller: `balance_torque` reads the state and one reference frame, keeps nothing."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.control.balance.controller import balance_torque, equilibrium_torque, pd_torque, stance_forces
from eigengait.control.balance.pd import pd_torques
from eigengait.control.balance.standing import standing_reference
from eigengait.control.balance.tracker import Tracker
from eigengait.sim.world import build_world


@pytest.fixture(scope="module")
def standing():
    """A walker tracker that has stood for 0.1 s in its pose (feet loaded), forwarded, and the reference frame."""
    world = build_world(load_character("walker"))
    tracker = Tracker(world, standing_reference(world, 0.5), robustness=0.5)
    tracker.run(duration_s=0.1)
    mujoco.mj_forward(tracker.model, tracker.data)
    return tracker, tracker._reference_at(tracker.data.time)


def _state(data):
    return [a.copy() for a in (data.qpos, data.qvel, data.ctrl, data.xfrc_applied, data.qfrc_applied)]


def test_the_same_state_and_frame_give_the_same_command_and_leave_the_state(standing):
    tracker, target = standing
    before = _state(tracker.data)
    first = balance_torque(tracker.model, tracker.data, tracker.rig, target)
    second = balance_torque(tracker.model, tracker.data, tracker.rig, target)
    assert np.array_equal(first.torque, second.torque) and first.artificial == second.artificial
    assert first.foot_torques.keys() == second.foot_torques.keys() and first.foot_torques  # standing: feet loaded
    for a, b in zip(before, _state(tracker.data)):
        assert np.array_equal(a, b)


def test_the_command_is_the_pd_plus_the_balance_on_the_stance_feet(standing):
    tracker, target = standing
    model, data, rig = tracker.model, tracker.data, tracker.rig
    forces = stance_forces(model, data, rig)
    assert all(n > 0 for n in forces.values())  # both feet on the floor
    command = balance_torque(model, data, rig, target)
    tau_eq, feet, magnitude = equilibrium_torque(model, data, rig, target, forces)
    np.testing.assert_array_equal(command.torque, pd_torque(data, rig, target) + tau_eq)
    assert magnitude == pytest.approx(sum(np.linalg.norm(t) for t in feet.values())) and magnitude > 0
    dof = rig.ball_dof
    expected = pd_torques(
        data.qpos[rig.ball_qpos], target["qpos"][rig.ball_qpos], 0.0, target["qvel"][dof], rig.k_s[dof], rig.k_d[dof]
    )
    np.testing.assert_array_equal(pd_torque(data, rig, target)[dof], expected)
    assert np.abs(expected).max() > 0


def test_in_flight_there_is_no_balance_torque(standing):
    tracker, target = standing
    model, rig = tracker.model, tracker.rig
    data = mujoco.MjData(model)
    data.qpos[:] = tracker.data.qpos
    data.qpos[rig.root_qpos + 2] += 1.0  # a metre up
    mujoco.mj_forward(model, data)
    command = balance_torque(model, data, rig, target)
    assert command.foot_torques == {} and command.artificial == 0.0
    np.testing.assert_array_equal(command.torque, pd_torque(data, rig, target))
