"""Take-off: the push-off before a flight sets the flight, so its vertical COM is tracked harder.

Once a runner or a jumper leaves the floor, the vertical velocity it left with decides how high it
flies and when it lands; nothing in flight can change it. A retargeted reference's push-off is not
dynamically consistent (the CMU run's COM decelerates upwards at about 17 m/s² while its foot is
still down, which only a foot pulling on the floor could do), so tracking its joints launches the
body faster than its COM: measured on fast non-CMU runs (docs/balance.md), the simulated body flew
up to 14 cm higher than the reference's, its next foot landed 0.1 s late, the shortened stance
launched it higher still, and it pitched over after a few strides.

So over the last TAKEOFF_S of a stance that the reference ends in a flight (every foot's lowest
sole point above CONTACT_M), the whole-body QP weights the vertical row of its COM task
TAKEOFF_COM_GAIN times (`wbc.py`): the take-off velocity follows the reference's COM rather than its
ankles. Clips without flights (walks, standing) are tracked as before.
"""

from __future__ import annotations

import numpy as np

from eigengait.control.balance.double_support import CONTACT_M

TAKEOFF_S = 0.15  # s: the push-off before a flight
TAKEOFF_COM_GAIN = 3.0  # the COM task's vertical row, over its usual weight


def takeoff_windows(
    foot_height: np.ndarray, frame_time: float, window_s: float = TAKEOFF_S
) -> np.ndarray:
    """(F,) bool: the frames within `window_s` (s) before a reference flight begins, while a foot is
    still down; `foot_height` (F, n_feet) m is each foot's lowest sole point, `frame_time` (s)."""
    flight = (np.asarray(foot_height) > CONTACT_M).all(axis=1)
    starts = np.flatnonzero(flight[1:] & ~flight[:-1]) + 1
    reach = int(round(window_s / frame_time))
    out = np.zeros(len(flight), bool)
    for start in starts:
        out[max(0, start - reach) : start] = True
    return out
