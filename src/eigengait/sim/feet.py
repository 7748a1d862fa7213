"""The direction a character's foot calls up: the one that points straight up when its sole stands
flat (`sole_up`), and world up as a foot sees it in a pose (`foot_up`)."""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.character.guess import FOOT_SITE_PREFIX
from eigengait.geometry import quat_to_mat
from eigengait.sim.world import World

UP = np.array([0.0, 0.0, 1.0])


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
    return foot_up(model, mujoco.MjData(model), model.qpos0, body)


def foot_up(model: mujoco.MjModel, data: mujoco.MjData, qpos: np.ndarray, body: int) -> np.ndarray:
    """World up seen in the frame of `body` (3,) for pose qpos (nq,) (kinematics run in `data`)."""
    data.qpos[:] = qpos
    mujoco.mj_kinematics(model, data)
    return data.xmat[body].reshape(3, 3).T @ UP
