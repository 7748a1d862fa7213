"""Foot contacts that vanish for a few physics steps are bridged.

MuJoCo's soft contact lets a foot pressed onto the floor by a stiff leg part from it for single
physics steps: on the standing CMU laugh the feet's normal forces alternated between 0 and 700-900 N
from one 0.5 ms step to the next for whole seconds. Read raw, each empty step switched the balance
torque off (no foot touching) and set the double-support press to its full force, which fed the
chatter. A foot whose contacts vanish therefore keeps its last ones for up to HOLD seconds; a foot
off the floor for longer has left it.
"""

from __future__ import annotations

import numpy as np

HOLD = 0.002  # s a foot's last contacts outlive them


class ContactMemory:
    """Per foot, the last non-empty contacts (`controller.foot_contacts` rows) and when they were
    read."""

    def __init__(self, hold: float = HOLD):
        self.hold = hold
        self.last: dict[str, tuple[np.ndarray, float]] = {}

    def bridged(self, contacts: dict[str, np.ndarray], time: float) -> dict[str, np.ndarray]:
        """The contacts read at `time` (s), a foot without any given its last ones if they are at
        most `hold` old."""
        out = {}
        for foot, rows in contacts.items():
            if len(rows):
                self.last[foot] = (rows, time)
                out[foot] = rows
                continue
            kept = self.last.get(foot)
            recent = kept is not None and time - kept[1] <= self.hold + 1e-12
            out[foot] = kept[0] if recent else rows
        return out
