"""Retargeting the CMU clips onto the humanoid, the kinematic reference, and a short closed-loop
tracking run."""

import re

import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.control.balance.reference import kinematic_replay
from eigengait.control.balance.tracker import IMPRATIO, Tracker, TrackerSettings, track
from eigengait.errors import UserInputError
from eigengait.motion.bvh import BvhClip, BvhJoint, read_bvh, write_bvh
from eigengait.motion.retarget import builtin_mapping, load_mapping, retarget
from eigengait.motion.tracking import run_track
from eigengait.sim.world import build_world
from shared_data import MOCAP


@pytest.fixture(scope="module")
def world():
    return build_world(load_character("humanoid"))


@pytest.fixture(scope="module")
def walk(world):
    clip = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    poses = retarget(clip, world, builtin_mapping("humanoid", clip))
    return poses, kinematic_replay(world, poses.qpos, poses.frame_time)


def test_walk_is_upright_forward_and_on_the_floor(walk):
    poses, ref = walk
    assert poses.scale == pytest.approx(0.0564, rel=0.1)  # the CMU unit is 0.0564 m
    travel = ref.com[-1] - ref.com[0]
    assert 3.0 < travel[0] < 4.0 and abs(travel[1]) < 0.3  # about 3.4 m along +x
    assert np.all((ref.com[:, 2] > 0.8) & (ref.com[:, 2] < 1.1))
    speed = np.linalg.norm(ref.com_vel[:, :2], axis=1).mean()
    assert 1.0 < speed < 1.4  # 1.1–1.2 m/s per the data notes
    assert 0.45 < ref.foot_contact.mean() < 0.85  # each foot stands most of the time, not always
    # walking: (almost) never both feet in the air
    assert ref.foot_contact.any(axis=1).mean() > 0.95


def test_daz_run_maps_and_has_flight(world):
    clip = read_bvh(MOCAP / "cmu_16_36_run_daz.bvh")
    poses = retarget(clip, world, builtin_mapping("humanoid", clip))
    ref = kinematic_replay(world, poses.qpos, poses.frame_time)
    speed = (ref.com[-1, 0] - ref.com[0, 0]) / ref.duration
    assert 2.0 < speed < 3.2
    assert not np.all(ref.foot_contact.any(axis=1))


def test_unmappable_skeleton_and_bad_mapping_files(world, tmp_path):
    clip = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    clip.joints[clip.joint_index("LeftUpLeg")].name = "Thigh_L_01"
    with pytest.raises(UserInputError, match="matches no mapping.*lacks left_thigh"):
        builtin_mapping("humanoid", clip)
    bad = tmp_path / "map.yaml"
    bad.write_text("joints: {Hips: root}\naxes: {x: +z, y: +x, z: -y}\n")
    with pytest.raises(UserInputError, match="right-handed"):
        load_mapping(bad)
    bad.write_text("joints: {Hips: root, LeftUpLeg: tail}\n")
    with pytest.raises(UserInputError, match="tail"):
        retarget(read_bvh(MOCAP / "cmu_02_01_walk.bvh"), world, load_mapping(bad))


def test_mapping_file_drives_the_same_pose_as_the_builtin(world, tmp_path, walk):
    clip = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    text = "joints:\n" + "".join(
        f"  {b}: {m}\n" for b, m in builtin_mapping("humanoid", clip).joints.items()
    )
    (tmp_path / "map.yaml").write_text(text)
    poses = retarget(clip, world, load_mapping(tmp_path / "map.yaml"))
    np.testing.assert_allclose(poses.qpos, walk[0].qpos)


def test_short_tracking_run_follows_the_clip(world, walk):
    _, ref = walk
    full = track(world, ref, 1.0, duration_s=0.5)
    free = track(world, ref, 0.0, duration_s=0.5)
    assert not full.fell and full.duration_s == pytest.approx(0.5, abs=0.01)
    assert full.joint_rms_deg < 20.0 and full.com_error_m < 0.2
    assert free.artificial_torque == 0.0 and full.artificial_torque > 0.0


@pytest.fixture(scope="module")
def walker_walk():
    world = build_world(load_character("walker"))
    clip = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    poses = retarget(clip, world, builtin_mapping("walker", clip))
    return world, kinematic_replay(world, poses.qpos, poses.frame_time)


def test_walker_has_ankles_and_its_reference_walks(walker_walk):
    world, ref = walker_walk
    assert world.nmotor == 36 and {"left_foot", "right_foot"} <= set(world.character.joints)
    travel = ref.com[-1] - ref.com[0]
    assert 3.0 < travel[0] < 4.0 and abs(travel[1]) < 0.3
    assert ref.foot_contact.any(axis=1).mean() > 0.95
    # the momentum rates are derivatives of the momenta
    np.testing.assert_allclose(
        ref.com_acc[100:200].mean(0) * ref.frame_time * 100,
        ref.com_vel[200] - ref.com_vel[100],
        atol=0.2,
    )


def test_walker_tracks_the_first_second_of_the_cmu_walk_at_moderate_robustness(walker_walk):
    # The momentum controller (the qp one: test_whole_body.py). Measured: COM error 0.010 m, joint
    # RMS 2.0°, mean artificial torque 47 N·m (robustness 0.5, 1 s; before the feet got soles,
    # support-limited ankle torques, stance ankles, load sharing and mass-scaled gains: 0.084 m).
    world, ref = walker_walk
    res = track(world, ref, 0.5, TrackerSettings(controller="momentum"), duration_s=1.0)
    assert not res.fell and res.duration_s == pytest.approx(1.0, abs=0.01)
    assert res.com_error_m < 0.03 and res.joint_rms_deg < 4.0
    assert 0.0 < res.artificial_torque < 80.0


def _other_side(name: str) -> str:
    """A joint name with its side swapped: Left/Right, left/right, or an l/r prefix (lThigh)."""
    for a, b in (("Left", "Right"), ("left", "right")):
        if a in name or b in name:
            return name.replace(a, "\0").replace(b, a).replace("\0", b)
    side = re.match(r"^([lrLR])(?=[A-Z])", name)
    return {"l": "r", "r": "l", "L": "R", "R": "L"}[side.group(1)] + name[1:] if side else name


def _mirrored(clip: BvhClip) -> BvhClip:
    """The clip mirrored across its file x axis (the CMU clips' lateral axis): sides swapped, x
    offsets and positions negated, rotations about y and z negated (M R M with M = diag(−1, 1, 1)
    turns each elementary rotation so)."""
    frames, joints, flip = clip.frames.copy(), [], np.array([-1.0, 1.0, 1.0])
    for joint, columns in zip(clip.joints, clip.channel_slices()):
        for k, channel in enumerate(joint.channels):
            if channel in ("Xposition", "Yrotation", "Zrotation"):
                frames[:, columns.start + k] *= -1
        end = None if joint.end_site is None else joint.end_site * flip
        joints.append(
            BvhJoint(
                _other_side(joint.name), joint.parent, joint.offset * flip, joint.channels, end
            )
        )
    return BvhClip(joints, clip.frame_time, frames)


def test_a_mirrored_clip_is_tracked_as_the_mirror_image(tmp_path):
    """Nothing in retargeting, foot cleanup or the controller favours one side: the Daz walk's first
    second mirrored left to right is tracked as the mirror image of the walk (to rounding: the
    physics is chaotic over seconds, not over one)."""
    clip = read_bvh(MOCAP / "cmu_05_01_walk_daz.bvh")
    first_second = BvhClip(
        clip.joints, clip.frame_time, clip.frames[: int(round(1.0 / clip.frame_time)) + 2]
    )
    runs = []
    for name, version in (("walk", first_second), ("mirrored", _mirrored(first_second))):
        write_bvh(version, tmp_path / f"{name}.bvh")
        runs.append(run_track(tmp_path / f"{name}.bvh", "walker", 0.5, None, None, 1, 0.0))
    (_, reference, walked), (_, mirror_reference, mirrored) = runs
    np.testing.assert_allclose(mirror_reference.qpos[:, 0], reference.qpos[:, 0], atol=1e-9)
    np.testing.assert_allclose(mirror_reference.qpos[:, 1], -reference.qpos[:, 1], atol=1e-9)
    assert np.ptp(reference.qpos[:, 1]) > 0.02  # the walk sways: the check can see a side
    assert not walked.fell and not mirrored.fell
    np.testing.assert_allclose(mirrored.qpos[:, 0], walked.qpos[:, 0], atol=1e-6)
    np.testing.assert_allclose(mirrored.qpos[:, 1], -walked.qpos[:, 1], atol=1e-6)
    assert mirrored.joint_rms_deg == pytest.approx(walked.joint_rms_deg, abs=1e-3)


def test_the_tracker_hardens_friction_on_its_own_copy_of_the_model(walker_walk):
    """The tracker's model has friction IMPRATIO times as hard as its normal contact (the walks'
    skate, docs/balance.md); the world the caller shares keeps its own."""
    world, ref = walker_walk
    before = world.model.opt.impratio
    tracker = Tracker(world, ref, 0.5)
    assert tracker.model.opt.impratio == IMPRATIO > 1.0
    assert world.model.opt.impratio == before == 1.0
