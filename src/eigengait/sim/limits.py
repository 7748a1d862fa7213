"""Poses the simulation can start from. Joint ranges: a pose outside a limited joint's range starts
inside a violated limit constraint, whose restoring force can launch the body in a few steps (a user
model's ankle at 64° against a 55° limit spun to 500 rad/s within 3 ms). The floor: a pose that
starts inside it is launched out."""

from __future__ import annotations

import mujoco
import numpy as np

ONE_DOF = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))


def clip_to_joint_ranges(model: mujoco.MjModel, qpos: np.ndarray) -> None:
    """Clip every limited hinge and slide joint of `qpos` (rad or m) into its range, in place; ball
    joints are left as they are (their range bounds a rotation angle, not a coordinate)."""
    for j in np.flatnonzero(model.jnt_limited):
        if int(model.jnt_type[j]) in ONE_DOF:
            a = model.jnt_qposadr[j]
            qpos[a] = np.clip(qpos[a], *model.jnt_range[j])


def floor_penetration(model: mujoco.MjModel, qpos: np.ndarray, floor_geom: int) -> float:
    """How deep (m, ≥ 0) the pose `qpos` sinks its deepest geom into the floor geom: the most
    negative distance of the floor's contacts. A pose that starts inside the floor is pushed out by
    the contact's spring within a few milliseconds, a launch that no torque paid for."""
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(model, data)
    mujoco.mj_collision(model, data)
    depths = [-float(c.dist) for c in data.contact[: data.ncon] if floor_geom in (c.geom1, c.geom2)]
    return max([0.0, *depths])
