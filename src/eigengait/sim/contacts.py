"""The one rule for "this foot is on the ground", shared by the controller, the gait metrics and the
renderer.

A foot touches the ground (`foot_touching`) when one of its contact spheres (the geoms the engine
collides with the floor plane z = 0) has its bottom, centre z − radius, within `CONTACT_TOLERANCE`
of the floor.
"""

from __future__ import annotations

import numpy as np

CONTACT_TOLERANCE = 0.005  # m


def spheres_touching(centre_z: np.ndarray, radius: np.ndarray | float) -> np.ndarray:
    """Per sphere (any shape): its bottom is within `CONTACT_TOLERANCE` (m) of the floor."""
    return np.asarray(centre_z) - radius <= CONTACT_TOLERANCE


def foot_touching(points: np.ndarray, radius: float) -> np.ndarray:
    """Per row (…): one of a foot's contact spheres, centres `points` (…, k, 3) in m, touches the
    floor."""
    return spheres_touching(points[..., 2], radius).any(axis=-1)
