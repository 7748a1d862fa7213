"""Unit, up axis and facing detected on both CMU skeleton families, on a re-axed metre copy, and
joint roles by name."""

import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.motion.bvh import BvhClip, BvhJoint, read_bvh
from eigengait.motion.conventions import detect_conventions
from eigengait.motion.retarget import builtin_mapping, retarget
from eigengait.motion.skeleton_names import find_roles
from eigengait.sim.world import build_world
from shared_data import MOCAP

Z_UP = np.array([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])  # new = Z_UP @ old: old +Y → new +Z


@pytest.fixture(scope="module")
def walk():
    return read_bvh(MOCAP / "cmu_02_01_walk.bvh")


@pytest.fixture(scope="module")
def run():
    return read_bvh(MOCAP / "cmu_16_36_run_daz.bvh")


def test_motionbuilder_family(walk):
    roles = find_roles(walk)
    assert (
        roles["root"] == "Hips" and roles["torso"] == "Spine1" and roles["left_shin"] == "LeftLeg"
    )
    conv = detect_conventions(walk, roles)
    assert (conv.up, conv.forward, conv.unit) == ("+y", "+z", "CMU")
    assert conv.hip_height * conv.metres_per_unit == pytest.approx(0.93, abs=0.03)
    assert conv.rotation_orders == {"ZYX": 31}


def test_daz_family(run):
    roles = find_roles(run)
    assert (roles["root"], roles["torso"], roles["right_thigh"], roles["right_foot"]) == (
        "hip",
        "chest",
        "rThigh",
        "rFoot",
    )
    conv = detect_conventions(run, roles)
    assert (conv.up, conv.forward, conv.unit) == ("+y", "+z", "cm")
    assert conv.rotation_orders == {"ZXY": 42, "ZYX": 1}


def _reaxed(clip: BvhClip, matrix: np.ndarray, scale: float) -> BvhClip:
    """The same motion in other file axes (new = matrix @ old, a signed permutation) and length
    unit."""
    relabel = {}
    for old in range(3):
        new = int(np.flatnonzero(matrix[:, old])[0])
        relabel["XYZ"[old]] = ("XYZ"[new], matrix[new, old])
    joints, frames, column = [], clip.frames.copy(), 0
    for joint in clip.joints:
        channels = []
        for name in joint.channels:
            axis, sign = relabel[name[0]]
            channels.append(axis + name[1:])
            frames[:, column] *= sign * (scale if name.endswith("position") else 1.0)
            column += 1
        end = None if joint.end_site is None else scale * matrix @ joint.end_site
        joints.append(
            BvhJoint(joint.name, joint.parent, scale * matrix @ joint.offset, channels, end)
        )
    return BvhClip(joints, clip.frame_time, frames)


def test_z_up_metre_copy_is_detected_and_retargets_identically(run):
    other = _reaxed(run, Z_UP, 0.01)
    conv = detect_conventions(other, find_roles(other))
    assert (conv.up, conv.forward, conv.unit) == ("+z", "-y", "m")
    world = build_world(load_character("walker"))
    a = retarget(run, world, builtin_mapping("walker", run)).qpos
    b = retarget(other, world, builtin_mapping("walker", other)).qpos
    np.testing.assert_allclose(b, a, atol=1e-6)


def test_namespaced_common_names_map_like_the_originals(walk):
    renamed = BvhClip(
        [
            BvhJoint("mixamorig:" + j.name, j.parent, j.offset, j.channels, j.end_site)
            for j in walk.joints
        ],
        walk.frame_time,
        walk.frames,
    )
    original = builtin_mapping("walker", walk).joints
    mapped = builtin_mapping("walker", renamed).joints
    assert mapped == {"mixamorig:" + k: v for k, v in original.items()}
