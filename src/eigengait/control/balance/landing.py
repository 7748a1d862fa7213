"""Where a flight lands: the COM target shifted to the landing point, then eased back onto the
reference.

In flight (a run's, a jump's) nothing can change the COM's path, and the stance-foot compensation
has no foot to act on; whatever horizontal COM error the take-off left is still there at touch-down.
Pulled back to the reference's COM from there at once, the landing foot would be asked for the whole
correction in the few tenths of a second when it is least able to give it (the forward jump falls on
landing with stiff COM gains). So at each touch-down after a flight the horizontal COM target is
shifted by the COM error of that instant, and the shift decays to zero with time constant EASE_S:
the character lands where it lands and then walks back onto the reference. Clips without flight are
tracked against the reference itself.
"""

from __future__ import annotations

import numpy as np

EASE_S = 1.0  # s, time constant of the shift's decay


class LandingShift:
    """The horizontal shift (m, world) of the COM target, updated once per control step of `dt`
    seconds."""

    def __init__(self, dt: float):
        self.shift = np.zeros(3)
        self.decay = float(np.exp(-dt / EASE_S))
        self.airborne = False

    def shifted(self, com_ref: np.ndarray) -> np.ndarray:
        """The COM target (3,) for the reference COM `com_ref` (3,)."""
        return com_ref + self.shift

    def update(self, airborne: bool, com: np.ndarray, com_ref: np.ndarray) -> None:
        """After a control step: the character in flight or not, its COM and the reference's
        (3,)."""
        self.shift *= self.decay
        if self.airborne and not airborne:
            self.shift[:2] = com[:2] - com_ref[:2]
        self.airborne = airborne
