"""Scale a retargeted root path to the character's legs: the root translation under which the stance
feet stay put.

The hip-height scale (`retarget`) makes the character's legs as long as the clip's, but a clip's
root translation and its joint rotations need not agree on one body: the Daz-skeleton CMU exports
translate the root about 1.5 times further than their leg rotations carry any body (their stance
feet slide at about 1 m/s, and the forward jump rises 1.4 times higher than its flight time allows
under gravity). A reference like that cannot be tracked: the physical legs carry the body where the
rotations say, the reference COM runs ahead.

With the root path p(t) (m, world) and a foot's sole centre o(t) relative to the root (fixed by the
joint rotations), the foot moves at k ṗ + ȯ when the path is scaled by k. Over the frames in which
one foot clearly supports (its lowest sole point at least SUPPORT_GAP_M below the other foot's and
within SUPPORT_HEIGHT_M of the floor) the horizontal speed of that foot is minimised in least
squares: k = −Σ ṗ·ȯ / Σ |ṗ|². Too little root travel over those frames (a clip standing still)
leaves k = 1; k is bounded to FACTOR_RANGE. The supporting frames are chosen once, on the path at
the hip-height scale: refitting on the rescaled path is no better, since a lowered jump or run
brings its feet within SUPPORT_HEIGHT_M of the floor in flight, where they move with the root and
bias k towards 0.
"""

from __future__ import annotations

import numpy as np

SUPPORT_GAP_M = 0.01
SUPPORT_HEIGHT_M = 0.06
MIN_TRAVEL_M = 0.2  # root travel over the supporting frames below which the fit is not used
FACTOR_RANGE = (0.5, 2.0)


def leg_consistent_factor(
    root_path: np.ndarray, soles: dict[str, np.ndarray], frame_time: float
) -> float:
    """k for a root path (F, 3) and the sole points per foot (F, k, 3) it gives (world, m, floor at
    z = 0); see the module doc. Needs two feet; any other count gives 1."""
    if len(soles) != 2 or len(root_path) < 3:
        return 1.0
    lows = np.stack([points[..., 2].min(axis=1) for points in soles.values()], axis=1)
    offsets = np.stack(
        [points[..., :2].mean(axis=1) - root_path[:, :2] for points in soles.values()], axis=1
    )
    support = lows.argmin(axis=1)
    frames = (np.abs(lows[:, 0] - lows[:, 1]) >= SUPPORT_GAP_M) & (
        lows.min(axis=1) <= SUPPORT_HEIGHT_M
    )
    root_velocity = np.gradient(root_path[:, :2], frame_time, axis=0)[frames]
    offset_velocity = np.gradient(offsets, frame_time, axis=0)[
        np.flatnonzero(frames), support[frames]
    ]
    travel = np.linalg.norm(root_velocity, axis=1).sum() * frame_time
    if travel < MIN_TRAVEL_M:
        return 1.0
    factor = -np.sum(root_velocity * offset_velocity) / np.sum(root_velocity**2)
    return float(np.clip(factor, *FACTOR_RANGE))
