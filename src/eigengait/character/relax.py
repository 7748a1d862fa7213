"""Relax poses: the pose at which the springs rest, joint frames are measured and modes are
computed.

A relax pose is `default` (the MJCF as written), a preset named in the character's sidecar, or
per-joint rotations `{joint: rotation vector in degrees}` (joint frame; a hinge takes one angle
about its axis). Applying it rotates each joint's child body about the joint anchor, so the new pose
becomes the model's zero pose.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from eigengait.character.loader import Character
from eigengait.character.scene import compile_spec
from eigengait.errors import UserInputError
from eigengait.geometry import quat_exp

DEFAULT_POSE = "default"


def parse_relax_argument(text: str | None) -> str | dict[str, list[float]]:
    """`crouched` -> preset name; `left_thigh=0,-30,0;right_shin=45` -> per-joint rotations
    (degrees)."""
    if text is None or text.strip() == "":
        return DEFAULT_POSE
    if "=" not in text:
        return text.strip()
    rotations: dict[str, list[float]] = {}
    for item in filter(None, (s.strip() for s in text.split(";"))):
        joint, _, values = item.partition("=")
        try:
            rotations[joint.strip()] = [float(v) for v in values.split(",")]
            if not all(math.isfinite(v) and abs(v) <= 360 for v in rotations[joint.strip()]):
                raise ValueError
        except ValueError:
            raise UserInputError(
                f"cannot read rotation '{item}'",
                field="relax",
                fix="write JOINT=rx,ry,rz in degrees (finite, within ±360), items separated by ';'",
            ) from None
    return rotations


def pose_rotations(character: Character, pose: str | dict) -> dict[str, np.ndarray]:
    """Per-joint rotations in radians for a pose name or dict; validates names and sizes."""
    if isinstance(pose, str):
        if pose == DEFAULT_POSE:
            return {}
        presets = character.meta.relax_poses
        if pose not in presets:
            known = ", ".join([DEFAULT_POSE, *presets]) or DEFAULT_POSE
            raise UserInputError(
                f"unknown relax pose '{pose}'",
                file=character.path,
                field="relax_poses",
                fix=f"use one of: {known}, or JOINT=rx,ry,rz rotations",
            )
        pose = presets[pose]
    rotations = {}
    for joint, value in pose.items():
        if joint not in character.joint_dofs:
            raise UserInputError(
                f"relax pose names unknown joint '{joint}'",
                file=character.path,
                field="relax pose",
                fix=f"joints are: {', '.join(character.joints)}",
            )
        v = np.atleast_1d(np.asarray(value, dtype=float))
        if v.size != character.joint_dofs[joint]:
            raise UserInputError(
                f"joint '{joint}' needs {character.joint_dofs[joint]} rotation value(s), got "
                f"{v.size}",
                file=character.path,
                field="relax pose",
            )
        rotations[joint] = np.deg2rad(v)
    return rotations


def posed_spec(character: Character, pose: str | dict = DEFAULT_POSE) -> mujoco.MjSpec:
    """A fresh spec of the character whose zero pose is the given relax pose."""
    spec = character.raw_spec()
    rotations = pose_rotations(character, pose)
    if not rotations:
        return spec
    model = compile_spec(spec)
    for joint, rot in rotations.items():
        j = model.joint(joint).id
        b = int(model.jnt_bodyid[j])
        rotvec = rot * model.jnt_axis[j] if rot.size == 1 else rot
        q_rel = quat_exp(rotvec)
        anchor = model.jnt_pos[j]
        rotated_anchor = np.zeros(3)
        mujoco.mju_rotVecQuat(rotated_anchor, anchor, q_rel)
        offset = np.zeros(3)
        mujoco.mju_rotVecQuat(offset, anchor - rotated_anchor, model.body_quat[b])
        new_quat = np.zeros(4)
        mujoco.mju_mulQuat(new_quat, model.body_quat[b], q_rel)
        body = spec.body(model.body(b).name)
        body.pos = model.body_pos[b] + offset
        body.quat = new_quat
        body.alt.type = mujoco.mjtOrientation.mjORIENTATION_QUAT
    return spec
