"""A starter sketch for any character (`eigengait sketch new`): a first guess to edit, not a tuned
gait.

* feet: the character's gait order, not mirrored (`symmetric: false`);
* priority: the `PRIORITY_MODES` lowest modes of each phase, ψ = `PSI_ANGLE` × the median joint
  stiffness (N·m), alternating in sign, and the next `ALLOWED_MODES` modes allowed;
* timing: period T = half the lowest ground mode's period, clamped to `PERIOD_RANGE` (s); air ratio
  0.3; each pulse lasts half its phase;
* initial: forward speed `START_SPEED` (m/s); targets scaled to that speed.
"""

from __future__ import annotations

import numpy as np

from eigengait.character.loader import Character
from eigengait.modal import compute_modes
from eigengait.control.sketch import FORMAT_VERSION

PRIORITY_MODES, ALLOWED_MODES = 3, 3
PSI_ANGLE = 0.2  # rad
PERIOD_RANGE = (0.4, 1.2)
AIR_RATIO = 0.3
START_SPEED = 0.5  # m/s


def starter_sketch(character: Character, reference: str) -> dict:
    """The sketch as a mapping, `character: reference` (a built-in name or a path relative to the
    sketch)."""
    feet = list(character.meta.gait_order)
    air = compute_modes(character, "air")
    ground = compute_modes(character, "ground", feet[0])
    psi = PSI_ANGLE * float(np.median(np.concatenate(list(character.stiffness.values()))))

    def phase(count: int) -> dict:
        chosen = range(1, min(PRIORITY_MODES, count) + 1)
        return {
            "priority": {m: round(psi * (-1) ** (m + 1), 3) for m in chosen},
            "allowed": list(range(len(chosen) + 1, min(len(chosen) + ALLOWED_MODES, count) + 1)),
        }

    period = float(np.clip(0.5 / ground.frequencies_hz[0], *PERIOD_RANGE))
    share = period / len(feet)
    return {
        "eigengait_sketch": FORMAT_VERSION,
        "description": (
            f"Starter sketch for {character.name}: lowest modes as priority, timing from the "
            f"lowest ground mode ({ground.frequencies_hz[0]:.2f} Hz). Edit freely."
        ),
        "character": reference,
        "relax_pose": "default",
        "feet": feet,
        "symmetric": False,
        "air": phase(air.count),
        "ground": phase(ground.count),
        "timing": {
            "period": round(period, 3),
            "air_ratio": AIR_RATIO,
            "pulse_air": round(0.5 * AIR_RATIO * share, 3),
            "pulse_ground": round(0.5 * (1 - AIR_RATIO) * share, 3),
        },
        "initial": {"speed": START_SPEED, "height": 0.0},
        "targets": {"min_speed": round(0.3 * START_SPEED, 3), "mean_speed": START_SPEED},
    }
