"""Double support: share the body's weight between the feet as the reference does.

With stiff joint tracking the load of two planted feet is decided by millimetres: the foot whose leg
reaches a little lower carries the body, the other rests on the floor unloaded (measured: the
forward jump's take-off and the standing clip's weight shifts ran on one foot, which pushed the jump
sideways into a spin and let the standing character topple towards the idle foot). For each foot
that the reference has on the floor (its lowest sole point within CONTACT_M), the load it should
carry follows from the lever rule on the reference: a foot's share is 1 − t, with t the reference
COM's position along the segment between the feet's sole centres (clipped to [0, 1]; 1 when the
reference stands on that foot alone). A foot carrying less than its share of the load W (the body
weight, or the feet's total normal force when larger, as in a push-off) is pressed down: the leg's
joints get
τ = J_footᵀ (0, 0, −f) with f = PRESS_GAIN (share · W − N) (N its normal force), J_foot the
translational Jacobian of the foot body on the leg's own joints (pelvis-rooted). The reaction lifts
the pelvis off the other leg, which is how a weight shift is made.
"""

from __future__ import annotations

import numpy as np

CONTACT_M = 0.02
PRESS_GAIN = 1.0


def load_shares(com_ref: np.ndarray, centres: np.ndarray, heights: np.ndarray) -> np.ndarray:
    """Share (n_feet,) of the body weight each foot should carry, from the reference COM (2+,) and
    each foot's sole centre (n_feet, 2) and lowest sole height (n_feet,), m; zero for a foot off the
    floor."""
    down = heights <= CONTACT_M
    shares = down.astype(float)
    if down.sum() != 2:
        return shares
    a, b = centres[down]
    span = b - a
    t = float(np.clip((com_ref[:2] - a) @ span / max(span @ span, 1e-9), 0.0, 1.0))
    shares[np.flatnonzero(down)] = [1.0 - t, t]
    return shares


def pressing_force(share: float, load: float, normal: float) -> float:
    """Downward force (N) on a foot that should carry `share` of `load` (N) and carries `normal`
    (N)."""
    return PRESS_GAIN * max(share * load - normal, 0.0)
