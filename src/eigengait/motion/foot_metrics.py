"""Foot contact quality of a motion from its sole points: stances, skate, floor penetration, ground
clearance.

Sole points are per foot an array (F, k, 3) of world positions (m, z up, floor at z = 0) of the
foot's lowest points, one row per frame (e.g. the bottoms of its contact spheres).

* Stance: a run of at least MIN_STANCE_S seconds in which the foot's lowest sole point is within
  CONTACT_M of the floor. A foot that leaves that band for less than BOUNCE_S and comes back has
  bounced, not stepped: the two runs are one stance.
* Skate of a stance: the horizontal travel (m) of the foot's touching part: per pair of successive
  touching frames (consecutive, or the two sides of a bounce), the mean horizontal displacement of
  the sole points within CONTACT_M of the floor in both, summed as lengths. A foot rolling from heel
  to toe does not skate; a sliding one does, and so does one that bounces and lands elsewhere. The
  clip's skate is the mean over stances; its worst stance is reported beside it.
* Floor penetration: the deepest sole point below the floor (m, ≥ 0).
* Ground clearance: per swing (the frames between two stances of one foot) the highest its lowest
  sole point gets; the mean over swings (m), None without swings.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

CONTACT_M = 0.02
MIN_STANCE_S = 0.05
BOUNCE_S = 0.05  # s: a shorter lift out of the contact band inside a stance is a bounce


@dataclass(frozen=True)
class FootReport:
    """Foot skate (m, mean per stance, and of the worst stance), stance count, floor penetration
    (m), ground clearance (m or None)."""

    foot_skate_m: float
    foot_skate_max_m: float
    stances: int
    floor_penetration_m: float
    ground_clearance_m: float | None

    def summary(self) -> dict:
        clearance = None if self.ground_clearance_m is None else round(self.ground_clearance_m, 4)
        return {
            "foot_skate_m": round(self.foot_skate_m, 4),
            "foot_skate_max_m": round(self.foot_skate_max_m, 4),
            "stances": self.stances,
            "floor_penetration_m": round(self.floor_penetration_m, 4),
            "ground_clearance_m": clearance,
        }


def runs(mask: np.ndarray, frame_time: float, min_s: float) -> list[tuple[int, int]]:
    """Frame ranges [start, end) where the boolean mask (F,) holds for at least min_s seconds."""
    down = np.concatenate([[False], np.asarray(mask, bool), [False]])
    edges = np.flatnonzero(np.diff(down.astype(int)))
    shortest = max(1, int(round(min_s / frame_time)))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2]) if b - a >= shortest]


def bridge_bounces(mask: np.ndarray, frame_time: float, bounce_s: float = BOUNCE_S) -> np.ndarray:
    """The boolean mask (F,) with its False gaps shorter than `bounce_s` between two True runs
    filled."""
    mask = np.asarray(mask, bool).copy()
    for a, b in runs(~mask, frame_time, 0.0):
        if 0 < a and b < len(mask) and b - a < bounce_s / frame_time:
            mask[a:b] = True
    return mask


def stances(
    low: np.ndarray,
    frame_time: float,
    contact_m: float = CONTACT_M,
    min_stance_s: float = MIN_STANCE_S,
    bounce_s: float = BOUNCE_S,
) -> list[tuple[int, int]]:
    """Frame ranges [start, end) where the lowest sole height `low` (F,) stays within `contact_m` of
    the floor, bounces shorter than `bounce_s` bridged."""
    down = bridge_bounces(np.asarray(low) <= contact_m, frame_time, bounce_s)
    return runs(down, frame_time, min_stance_s)


def stance_skate(points: np.ndarray, start: int, end: int, contact_m: float = CONTACT_M) -> float:
    """Horizontal travel (m) of the touching sole points (F, k, 3) over frames [start, end),
    across any bounce within them."""
    travel, previous = 0.0, None
    for i in range(start, end):
        now = points[i, :, 2] <= contact_m
        if not now.any():
            continue
        if previous is not None:
            touching = now & (points[previous, :, 2] <= contact_m)
            if touching.any():
                step = points[i, touching, :2] - points[previous, touching, :2]
                travel += float(np.linalg.norm(step.mean(axis=0)))
        previous = i
    return travel


def foot_report(
    soles: dict[str, np.ndarray], frame_time: float, contact_m: float = CONTACT_M
) -> FootReport:
    """Skate, penetration and clearance of all feet (sole points per foot, see the module doc)."""
    skates, peaks, deepest = [], [], 0.0
    for points in soles.values():
        low = points[..., 2].min(axis=1)
        deepest = max(deepest, float(-low.min()))
        runs = stances(low, frame_time, contact_m)
        skates += [stance_skate(points, a, b, contact_m) for a, b in runs]
        peaks += [float(low[b:a2].max()) for (_, b), (a2, _) in zip(runs, runs[1:]) if a2 > b]
    return FootReport(
        foot_skate_m=float(np.mean(skates)) if skates else 0.0,
        foot_skate_max_m=max(skates, default=0.0),
        stances=len(skates),
        floor_penetration_m=max(deepest, 0.0),
        ground_clearance_m=float(np.mean(peaks)) if peaks else None,
    )
