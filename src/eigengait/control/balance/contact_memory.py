"""Foot contacts that vanish for one reading are bridged.

MuJoCo's soft contact lets a foot pressed onto the floor by a stiff leg part from it for single
physics steps: on the standing CMU laugh the feet's normal forces alternated between 0 and 700-900 N
from one 0.5 ms step to the next for whole seconds. Read raw, each empty step switched the balance
torque off (no foot touching) and set the double-support press to its full force, which fed the
chatter. A foot whose contacts vanish therefore keeps its last ones for STEPS readings. Longer
bridges hold stale contacts through real lift-offs: measured at robustness 0, the 02_01 walk's joint
error rose from 3.1° (one reading) to 4.6° (two) and 4.9° (four) (docs/balance.md, row 15).
"""

from __future__ import annotations

import numpy as np

STEPS = 1  # readings a foot's last contacts outlive them


class ContactMemory:
    """Per foot, the last non-empty contacts (`controller.foot_contacts` rows) and how many readings
    they have been bridged for; one reading per control step."""

    def __init__(self, steps: int = STEPS):
        self.steps = steps
        self.last: dict[str, tuple[np.ndarray, int]] = {}

    def bridged(self, contacts: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """This reading's contacts, a foot without any given its last ones for at most `steps`
        readings in a row."""
        out = {}
        for foot, rows in contacts.items():
            kept, bridged = self.last.get(foot, (rows, self.steps))
            if len(rows):
                self.last[foot] = (rows, 0)
            elif bridged < self.steps:
                self.last[foot] = (kept, bridged + 1)
                rows = kept
            out[foot] = rows
        return out
