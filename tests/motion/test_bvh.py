"""BVH reader/writer: round trips on the real CMU clips, channel orders, and clear errors for bad
files."""

import numpy as np
import pytest

from eigengait.errors import UserInputError
from eigengait.motion.bvh import (
    BvhClip,
    BvhJoint,
    axis_rotation,
    global_transforms,
    read_bvh,
    write_bvh,
)
from shared_data import MOCAP

CLIPS = {
    "cmu_02_01_walk.bvh": (31, 96, 344),
    "cmu_16_36_run_daz.bvh": (43, 132, 190),
    "cmu_13_14_stand_laugh_daz.bvh": (43, 132, 2425),
}


@pytest.mark.parametrize("name", sorted(CLIPS))
def test_round_trip_is_identical(name, tmp_path):
    clip = read_bvh(MOCAP / name)
    n_joints, n_channels, n_frames = CLIPS[name]
    assert (len(clip.joints), clip.frames.shape) == (n_joints, (n_frames, n_channels))
    write_bvh(clip, tmp_path / "again.bvh")
    again = read_bvh(tmp_path / "again.bvh")
    assert [j.name for j in again.joints] == [j.name for j in clip.joints]
    assert [j.parent for j in again.joints] == [j.parent for j in clip.joints]
    assert [j.channels for j in again.joints] == [j.channels for j in clip.joints]
    for a, b in zip(again.joints, clip.joints):
        np.testing.assert_allclose(a.offset, b.offset, atol=1e-6)
        assert (a.end_site is None) == (b.end_site is None)
        if a.end_site is not None:
            np.testing.assert_allclose(a.end_site, b.end_site, atol=1e-6)
    assert again.frame_time == pytest.approx(clip.frame_time, abs=1e-9)
    np.testing.assert_allclose(again.frames, clip.frames, atol=1e-6, rtol=1e-9)


def test_header_quirks_are_read():
    walk = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    assert walk.frame_time == pytest.approx(0.0083333)
    assert walk.joints[0].channels == [
        "Xposition",
        "Yposition",
        "Zposition",
        "Zrotation",
        "Yrotation",
        "Xrotation",
    ]
    assert sum(j.end_site is not None for j in walk.joints) == 7
    run = read_bvh(MOCAP / "cmu_16_36_run_daz.bvh")
    assert run.joints[1].channels == ["Zrotation", "Xrotation", "Yrotation"]
    assert sum(j.end_site is not None for j in run.joints) == 14
    # T-pose hip heights quoted in the data README (CMU units, centimetres).
    assert walk.frames[0, 1] == pytest.approx(16.70, abs=0.01)
    assert run.frames[0, 1] == pytest.approx(85.0, abs=0.05)


def _two_joint_clip(channels, values):
    joints = [
        BvhJoint("root", -1, np.zeros(3), ["Xposition", "Yposition", "Zposition"] + channels),
        BvhJoint("child", 0, np.array([0.0, 1.0, 0.0]), [], end_site=np.array([1.0, 0.0, 0.0])),
    ]
    return BvhClip(joints, 0.01, np.array([[0.0, 0.0, 0.0] + list(values)]))


def test_channel_order_is_intrinsic_product_in_listed_order():
    angles = [30.0, -50.0, 70.0]
    zxy = _two_joint_clip(["Zrotation", "Xrotation", "Yrotation"], angles)
    xyz = _two_joint_clip(["Xrotation", "Yrotation", "Zrotation"], angles)
    rot_zxy, pos_zxy = global_transforms(zxy)
    rot_xyz, _ = global_transforms(xyz)
    expected = axis_rotation("Z", 30.0) @ axis_rotation("X", -50.0) @ axis_rotation("Y", 70.0)
    np.testing.assert_allclose(rot_zxy[0, 0], expected, atol=1e-12)
    assert not np.allclose(rot_xyz[0, 0], expected, atol=1e-3)
    np.testing.assert_allclose(pos_zxy[0, 1], expected @ [0.0, 1.0, 0.0], atol=1e-12)


def test_single_axis_rotation_is_right_handed():
    np.testing.assert_allclose(
        axis_rotation("Z", 90.0) @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-12
    )
    np.testing.assert_allclose(
        axis_rotation("X", 90.0) @ [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], atol=1e-12
    )
    np.testing.assert_allclose(
        axis_rotation("Y", 90.0) @ [0.0, 0.0, 1.0], [1.0, 0.0, 0.0], atol=1e-12
    )


def test_walk_feet_stay_below_hips():
    walk = read_bvh(MOCAP / "cmu_02_01_walk.bvh")
    _, pos = global_transforms(walk)
    hips, foot = walk.joint_index("Hips"), walk.joint_index("LeftFoot")
    assert np.all(pos[:, foot, 1] < pos[:, hips, 1] - 10.0)
    travel = pos[-1, hips] - pos[1, hips]
    assert travel[2] > 50.0 and abs(travel[0]) < 10.0  # about 59.6 units along +Z


def _truncate(tmp_path, keep_lines):
    lines = (MOCAP / "cmu_02_01_walk.bvh").read_text().splitlines()
    bad = tmp_path / "bad.bvh"
    bad.write_text("\n".join(lines[:keep_lines]) + "\n")
    return bad


def test_truncated_motion_names_the_line(tmp_path):
    bad = _truncate(tmp_path, 200)
    with pytest.raises(UserInputError) as info:
        read_bvh(bad)
    assert "344 frames" in str(info.value) and "line 200" in str(info.value)


def test_truncated_hierarchy_and_cut_last_line(tmp_path):
    with pytest.raises(UserInputError, match="MOTION"):
        read_bvh(_truncate(tmp_path, 40))
    lines = (MOCAP / "cmu_02_01_walk.bvh").read_text().splitlines()
    cut = tmp_path / "cut.bvh"
    cut.write_text("\n".join(lines[:-1] + [" ".join(lines[-1].split()[:50])]) + "\n")
    with pytest.raises(UserInputError) as info:
        read_bvh(cut)
    assert f"line {len(lines)}" in str(info.value) and "50 values" in str(info.value)


@pytest.mark.parametrize(
    "text, fragment",
    [
        (
            "HIERARCHY\nROOT a\n{\nOFFSET 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 1\nFrame "
            "Time: 0.1\n0\n",
            "number",
        ),
        (
            "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Wrotation\n}\nMOTION\nFrames: 1\nFrame "
            "Time: 0.1\n0\n",
            "Wrotation",
        ),
        (
            "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: x\nFrame "
            "Time: 0.1\n0\n",
            "integer",
        ),
        (
            "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 1\nFrame "
            "Time: 0.1\nabc\n",
            "not a number",
        ),
        ("hello\n", "MOTION"),
    ],
)
def test_malformed_files_raise_one_clear_error(tmp_path, text, fragment):
    bad = tmp_path / "bad.bvh"
    bad.write_text(text)
    with pytest.raises(UserInputError, match=fragment):
        read_bvh(bad)
