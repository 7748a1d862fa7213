"""Exported BVH read back by a small reader written here from the format's description (not
eigengait's own), and, where Debian's Blender is installed, imported by Blender."""

import shutil
import subprocess

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.motion.bvh_export import write_trajectory_bvh
from eigengait.sim.world import build_world

SOURCE_FPS = 1 / (33 * 0.0005)  # 60.606…: what a rounded stride of the physics step gives
FPS = 60.0


def read(path):
    """(joints, frame_time, frames): joints as dicts name/parent/offset/channels/end (end-site
    offset or None)."""
    tokens = path.read_text().split()
    joints, stack, i = [], [], 1
    while tokens[i] != "MOTION":
        word = tokens[i]
        if word in ("ROOT", "JOINT"):
            joints.append(
                {"name": tokens[i + 1], "parent": stack[-1] if stack else -1, "end": None}
            )
            i += 2
        elif word == "End":
            joints[stack[-1]]["end"] = np.array(tokens[i + 4 : i + 7], float)
            i += 8
        elif word == "{":
            stack.append(len(joints) - 1)
            i += 1
        elif word == "}":
            stack.pop()
            i += 1
        elif word == "OFFSET":
            joints[-1]["offset"] = np.array(tokens[i + 1 : i + 4], float)
            i += 4
        elif word == "CHANNELS":
            n = int(tokens[i + 1])
            joints[-1]["channels"] = tokens[i + 2 : i + 2 + n]
            i += 2 + n
        else:
            raise AssertionError(f"unexpected token {word}")
    count, frame_time = int(tokens[i + 2]), float(tokens[i + 5])
    frames = np.array(tokens[i + 6 :], float).reshape(count, -1)
    return joints, frame_time, frames


def axis(name, degrees):
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    return {
        "X": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
        "Y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
        "Z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]),
    }[name]


def end_sites(joints, row):
    """World positions of every end site in one frame (channels applied in the order listed)."""
    world, column, ends = [], 0, {}
    for j in joints:
        rotation, offset = np.eye(3), j["offset"].copy()
        for channel in j["channels"]:
            if channel.endswith("position"):
                offset["XYZ".index(channel[0])] = row[column]
            else:
                rotation = rotation @ axis(channel[0], row[column])
            column += 1
        if j["parent"] < 0:
            world.append((rotation, offset))
        else:
            parent_rot, parent_pos = world[j["parent"]]
            world.append((parent_rot @ rotation, parent_pos + parent_rot @ offset))
        if j["end"] is not None:
            ends[j["name"]] = world[-1][1] + world[-1][0] @ j["end"]
    return ends


@pytest.fixture(scope="module")
def running_poses():
    """The humanoid, travelling 1 m/s forward for 1 s while its left thigh swings (qpos at
    SOURCE_FPS)."""
    world = build_world(load_character("humanoid"))
    model = world.model
    t = np.arange(62) / SOURCE_FPS  # 0 … 1.0065 s
    qpos = np.repeat(model.qpos0[None], len(t), axis=0)
    qpos[:, 0] += t
    thigh = model.jnt_qposadr[model.joint("left_thigh").id]
    angle = 0.4 * np.sin(2 * np.pi * t)
    qpos[:, thigh : thigh + 4] = np.c_[
        np.cos(angle / 2), np.zeros_like(t), np.sin(angle / 2), np.zeros_like(t)
    ]
    return world, qpos


@pytest.mark.parametrize("units, scale", [("m", 1.0), ("cm", 100.0)])
def test_bvh_frame_time_bones_feet_and_hip_height(tmp_path, running_poses, units, scale):
    world, qpos = running_poses
    model = world.model
    path = tmp_path / "run.bvh"
    write_trajectory_bvh(world, qpos, SOURCE_FPS, path, fps=FPS, units=units)
    joints, frame_time, frames = read(path)

    assert frame_time == pytest.approx(1 / FPS, rel=1e-9)
    assert len(frames) == 61  # 0 … 1.0 s at exactly 60 frames/s
    assert len(joints) == (model.nbody - 1) + 2  # every body, plus a foot per leg
    assert frames.shape[1] == sum(len(j["channels"]) for j in joints)

    data = mujoco.MjData(model)
    for k in (0, 30, 60):  # frame k is at k/60 s
        data.qpos[:] = qpos[0]
        data.qpos[0] = model.qpos0[0] + k / FPS  # root travel is kept
        mujoco.mj_kinematics(model, data)
        pelvis = data.xpos[world.root_body]
        assert frames[k, 0] / scale == pytest.approx(pelvis[0], abs=1e-6)  # BVH x = forward
        assert frames[k, 1] / scale == pytest.approx(pelvis[2], abs=1e-6)  # BVH y = hip height, m
    assert 0.8 < frames[0, 1] / scale < 1.2

    ends = end_sites(joints, frames[0])
    data.qpos[:] = qpos[0]
    mujoco.mj_kinematics(model, data)
    for foot in ("left", "right"):
        toe = data.site_xpos[model.site(f"{foot}_toe").id]
        heel = data.site_xpos[model.site(f"{foot}_heel").id]
        np.testing.assert_allclose(
            ends[f"{foot}_foot"] / scale, [toe[0], toe[2], -toe[1]], atol=1e-6
        )
        foot_joint = next(j for j in joints if j["name"] == f"{foot}_foot")
        along = toe - heel  # the foot's direction, relax pose
        np.testing.assert_allclose(
            foot_joint["end"] / scale, [along[0], along[2], -along[1]], atol=1e-6
        )
        assert along[0] > 0.1 and abs(along[2]) < 0.01  # pointing forward along the floor


BLENDER_SCRIPT = """
import sys, bpy
from bpy_extras import io_utils
import builtins
_open = builtins.open
builtins.open = lambda f, mode='r', *a, **k: _open(f, mode.replace('U', ''), *a, **k)   # Blender 3.4 opens 'rU'
path = sys.argv[sys.argv.index('--') + 1]
bpy.ops.import_anim.bvh(filepath=path)
arm = next(o for o in bpy.context.scene.objects if o.type == 'ARMATURE')
print('BONES', len(arm.data.bones), 'FPS', bpy.context.scene.render.fps / bpy.context.scene.render.fps_base)
print('HEIGHT', max(v[2] for v in [arm.matrix_world @ b.head_local for b in arm.data.bones]))
"""  # noqa: E501


@pytest.mark.skipif(shutil.which("blender") is None, reason="Debian's blender is not installed")
def test_blender_imports_the_bvh_life_size(tmp_path, running_poses):
    world, qpos = running_poses
    path = tmp_path / "run.bvh"
    write_trajectory_bvh(world, qpos, SOURCE_FPS, path, fps=FPS, units="m")
    script = tmp_path / "import.py"
    script.write_text(BLENDER_SCRIPT)
    run = subprocess.run(
        ["blender", "--background", "--factory-startup", "--python", str(script), "--", str(path)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    lines = {
        line.split()[0]: line.split()[1:]
        for line in run.stdout.splitlines()
        if line[:5] in ("BONES", "HEIGH")
    }
    assert int(lines["BONES"][0]) == world.model.nbody - 1 + 2
    assert 1.0 < float(lines["HEIGHT"][0]) < 2.0  # metres: a life-size humanoid
