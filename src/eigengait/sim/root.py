"""Where the creature's root lives in the state: a free joint, or a planar root's slide and hinge
joints.

Frames: world axes, x forward, z up. A free root has position (x, y, z) and orientation quaternion
in qpos, linear velocity (world) and angular velocity (root frame) in qvel. Its uprightness,
heading, pitch and roll are read from its turn away from its orientation in the model's zero pose
(`upright_quat`): a model whose root frame is not z-up there (dm_control's CMU humanoid turns its
root 90° about x) stands upright in that pose, as every other model does. A planar root
(e.g. slide x, slide z, hinge y) has one qpos/qvel entry per joint; its forward, vertical and pitch
coordinates are the joints whose axis is x, z and ±y.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from eigengait.errors import UserInputError
from eigengait.geometry import quat_conj, quat_mul, quat_pitch_roll

AXIS_TOLERANCE = 0.99  # |cos| between a joint axis and a world axis to count as that axis


@dataclass(frozen=True)
class RootLayout:
    """Addresses of the root coordinates. For a planar root, absent coordinates are None."""

    kind: str  # "free" or "planar"
    translation_qvel: tuple[int, ...]  # qvel entries of the root's translation
    forward_qpos: int | None  # root x position (m)
    forward_qvel: int | None  # root x velocity (m/s)
    height_qpos: int | None  # root z position (m)
    vertical_qvel: int | None  # root z velocity (m/s)
    quat_qpos: int | None = None  # free root: orientation quaternion (w, x, y, z)
    pitch_qpos: int | None = None  # planar root: hinge about ±y (rad)
    pitch_sign: float = 1.0  # +1 if that hinge's axis is +y
    # free root: its orientation (w, x, y, z) in the zero pose (qpos0), upright by definition
    rest_quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)

    def upright_quat(self, qpos: np.ndarray) -> np.ndarray:
        """A free root's turn (…, 4; w, x, y, z; world frame) from its zero-pose orientation:
        q ⊗ q_rest⁻¹, the identity when it stands as in the model's zero pose."""
        q = qpos[..., self.quat_qpos : self.quat_qpos + 4]
        if self.rest_quat == (1.0, 0.0, 0.0, 0.0):
            return q
        return quat_mul(q, quat_conj(np.array(self.rest_quat)))

    def lift_and_pitch(self, qpos: np.ndarray, height: float, pitch: float) -> None:
        """Raise the root by `height` (m) and pitch it by `pitch` (rad, about world +y), in
        place."""
        if self.height_qpos is not None:
            qpos[self.height_qpos] += height
        if self.quat_qpos is not None:
            q, turn, out = qpos[self.quat_qpos : self.quat_qpos + 4], np.zeros(4), np.zeros(4)
            mujoco.mju_axisAngle2Quat(turn, np.array([0.0, 1.0, 0.0]), pitch)
            mujoco.mju_mulQuat(out, turn, q)
            qpos[self.quat_qpos : self.quat_qpos + 4] = out
        elif self.pitch_qpos is not None:
            qpos[self.pitch_qpos] += self.pitch_sign * pitch

    def position(self, qpos: np.ndarray) -> np.ndarray:
        """World position (…, 3) of the root for qpos rows (…, nq); a planar root's missing axes
        read 0."""
        if self.quat_qpos is not None:
            return qpos[..., self.quat_qpos - 3 : self.quat_qpos]
        out = np.zeros(qpos.shape[:-1] + (3,))
        for axis, adr in ((0, self.forward_qpos), (2, self.height_qpos)):
            if adr is not None:
                out[..., axis] = qpos[..., adr]
        return out

    def heading(self, qpos: np.ndarray) -> np.ndarray:
        """Yaw (rad, about world z) of the root's x axis for qpos rows (…, nq); a planar root
        reads 0."""
        if self.quat_qpos is None:
            return np.zeros(qpos.shape[:-1])
        w, x, y, z = np.moveaxis(self.upright_quat(qpos), -1, 0)
        return np.arctan2(2 * (x * y + w * z), 1 - 2 * (y * y + z * z))

    def up_z(self, qpos: np.ndarray) -> np.ndarray:
        """World z of the root's up axis for qpos rows (…, nq): 1 upright, < 0 upside down."""
        if self.quat_qpos is not None:
            q = self.upright_quat(qpos)
            return 1 - 2 * (q[..., 1] ** 2 + q[..., 2] ** 2)
        if self.pitch_qpos is not None:
            return np.cos(qpos[..., self.pitch_qpos])
        return np.ones(qpos.shape[:-1])

    def tilt_deg(self, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pitch and roll (degrees) of the root for qpos rows (…, nq), independent of the heading.

        A free root: `geometry.quat_pitch_roll` of its quaternion. A planar root: its hinge about ±y
        as pitch (same sign convention) and roll 0. NaN for a planar root without that hinge.
        """
        if self.quat_qpos is not None:
            pitch, roll = quat_pitch_roll(self.upright_quat(qpos))
            return np.degrees(pitch), np.degrees(roll)
        if self.pitch_qpos is not None:
            return np.degrees(self.pitch_sign * qpos[..., self.pitch_qpos]), np.zeros(
                qpos.shape[:-1]
            )
        return np.full(qpos.shape[:-1], np.nan), np.full(qpos.shape[:-1], np.nan)


def root_layout(model: mujoco.MjModel, root_body: int) -> RootLayout:
    """The layout of the root joints of body `root_body`."""
    joints = [j for j in range(model.njnt) if model.jnt_bodyid[j] == root_body]
    if len(joints) == 1 and model.jnt_type[joints[0]] == mujoco.mjtJoint.mjJNT_FREE:
        a, d = int(model.jnt_qposadr[joints[0]]), int(model.jnt_dofadr[joints[0]])
        rest = model.qpos0[a + 3 : a + 7] / np.linalg.norm(model.qpos0[a + 3 : a + 7])
        return RootLayout(
            "free",
            (d, d + 1, d + 2),
            a,
            d,
            a + 2,
            d + 2,
            quat_qpos=a + 3,
            rest_quat=tuple(float(c) for c in rest),
        )
    found: dict[str, tuple[int, int, float]] = {}
    translation = []
    for j in joints:
        axis, a, d = model.jnt_axis[j], int(model.jnt_qposadr[j]), int(model.jnt_dofadr[j])
        slide = model.jnt_type[j] == mujoco.mjtJoint.mjJNT_SLIDE
        if slide:
            translation.append(d)
        for name, world_axis in (("x", 0), ("y", 1), ("z", 2)):
            if abs(axis[world_axis]) >= AXIS_TOLERANCE:
                found[("slide_" if slide else "hinge_") + name] = (
                    a,
                    d,
                    float(np.sign(axis[world_axis])),
                )
    none = (None, None, 1.0)
    fx, fz, hy = (found.get(key, none) for key in ("slide_x", "slide_z", "hinge_y"))
    return RootLayout(
        "planar", tuple(translation), fx[0], fx[1], fz[0], fz[1], pitch_qpos=hy[0], pitch_sign=hy[2]
    )


def require_free_root(model: mujoco.MjModel, root_body: int, source: str, command: str) -> None:
    """Refuse, with one error naming the model and its root, a creature whose root is not a free
    joint (a planar model's root slides in x and z and turns about y): `command` balances and
    tracks in three dimensions."""
    if root_layout(model, root_body).kind == "free":
        return
    joints = [model.joint(j).name or str(j) for j in range(model.njnt)]
    joints = [n for j, n in enumerate(joints) if model.jnt_bodyid[j] == root_body]
    raise UserInputError(
        f"`{command}` needs a creature with a free-floating root; the root body "
        f"'{model.body(root_body).name}' moves on the joints {', '.join(joints) or '(none)'} "
        "(a planar model, or one fixed to the world).",
        file=source,
        field=f"body '{model.body(root_body).name}'",
        fix="give the root body a <freejoint/>; planar creatures take `modes`, `optimize` and "
        "`play`.",
    )
