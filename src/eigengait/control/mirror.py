"""Left/right mirroring through the character's sagittal plane (normal = the mirror axis, y by
default).

Assumes the relax pose is symmetric and paired bodies have mirror-image frames (true for the
built-ins, whose body frames are aligned with the world at the relax pose). Under a reflection S
(det −1), positions and linear velocities map as S v; rotations, angular velocities and joint
torques are axial vectors and map as −S v.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.errors import UserInputError
from eigengait.sim.world import World


class Mirror:
    """Mirror maps for a world: internal dof vectors (torques, joint velocities) and full states."""

    def __init__(self, world: World):
        mirror = world.character.meta.mirror
        if mirror is None:
            raise UserInputError(
                "the character has no mirror map, so it cannot be symmetric",
                file=world.character.path,
                field="mirror",
                fix="add mirror: {axis: y, pairs: {...}} to the sidecar, or set symmetric: false",
            )
        self.world = world
        axis = "xyz".index(mirror.axis)
        self.S = np.eye(3)
        self.S[axis, axis] = -1
        pairs = dict(mirror.pairs)
        pairs.update({b: a for a, b in mirror.pairs.items()})
        model = world.model
        index, sign = [], []
        for name in world.character.joints:
            other = pairs.get(name, name)
            j, jo = model.joint(name).id, model.joint(other).id
            if world.character.joint_dofs[name] == 3:
                index += list(model.jnt_dofadr[jo] + np.arange(3))
                sign += list(-np.diag(self.S))
            else:  # hinge: torque about axis a maps to −S a, projected on the partner's axis
                index.append(model.jnt_dofadr[jo])
                sign.append(float(-self.S @ model.jnt_axis[j] @ model.jnt_axis[jo]))
        # internal dof k (in world.internal_qvel order) receives sign * value of the partner dof
        pos = {int(d): i for i, d in enumerate(world.internal_qvel)}
        self.partner = np.array([pos[int(d)] for d in index])
        # per joint: (qpos address, partner's qpos address, ball?, hinge sign)
        self.joint_maps = []
        for name in world.character.joints:
            j, jo = model.joint(name).id, model.joint(pairs.get(name, name)).id
            ball = model.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL
            s = 1.0 if ball else float(-self.S @ model.jnt_axis[j] @ model.jnt_axis[jo])
            self.joint_maps.append((int(model.jnt_qposadr[j]), int(model.jnt_qposadr[jo]), ball, s))
        # a planar root (slides along x/z, hinge about y) lies in the mirror plane: mirroring leaves
        # it unchanged
        self.root_qpos = world.root.forward_qpos if world.root.kind == "free" else None
        self.root_qvel = world.root.forward_qvel
        self.sign = np.array(sign)
        self.S_quat_axis = -np.diag(self.S)

    def dofs(self, v: np.ndarray) -> np.ndarray:
        """Mirror internal-dof vectors (last axis: n_internal), e.g. torques or joint velocities."""
        out = np.empty_like(v)
        out[..., self.partner] = v * self.sign
        return out

    def _quat(self, q: np.ndarray) -> np.ndarray:
        return np.r_[q[0], q[1:] * self.S_quat_axis]

    def state(self, qpos: np.ndarray, qvel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Mirror a full state (free root + ball/hinge joints)."""
        qp, qv = qpos.copy(), qvel.copy()
        a, d = self.root_qpos, self.root_qvel
        if a is not None:
            qp[a : a + 3] = self.S @ qpos[a : a + 3]
            qp[a + 3 : a + 7] = self._quat(qpos[a + 3 : a + 7])
            qv[d : d + 3] = self.S @ qvel[d : d + 3]
            qv[d + 3 : d + 6] = -self.S @ qvel[d + 3 : d + 6]
        qv[self.world.internal_qvel] = self.dofs(qvel[self.world.internal_qvel])
        for adr, partner, ball, sign in self.joint_maps:
            if ball:
                qp[partner : partner + 4] = self._quat(qpos[adr : adr + 4])
            else:
                qp[partner] = sign * qpos[adr]
        return qp, qv
