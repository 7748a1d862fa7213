"""The stateless balance controller: `balance_torque` reads the state and one reference frame, keeps
nothing."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.control.balance.controller import (
    balance_torque,
    equilibrium_torque,
    foot_contacts,
    normal_forces,
    pd_target,
    pd_torque,
    plant_torque,
    press_torque,
    stance_forces,
)
from eigengait.control.balance.pd import pd_torques
from eigengait.control.balance.standing import standing_reference
from eigengait.control.balance.tracker import Tracker
from eigengait.sim.world import build_world


@pytest.fixture(scope="module")
def standing():
    """A walker tracker that has stood for 0.1 s in its pose (feet loaded), forwarded, and the
    reference frame."""
    world = build_world(load_character("walker"))
    tracker = Tracker(world, standing_reference(world, 0.5), robustness=0.5)
    tracker.run(duration_s=0.1)
    mujoco.mj_forward(tracker.model, tracker.data)
    return tracker, tracker._reference_at(tracker.data.time)


def _state(data):
    return [
        a.copy() for a in (data.qpos, data.qvel, data.ctrl, data.xfrc_applied, data.qfrc_applied)
    ]


def test_the_same_state_and_frame_give_the_same_command_and_leave_the_state(standing):
    tracker, target = standing
    before = _state(tracker.data)
    first = balance_torque(tracker.model, tracker.data, tracker.rig, target)
    second = balance_torque(tracker.model, tracker.data, tracker.rig, target)
    assert np.array_equal(first.torque, second.torque) and first.artificial == second.artificial
    # standing: feet loaded
    assert first.foot_torques.keys() == second.foot_torques.keys() and first.foot_torques
    for a, b in zip(before, _state(tracker.data)):
        assert np.array_equal(a, b)


def test_the_command_is_the_pd_plus_the_balance_on_the_stance_feet(standing):
    tracker, target = standing
    model, data, rig = tracker.model, tracker.data, tracker.rig
    forces = stance_forces(model, data, rig)
    assert all(n > 0 for n in forces.values())  # both feet on the floor
    contacts = foot_contacts(model, data, rig)
    command = balance_torque(model, data, rig, target)
    tau_eq, feet, magnitude = equilibrium_torque(model, data, rig, target, contacts)
    tau_pd = pd_torque(data, rig, {**target, "qpos": pd_target(model, data, rig, target, contacts)})
    press = press_torque(model, data, rig, target, contacts)
    plant = plant_torque(model, data, rig, target, contacts)
    np.testing.assert_array_equal(command.torque, tau_pd + tau_eq + press + plant)
    assert not plant.any()  # both feet carry their share of the weight
    assert not command.airborne
    assert (
        magnitude == pytest.approx(sum(np.linalg.norm(t) for t in feet.values())) and magnitude > 0
    )
    dof = rig.ball_dof
    expected = pd_torques(
        data.qpos[rig.ball_qpos],
        target["qpos"][rig.ball_qpos],
        0.0,
        target["qvel"][dof],
        rig.k_s[dof],
        rig.k_d[dof],
    )
    np.testing.assert_array_equal(pd_torque(data, rig, target)[dof], expected)
    assert np.abs(expected).max() > 0


def test_a_foot_carries_the_support_asked_of_it_not_a_larger_measured_force(standing):
    """With the COM target 15 cm ahead the feet cannot carry the balance torque: part of it is
    cancelled by the artificial torque. Measured normal forces 3 or 30 times the standing ones (an
    ankle pressing one edge of the foot into the floor raises them) change nothing: the torque a
    foot carries is bounded by the vertical support the balance asks of it."""
    tracker, target = standing
    model, data, rig = tracker.model, tracker.data, tracker.rig
    ahead = {**target, "com": target["com"] + np.array([0.15, 0.0, 0.0])}
    contacts = foot_contacts(model, data, rig)
    results = []
    for scale in (3.0, 30.0):
        scaled = {f: c * np.array([1.0, 1.0, 1.0, scale]) for f, c in contacts.items()}
        results.append(equilibrium_torque(model, data, rig, ahead, scaled))
    (tau_a, _, size_a), (tau_b, _, size_b) = results
    assert size_a > 1.0
    assert size_b == pytest.approx(size_a, rel=1e-9)
    np.testing.assert_allclose(tau_b, tau_a, atol=1e-9)


def test_in_flight_there_is_no_balance_torque_and_the_legs_reach_for_the_floor(standing):
    tracker, target = standing
    model, rig = tracker.model, tracker.rig
    data = mujoco.MjData(model)
    data.qpos[:] = tracker.data.qpos
    data.qpos[rig.root_qpos + 2] += 1.0  # a metre up
    mujoco.mj_forward(model, data)
    command = balance_torque(model, data, rig, target)
    assert command.foot_torques == {} and command.artificial == 0.0 and command.airborne
    # the PD toward the reference's own pose, and the feet that the reference has on the floor
    # pressed down
    press = press_torque(model, data, rig, target, foot_contacts(model, data, rig))
    plant = plant_torque(model, data, rig, target, foot_contacts(model, data, rig))
    np.testing.assert_array_equal(command.torque, pd_torque(data, rig, target) + press + plant)
    assert not plant.any()  # a metre up: the feet are not near the floor
    # legs only
    assert np.abs(press[rig.leg_dofs["left"]]).max() > 0 and not press[rig.ball_dof[0]].any()


def test_the_tracker_gives_the_walker_soles():
    # The box of each foot touches the floor, its bottom on the plane of the heel and toe spheres'
    # bottoms (the walker's boxes sit 3 cm higher, so a flat foot stood on its two spheres only).
    world = build_world(load_character("walker"))
    tracker = Tracker(world, standing_reference(world, 0.2), robustness=0.5)
    model = tracker.model
    for spheres in world.foot_spheres.values():
        body = model.geom_bodyid[spheres[0]]
        boxes = [
            g
            for g in range(model.ngeom)
            if model.geom_bodyid[g] == body and model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX
        ]
        assert len(boxes) == 1 and model.geom_contype[boxes[0]] != 0
        sole = model.geom_pos[boxes[0], 2] - model.geom_size[boxes[0], 2]
        assert sole == pytest.approx(
            float(np.min(model.geom_pos[spheres, 2] - model.geom_size[spheres, 0]))
        )
    # the world's own model: as it was
    assert world.model.geom_pos[boxes[0], 2] > model.geom_pos[boxes[0], 2] + 0.02


def test_toes_on_their_own_joint_touch_as_their_foot():
    """dm_control's CMU humanoid: each foot body carries toes on their own joint. Standing with no
    clip, every push of the floor on a foot or its toes is read as that foot's, the toes'
    included, and nothing else touches."""
    from shared_data import DM_CONTROL

    world = build_world(load_character(DM_CONTROL / "suite/humanoid_CMU.xml", stiffness="auto"))
    tracker = Tracker(world, standing_reference(world, 0.3), robustness=0.5)
    tracker.run(duration_s=0.2)
    model, data, rig = tracker.model, tracker.data, tracker.rig
    mujoco.mj_forward(model, data)
    toes = {model.body(name).id: foot for name, foot in (("ltoes", "lfoot"), ("rtoes", "rfoot"))}
    assert {b: rig.foot_of_body[b] for b in toes} == toes
    wrench, on_floor, on_toes = np.zeros(6), 0.0, 0.0
    for i in range(data.ncon):
        contact = data.contact[i]
        if rig.floor in (contact.geom1, contact.geom2):
            mujoco.mj_contactForce(model, data, i, wrench)
            on_floor += max(wrench[0], 0.0)
            other = contact.geom2 if contact.geom1 == rig.floor else contact.geom1
            on_toes += max(wrench[0], 0.0) * (model.geom_bodyid[other] in toes)
    read = sum(normal_forces(foot_contacts(model, data, rig)).values())
    assert on_toes > 0.02 * on_floor and read == pytest.approx(on_floor, rel=1e-9)
