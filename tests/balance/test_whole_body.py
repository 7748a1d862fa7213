"""The tracker's whole-body inverse-dynamics controller (`wbc.py`, `--controller qp`)."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.control.balance.controller import foot_contacts
from eigengait.control.balance.reference import kinematic_replay
from eigengait.control.balance.standing import stand, standing_reference
from eigengait.control.balance.tracker import Tracker, TrackerSettings, track
from eigengait.errors import UserInputError
from eigengait.motion.bvh import read_bvh
from eigengait.motion.retarget import builtin_mapping, retarget
from eigengait.sim.world import GRAVITY, build_world
from shared_data import MOCAP

QP = TrackerSettings(controller="qp")


@pytest.fixture(scope="module")
def walker():
    return build_world(load_character("walker"))


def test_standing_still_the_feet_carry_the_weight_and_nothing_else_is_needed(walker):
    tracker = Tracker(walker, standing_reference(walker, 1.0), 0.5, QP)
    mujoco.mj_forward(tracker.model, tracker.data)
    target = tracker._reference_at(0.0)
    command = tracker.qp.command(
        tracker.data, target, foot_contacts(tracker.model, tracker.data, tracker.rig)
    )
    weight = walker.mass() * GRAVITY
    # at rest the contact forces the solution counts on are the weight, straight up (statics)
    np.testing.assert_allclose(command.contact_force, [0.0, 0.0, weight], atol=0.01 * weight)
    assert np.linalg.norm(command.artificial) < 1.0  # N·m: the pose stands on its own


def test_standing_at_robustness_0_holds_still_with_no_artificial_torque(walker):
    standing = stand(walker, 0.0, 1.0, settings=QP)
    result = standing.tracking
    assert standing.at_rest and result.artificial_torque == 0.0
    # measured: COM error 0.9 mm, joint RMS 0.04°
    assert result.com_error_m < 0.005 and result.joint_rms_deg < 1.0


def test_the_walker_tracks_the_first_second_of_the_cmu_walk(walker):
    # measured: joint RMS 1.5°, COM error 0.014 m, mean artificial torque 45 N·m (robustness 0.5;
    # the raw retargeted feet, which slide); the momentum controller on the same second: 2.0°,
    # 0.010 m, 47 N·m
    clip = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    poses = retarget(clip, walker, builtin_mapping("walker", clip))
    reference = kinematic_replay(walker, poses.qpos, poses.frame_time)
    result = track(walker, reference, 0.5, QP, duration_s=1.0)
    assert not result.fell and result.duration_s == pytest.approx(1.0, abs=0.01)
    assert result.joint_rms_deg < 3.0 and result.com_error_m < 0.03
    assert 0.0 < result.artificial_torque < 100.0


def test_an_unknown_controller_is_refused_by_name(walker):
    with pytest.raises(UserInputError) as err:
        Tracker(walker, standing_reference(walker, 0.1), 0.5, TrackerSettings(controller="pid"))
    assert err.value.field == "controller" and "qp" in str(err.value)


def _lowest_point_after_a_raised_reference_foot(walker, monkeypatch, lift_weight: float) -> float:
    """Height (m) of the first foot's lowest sole point after 0.3 s of standing while the reference
    raises that foot's lowest sole point from 3 cm at 0.2 m/s (its pose standing, so the joint task
    alone asks for no lift)."""
    from eigengait.control.balance import wbc
    from eigengait.control.balance.foot_sole import lowest_sole_point, sole_geoms

    monkeypatch.setattr(wbc, "LIFT_WEIGHT", lift_weight)
    reference = standing_reference(walker, 0.5)
    times = np.arange(len(reference.foot_height)) * reference.frame_time
    reference.foot_height[:, 0] = 0.03 + 0.2 * times
    tracker = Tracker(walker, reference, 0.5, QP)
    model, data, rig = tracker.model, tracker.data, tracker.rig
    foot = next(iter(rig.foot_bodies))
    spheres = rig.foot_spheres[foot]
    while data.time < 0.3:
        mujoco.mj_forward(model, data)
        tracker._whole_body_step(tracker._reference_at(data.time), foot_contacts(model, data, rig))
        mujoco.mj_step(model, data)
    mujoco.mj_forward(model, data)
    return float(lowest_sole_point(model, data, spheres, sole_geoms(model, spheres))[2])


def test_a_foot_the_reference_raises_is_lifted_off_the_floor(walker, monkeypatch):
    # the lift-off row raises the foot, which carries half the weight, 4.1 mm in 0.3 s (measured);
    # without it the standing pose's joint task keeps the foot on the floor (-0.1 mm)
    lifted = _lowest_point_after_a_raised_reference_foot(walker, monkeypatch, 10.0)
    left = _lowest_point_after_a_raised_reference_foot(walker, monkeypatch, 0.0)
    assert left < 0.001
    assert lifted > 0.003


def test_the_cmu_run_is_tracked_without_a_foot_skimming_the_floor():
    # measured at robustness 0.5: skate per stance 1.65 cm, 2.75 cm at worst (4.5 and 16.3 cm
    # without the lift-off row, its toe-off feet dragged along the floor); joint RMS 3.2°
    from eigengait.motion.tracking import run_track

    _, _, result = run_track(MOCAP / "cmu_16_36_run_daz.bvh", "walker", 0.5, None, None, 1, 0.0)
    assert not result.fell and result.joint_rms_deg < 4.0 and result.com_error_m < 0.05
    assert result.foot_skate_max_m < 0.05
