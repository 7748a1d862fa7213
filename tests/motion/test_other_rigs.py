"""Skeletons from outside CMU: game-rig joint names, position channels on every joint, and a rest
pose that does not stand (every bone along its joint's x axis, as Bandai Namco's files lay it)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from eigengait.character import load_character
from eigengait.control.balance.reference import kinematic_replay
from eigengait.geometry import min_arc, quat_angle
from eigengait.motion.bvh import BvhClip, BvhJoint, global_transforms, local_transforms, read_bvh
from eigengait.motion.conventions import detect_conventions
from eigengait.errors import UserInputError
from eigengait.motion.retarget import Mapping, builtin_mapping, retarget
from eigengait.motion.skeleton_names import find_roles
from eigengait.sim.world import build_world
from shared_data import MOCAP

# the rig naming conventions of the module doc: left thigh, shin, foot and upper arm
RIGS = {
    "unity": ("UpperLeg_L", "LowerLeg_L", "Foot_L", "UpperArm_L"),
    "unreal": ("thigh_l", "calf_l", "foot_l", "upperarm_l"),
    "blender": ("thigh.L", "shin.L", "foot.L", "upper_arm.L"),
    "smpl": ("L_Hip", "L_Knee", "L_Ankle", "L_Shoulder"),
    "mixamo": ("mixamorig:LeftUpLeg", "mixamorig:LeftLeg", "mixamorig:LeftFoot", "LeftArm"),
}
# Bandai Namco's names for the CMU MotionBuilder skeleton's joints
BANDAI_NAMES = {
    "LeftUpLeg": "UpperLeg_L",
    "LeftLeg": "LowerLeg_L",
    "LeftFoot": "Foot_L",
    "LeftToeBase": "Toes_L",
    "RightUpLeg": "UpperLeg_R",
    "RightLeg": "LowerLeg_R",
    "RightFoot": "Foot_R",
    "RightToeBase": "Toes_R",
    "LeftShoulder": "Shoulder_L",
    "LeftArm": "UpperArm_L",
    "LeftForeArm": "LowerArm_L",
    "RightShoulder": "Shoulder_R",
    "RightArm": "UpperArm_R",
    "RightForeArm": "LowerArm_R",
    "Spine1": "Chest",
}


@pytest.fixture(scope="module")
def walk():
    return read_bvh(MOCAP / "cmu_02_01_walk.bvh")


@pytest.mark.parametrize("rig", sorted(RIGS))
def test_each_rigs_names_give_the_legs_and_arms(rig):
    left = RIGS[rig]
    right = tuple(
        n.replace("_L", "_R").replace("_l", "_r").replace(".L", ".R").replace("L_", "R_")
        for n in left
    )
    right = tuple(n.replace("Left", "Right") for n in right)
    names = ["Hips", "Spine", *left, *right, "L_Collar" if rig == "smpl" else "Shoulder_L"]
    clip = BvhClip(
        [BvhJoint(n, 0 if i else -1, np.zeros(3), []) for i, n in enumerate(names)],
        1 / 30,
        np.zeros((1, 0)),
    )
    roles = find_roles(clip)
    for side, joints in (("left", left), ("right", right)):
        found = [roles[f"{side}_{part}"] for part in ("thigh", "shin", "foot", "upper_arm")]
        assert found == list(joints)
    assert roles["root"] == "Hips" and roles["torso"] == "Spine"


def rerested(clip: BvhClip, names: dict[str, str], seed: int = 0) -> BvhClip:
    """The same motion on a skeleton whose rest pose lays every bone along its joint's x axis,
    twisted at random about it, with position channels on every joint (holding the bone, as
    Bandai Namco's files do) and joints renamed: world positions are unchanged."""
    rng = np.random.default_rng(seed)
    joints = clip.joints
    turns = []
    for i, joint in enumerate(joints):
        child = next((j for j in joints if j.parent == i), None)
        bone = child.offset if child is not None else joint.end_site
        twist = Rotation.from_rotvec([rng.uniform(-np.pi, np.pi), 0, 0]).as_matrix()
        lay = min_arc([1.0, 0, 0], bone) if np.linalg.norm(bone) > 1e-9 else np.eye(3)
        turns.append(lay @ twist)
    local_rot, local_pos = local_transforms(clip)
    new_joints, columns = [], []
    for i, joint in enumerate(joints):
        parent = turns[joint.parent] if joint.parent >= 0 else np.eye(3)
        rotation = parent.T @ local_rot[:, i] @ turns[i]
        columns += [local_pos[:, i] @ parent, Rotation.from_matrix(rotation).as_euler("ZXY", True)]
        end = None if joint.end_site is None else turns[i].T @ joint.end_site
        channels = ["Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation"]
        name = names.get(joint.name, joint.name)
        new_joints.append(BvhJoint(name, joint.parent, parent.T @ joint.offset, channels, end))
    return BvhClip(new_joints, clip.frame_time, np.hstack(columns))


def test_position_channels_hold_the_bone_and_the_rest_pose_lies_flat(walk):
    other = rerested(walk, BANDAI_NAMES)
    np.testing.assert_allclose(global_transforms(other)[1], global_transforms(walk)[1], atol=1e-9)
    rest = global_transforms(other.rest())[1][0]
    assert np.ptp(rest[:, 1:], axis=0).max() < np.ptp(rest[:, 0]) / 4  # mostly along x
    roles = find_roles(other)
    assert detect_conventions(walk, find_roles(walk)).rest_stands
    conv = detect_conventions(other, roles)
    assert not conv.rest_stands
    assert (conv.up, conv.forward, conv.unit) == ("+y", "+z", "CMU")


def test_a_rest_pose_that_does_not_stand_retargets_like_the_t_pose(walk):
    """The rest offsets taken from the motion agree with the T-pose's, an independent choice, to a
    few degrees on the root, torso and legs (the feet, levelled either way, to 15°)."""
    world = build_world(load_character("walker"))
    model = world.model
    original = retarget(walk, world, builtin_mapping("walker", walk)).qpos
    other = rerested(walk, BANDAI_NAMES)
    moved = retarget(other, world, builtin_mapping("walker", other)).qpos
    limits = {"torso": 8, "left_thigh": 8, "right_thigh": 8, "left_shin": 8, "right_shin": 8}
    limits |= {"left_foot": 15, "right_foot": 15}
    root = model.jnt_qposadr[0] + 3
    assert (
        np.degrees(quat_angle(original[:, root : root + 4], moved[:, root : root + 4])).mean() < 5
    )
    for name, limit in limits.items():
        adr = model.jnt_qposadr[model.joint(name).id]
        angle = np.degrees(quat_angle(original[:, adr : adr + 4], moved[:, adr : adr + 4]))
        assert angle.mean() < limit, name


def test_a_30_hz_clip_keeps_its_accelerations(walk):
    """The reference's rates are smoothed over a time, not a frame count: a 30 Hz copy of a 120 Hz
    walk keeps most of its COM acceleration (RMS 0.74 of the original's, whose own noise a 30 Hz
    clip cannot carry; smoothed over 5 of its frames, as the 120 Hz clip is, it kept 0.31)."""
    world = build_world(load_character("walker"))
    qpos = retarget(walk, world, builtin_mapping("walker", walk)).qpos[:240]
    fast = kinematic_replay(world, qpos, walk.frame_time)
    slow = kinematic_replay(world, qpos[::4], 4 * walk.frame_time)
    ratio = np.sqrt(np.mean(slow.com_acc**2)) / np.sqrt(np.mean(fast.com_acc**2))
    assert 0.6 < ratio < 1.2


def test_a_lying_rest_pose_needs_its_thighs_mapped(walk):
    world = build_world(load_character("walker"))
    other = rerested(walk, BANDAI_NAMES)
    joints = dict(builtin_mapping("walker", other).joints)
    del joints["UpperLeg_L"]
    with pytest.raises(UserInputError) as err:
        retarget(other, world, Mapping(joints=joints))
    assert "UpperLeg_L" in str(err.value) and "rest pose does not stand" in str(err.value)
    # without the torso mapped the root still stands up: the file's up is the character's
    joints = {k: v for k, v in builtin_mapping("walker", other).joints.items() if v != "torso"}
    moved = retarget(other, world, Mapping(joints=joints)).qpos
    original = retarget(walk, world, builtin_mapping("walker", walk)).qpos
    root = world.model.jnt_qposadr[0] + 3
    assert (
        np.degrees(quat_angle(original[:, root : root + 4], moved[:, root : root + 4])).mean() < 10
    )


def test_a_hinged_arm_points_where_the_clips_arm_does_without_a_standing_rest_pose(walk):
    """dm_control's CMU humanoid holds its arms out sideways in its zero pose, so the character's
    left, which fixes a bone's twist in offsets taken from the motion, lies along its upper arm and
    fixed nothing: its arm twisted at random, its three limited hinges were clamped and the arm
    pointed 57° from the clip's (median). Forward fixes that twist."""
    import mujoco

    from shared_data import DM_CONTROL

    world = build_world(load_character(DM_CONTROL / "suite/humanoid_CMU.xml", stiffness="auto"))
    model, data = world.model, mujoco.MjData(world.model)
    other = rerested(walk, BANDAI_NAMES, seed=1)
    mapping = builtin_mapping(world.character.name, other, world)
    qpos = retarget(other, world, mapping).qpos
    names = [j.name for j in other.joints]
    positions = global_transforms(other)[1][1:]
    to_world = np.array([[0, 0, 1.0], [1.0, 0, 0], [0, 1.0, 0]])  # the file's +Y up, +Z forward
    for side in ("L", "R"):
        upper, lower = names.index(f"UpperArm_{side}"), names.index(f"LowerArm_{side}")
        joints = [model.joint(mapping.joints[names[i]]).id for i in (upper, lower)]
        bodies = model.jnt_bodyid[joints]
        errors = []
        for frame in range(0, len(qpos), 20):
            data.qpos[:] = qpos[frame]
            mujoco.mj_kinematics(model, data)
            arm = data.xpos[bodies[1]] - data.xpos[bodies[0]]
            clip_arm = to_world @ (positions[frame, lower] - positions[frame, upper])
            cosine = arm @ clip_arm / np.linalg.norm(arm) / np.linalg.norm(clip_arm)
            errors.append(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))
        assert np.median(errors) < 8.0, side
