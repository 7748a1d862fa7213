"""The clip's own flat feet: the frames in which a captured foot stands flat, and how flat the
character's foot stands in them.

A clip whose foot joint has a toe (a child joint or an End Site) says when its foot is flat
without any assumption about the sole: the ankle and the toe are then both at their lowest.
Checked on Bandai Namco's clips, where the ankle-to-toe bone points 40° down in every such frame
(16-63 % of the frames, runs included). The character's foot should stand flat there; its tilt
from level in those frames (`flat_tilt_deg`) measures the retarget's foot orientation
independently of the levelling (`foot_level`), which reads still feet through the character's own
sole points.
"""

from __future__ import annotations

import mujoco
import numpy as np
from scipy.ndimage import minimum_filter1d

from eigengait.motion.bvh import BvhClip, end_site_positions
from eigengait.sim.feet import foot_up, sole_up
from eigengait.sim.world import World

FLAT_BAND_SHARE = 0.12  # of the foot bone's length (ankle to toe)
FLAT_WINDOW_S = 2.0  # lowest heights read over this window: a capture floor may drift
# A tilt worth a warning: the CMU corpus's references stand 2-13° off level where their clips'
# feet are flat; 15 of the 44 Bandai Namco references stand 16-44° off, on their heels or toes.
FLAT_TILT_WARN_DEG = 15.0


def source_flat_frames(ankle: np.ndarray, toe: np.ndarray, frame_time: float) -> np.ndarray:
    """Frames (F,) bool in which a captured foot stands flat: its ankle and toe, at positions
    (F, 3) in world axes (z up, any length unit), both within FLAT_BAND_SHARE of the foot bone's
    median length above their lowest heights within FLAT_WINDOW_S."""
    band = FLAT_BAND_SHARE * float(np.median(np.linalg.norm(toe - ankle, axis=1)))
    size = max(1, int(round(FLAT_WINDOW_S / frame_time))) | 1
    lows = [minimum_filter1d(h, size, mode="nearest") for h in (ankle[:, 2], toe[:, 2])]
    return (ankle[:, 2] <= lows[0] + band) & (toe[:, 2] <= lows[1] + band)


def clip_flat_frames(
    clip: BvhClip, rot: np.ndarray, pos: np.ndarray, axes: np.ndarray, foot_joints: list[int]
) -> dict[int, np.ndarray]:
    """Per BVH foot joint in `foot_joints` that has a toe, its flat frames (F,) bool; `rot`, `pos`:
    the frames' global transforms (`bvh.global_transforms`, file axes), `axes`: file to world."""
    ends = end_site_positions(clip, rot, pos)
    parents = [j.parent for j in clip.joints]
    out = {}
    for joint in foot_joints:
        children = [i for i, p in enumerate(parents) if p == joint]
        toe = pos[:, children[0]] if children else ends.get(joint)
        if toe is not None:
            out[joint] = source_flat_frames(pos[:, joint] @ axes.T, toe @ axes.T, clip.frame_time)
    return out


def flat_tilt_deg(world: World, qpos: np.ndarray, flat: dict[str, np.ndarray]) -> dict[str, float]:
    """Per foot name in `flat`, the median tilt (degrees) of the character's foot from level over
    the poses qpos (F, nq) flagged (F,) bool: the angle between world up and the foot's up in the
    character's relax pose (its `sole_up`), carried by the foot. Feet with no flagged frame are
    left out."""
    model, data = world.model, mujoco.MjData(world.model)
    out = {}
    for foot, frames in flat.items():
        if not frames.any():
            continue
        body = int(model.geom_bodyid[world.foot_spheres[foot][0]])
        rest_up = sole_up(world, foot)
        cosines = [foot_up(model, data, q, body) @ rest_up for q in qpos[frames]]
        out[foot] = float(np.degrees(np.median(np.arccos(np.clip(cosines, -1.0, 1.0)))))
    return out


__all__ = ["FLAT_TILT_WARN_DEG", "clip_flat_frames", "flat_tilt_deg", "source_flat_frames"]
