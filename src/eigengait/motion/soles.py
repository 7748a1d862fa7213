"""Sole points of a character's feet along a pose sequence: the bottom of each foot contact sphere
(world, m)."""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.sim.world import World


def sole_points(world: World, qpos: np.ndarray) -> dict[str, np.ndarray]:
    """Per foot (F, k, 3): each contact sphere's centre lowered by its radius, for poses qpos
    (F, nq)."""
    model, data = world.model, mujoco.MjData(world.model)
    out = {foot: np.zeros((len(qpos), len(geoms), 3)) for foot, geoms in world.foot_spheres.items()}
    for i, q in enumerate(np.atleast_2d(qpos)):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        for foot, geoms in world.foot_spheres.items():
            out[foot][i] = data.geom_xpos[geoms]
            out[foot][i, :, 2] -= model.geom_size[geoms, 0]
    return out
