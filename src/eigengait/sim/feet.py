"""The direction a character's foot calls up: the one that points straight up when its sole stands
flat (`sole_up`)."""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.character.guess import FOOT_SITE_PREFIX
from eigengait.geometry import quat_to_mat
from eigengait.sim.world import World


def sole_up(world: World, foot: str) -> np.ndarray:
    """The foot's up (3,), in its body frame: the direction that points straight up when its sole
    stands flat. A guessed foot's toe site carries its sole's normal as its z axis
    (`character.guess`); for any other foot it is world up seen by the foot in the relax pose,
    where a character's sole stands flat."""
    model = world.model
    toe = world.character.feet[foot].toe
    if toe.startswith(FOOT_SITE_PREFIX):
        return quat_to_mat(model.site_quat[model.site(toe).id])[:, 2]
    body = int(model.geom_bodyid[world.foot_spheres[foot][0]])
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    return data.xmat[body].reshape(3, 3).T @ np.array([0.0, 0.0, 1.0])
