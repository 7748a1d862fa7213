"""`--stiffness auto`: joint stiffness from the weight each joint carries (the sag rule).

A joint carries the part of the creature below it (its child's subtree, mass m in kg, COM c). Held
with that part horizontal, gravity pulls with torque m·g·r, r (m) the distance from the joint anchor
to c (for a hinge, measured perpendicular to its axis). The rule gives the joint the stiffness that
lets that torque sag it by `SAG_DEG`:

    k = m · g · r / θ_sag        (N·m/rad, every axis of a ball joint alike)

so a limb of length ℓ swings near f ≈ (1/2π)·√(g / (ℓ θ_sag)) whatever the creature's size. A joint
whose load has almost no lever (r → 0) would get no stiffness: every k is at least `FLOOR_FRACTION`
of the largest one.
"""

from __future__ import annotations

import mujoco
import numpy as np

SAG_DEG = 10.0
FLOOR_FRACTION = 0.01
GRAVITY = 9.81


def auto_stiffness(model: mujoco.MjModel, joints: list[str]) -> dict[str, float]:
    """Stiffness (N·m/rad) of each named joint of `model` at its zero pose, by the sag rule."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    k = {}
    for name in joints:
        j = model.joint(name).id
        b = int(model.jnt_bodyid[j])
        lever = data.subtree_com[b] - data.xanchor[j]
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE:
            axis = data.xaxis[j]
            lever = lever - (lever @ axis) * axis
        k[name] = (
            float(model.body_subtreemass[b])
            * GRAVITY
            * float(np.linalg.norm(lever))
            / np.deg2rad(SAG_DEG)
        )
    floor = FLOOR_FRACTION * max(k.values(), default=0.0)
    return {name: max(v, floor) for name, v in k.items()}
