"""A body on several hinges retargeted: the chain's angles from a wanted turn, and dm_control's
humanoid (hips on three hinges, ankles on two) following a CMU walk's thighs."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.geometry import mat_to_quat, quat_angle, quat_exp, quat_to_mat
from eigengait.motion.bvh import global_transforms, read_bvh
from eigengait.motion.hinge_chain import hinge_angles
from eigengait.motion.retarget import clip_axes, load_mapping, retarget
from eigengait.sim.world import build_world
from shared_data import DM_CONTROL, MOCAP

HIP_AXES = np.array([[1.0, 0, 0], [0, 0, 1.0], [0, 1.0, 0]])  # dm_control's hip_x, hip_z, hip_y


def _chain(angles: np.ndarray, axes: np.ndarray) -> np.ndarray:
    turn = np.broadcast_to(np.eye(3), (len(angles), 3, 3))
    for i, axis in enumerate(axes):
        turn = turn @ quat_to_mat(quat_exp(angles[:, [i]] * axis))
    return turn


def test_three_hinges_are_recovered_from_their_turn():
    angles = np.random.default_rng(0).uniform(-1.2, 1.2, (400, 3))
    assert hinge_angles(_chain(angles, HIP_AXES), HIP_AXES) == pytest.approx(angles, abs=1e-9)


def test_two_hinges_give_the_nearest_turn_they_can_make():
    angles = np.random.default_rng(1).uniform(-1.0, 1.0, (50, 2))
    axes = HIP_AXES[[0, 2]]
    assert hinge_angles(_chain(angles, axes), axes) == pytest.approx(angles, abs=1e-9)
    # a turn about an axis the chain lacks is left out: x then y hinges, wanted a turn about z
    about_z = quat_to_mat(quat_exp(np.array([[0.0, 0.0, 0.4]])))
    assert hinge_angles(about_z, axes) == pytest.approx(np.zeros((1, 2)), abs=1e-9)


# the CMU humanoid's humerus: hinges rz, ry, rx
ARM_AXES = np.array([[0, 0, 1.0], [0, 1.0, 0], [1.0, 0, 0]])
ARM_RANGES = np.radians([[-90.0, 90.0], [-90.0, 90.0], [-60.0, 90.0]])


def _turn_error_deg(angles, wanted):
    return np.degrees(quat_angle(mat_to_quat(_chain(angles, ARM_AXES)), mat_to_quat(wanted)))


def test_where_the_ranges_bind_the_nearest_turn_they_allow_is_found():
    # an arm swinging through its ranges and twisted 29-40° about itself beyond them, on about
    # half of the frames: clamping the exact angles there is far from the nearest allowed turn
    t = np.linspace(0.0, 2 * np.pi, 120)[:, None]
    inside = 0.8 * ARM_RANGES[:, 1] * np.sin(t + np.array([0.0, 1.0, 2.0]))
    twist = (0.6 + 0.1 * np.sin(2 * t)) * np.array([0.0, -1.0, 0.0])
    wanted = _chain(inside, ARM_AXES) @ quat_to_mat(quat_exp(twist))
    low, high = ARM_RANGES.T
    exact = hinge_angles(wanted, ARM_AXES)
    exact -= 2 * np.pi * np.round(exact / (2 * np.pi))
    out = np.any((exact < low) | (exact > high), axis=1)
    assert 0.3 < out.mean() < 0.7
    bounded = hinge_angles(wanted, ARM_AXES, ARM_RANGES)
    assert np.all((bounded >= low - 1e-12) & (bounded <= high + 1e-12))
    clamped = _turn_error_deg(np.clip(exact, low, high), wanted)[out]
    nearest = _turn_error_deg(bounded, wanted)[out]
    assert np.all(nearest <= clamped + 0.5) and np.median(nearest) < 0.7 * np.median(clamped)


def test_angles_whole_turns_away_come_back_into_their_ranges():
    angles = np.random.default_rng(3).uniform(-1.0, 1.0, (20, 3))
    wanted = _chain(angles + 2 * np.pi * np.array([1, -2, 3]), ARM_AXES)
    assert hinge_angles(wanted, ARM_AXES, ARM_RANGES) == pytest.approx(angles, abs=1e-9)


def test_a_hip_on_three_hinges_follows_the_clips_thigh(tmp_path):
    """The mapping names one hinge of each hip (as a user's file does, one MJCF joint per BVH
    joint); all three are set, so the thigh points where the clip's does (within 6°; one hinge
    alone left it 18-20° off at the median, 29° at worst)."""
    mapping = tmp_path / "map.yaml"
    mapping.write_text(
        "joints:\n  Hips: root\n"
        + "".join(
            f"  {bvh}UpLeg: {side}_hip_x\n  {bvh}Leg: {side}_knee\n  {bvh}Foot: {side}_ankle_y\n"
            for bvh, side in (("Left", "left"), ("Right", "right"))
        )
    )
    clip = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    model_path = DM_CONTROL / "suite" / "humanoid.xml"
    world = build_world(load_character(model_path, stiffness="auto"))
    chosen = load_mapping(mapping)
    poses = retarget(clip, world, chosen).qpos
    _, pos = global_transforms(clip)
    axes, names = clip_axes(chosen, clip, 1), [j.name for j in clip.joints]
    model, data = world.model, mujoco.MjData(world.model)
    worst = 0.0
    for frame in range(0, len(poses), 10):
        data.qpos[:] = poses[frame]
        mujoco.mj_kinematics(model, data)
        for bvh, side in (("Left", "left"), ("Right", "right")):
            thigh = (
                data.xpos[model.body(f"{side}_shin").id] - data.xpos[model.body(f"{side}_thigh").id]
            )
            knee, hip = names.index(f"{bvh}Leg"), names.index(f"{bvh}UpLeg")
            wanted = axes @ (pos[frame + 1, knee] - pos[frame + 1, hip])
            cos = thigh @ wanted / np.linalg.norm(thigh) / np.linalg.norm(wanted)
            worst = max(worst, float(np.degrees(np.arccos(np.clip(cos, -1, 1)))))
    assert worst < 6.0


def test_dm_control_humanoids_are_mapped_by_their_body_names():
    """The suite humanoid's `right_thigh` … and the CMU humanoid's ASF names (`lfemur`, `ltibia`,
    `lhumerus`, `lradius`, `thorax`) give each role its body's first joint."""
    from eigengait.motion.retarget import body_roles

    suite = DM_CONTROL / "suite"
    humanoid = body_roles(build_world(load_character(suite / "humanoid.xml", stiffness="auto")))
    assert {k: humanoid[k] for k in ("root", "left_thigh", "right_shin", "left_forearm")} == {
        "root": "root",
        "left_thigh": "left_hip_x",
        "right_shin": "right_knee",
        "left_forearm": "left_elbow",
    }
    cmu = body_roles(build_world(load_character(suite / "humanoid_CMU.xml")))
    assert {
        k: cmu[k] for k in ("torso", "left_thigh", "right_shin", "left_foot", "right_upper_arm")
    } == {
        "torso": "thoraxrz",
        "left_thigh": "lfemurrz",
        "right_shin": "rtibiarx",
        "left_foot": "lfootrz",
        "right_upper_arm": "rhumerusrz",
    }
