"""Put a retargeted pose sequence's feet on the floor: the root height per frame.

1. Floor drift: the lowest foot point's running minimum over FLOOR_WINDOW_S, smoothed over the same
   window, is taken as the capture's floor (it drifts by some centimetres over a clip) and
   subtracted from the root height.
2. Hovering feet: a retargeted character's legs are not the actor's, so the root's vertical motion
   and the legs' reach disagree and the supporting foot hovers a few centimetres above that floor
   for part of a step (up to 5 cm on the Daz-skeleton CMU walks; a physical foot there has nothing
   to stand on). What remains of the lowest foot point's height h after step 1 is removed as well,
   with weight 1 up to HOVER_M and falling linearly to 0 at FLIGHT_M, so that the raised feet of a
   jump or a run's flight phase keep their height; the correction is smoothed over
   HOVER_SMOOTHING_S.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.sim.world import World

FLOOR_WINDOW_S = 1.0
HOVER_M = 0.03
FLIGHT_M = 0.08
HOVER_SMOOTHING_S = 0.05


def lowest_foot_points(world: World, qpos: np.ndarray) -> np.ndarray:
    """Height (m) of the lowest point of the feet's contact spheres (all geoms if there are none)
    per pose (F,)."""
    model, data = world.model, mujoco.MjData(world.model)
    geoms = [g for gs in world.foot_spheres.values() for g in gs] or [
        g for g in range(model.ngeom) if model.geom_bodyid[g] != 0
    ]
    lows = np.empty(len(qpos))
    for i, q in enumerate(qpos):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        lows[i] = np.min(data.geom_xpos[geoms, 2] - model.geom_rbound[geoms])
    return lows


def _box(values: np.ndarray, half: int) -> np.ndarray:
    """Moving average over 2 half + 1 samples, ends padded with the end values."""
    padded = np.concatenate([np.full(half, values[0]), values, np.full(half, values[-1])])
    return np.convolve(padded, np.ones(2 * half + 1) / (2 * half + 1), mode="valid")


def floor_offset(lows: np.ndarray, frame_time: float) -> np.ndarray:
    """Per-frame height (m) to subtract from the root so that the feet touch the floor, from the
    lowest foot point per frame (F,) at frame_time (s); see the module doc."""
    half = max(1, int(round(FLOOR_WINDOW_S / 2 / frame_time)))
    padded = np.concatenate([np.full(half, lows[0]), lows, np.full(half, lows[-1])])
    running = np.array([padded[i : i + 2 * half + 1].min() for i in range(len(lows))])
    floor = _box(running, half)
    hover = lows - floor
    weight = np.clip((FLIGHT_M - hover) / (FLIGHT_M - HOVER_M), 0.0, 1.0)
    return floor + _box(weight * hover, max(1, int(round(HOVER_SMOOTHING_S / 2 / frame_time))))
