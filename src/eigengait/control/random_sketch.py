"""Random sketches (thesis §5.3.4): priority modes and their signs drawn by a seeded procedure, not
chosen.

The thesis draws the priority modes among the first `DRAW_FROM` modes of each phase, each with one
preset normalized amplitude and a random sign, on top of a default set of allowed modes:

| procedure | air priority | ground priority | amplitude | optimized modes (air / ground, Table 5.1) |
|---|---:|---:|---:|---|
| 1 | 3 | 4 | 0.4 | 8 / 8 |
| 2 | 2 | 3 | 0.3 | 6 / 7 |

Here a normalized amplitude a is the torque ψ = a × the character's median joint stiffness (N·m: the
torque that holds a joint of median stiffness a radians from rest), and the allowed set is the
lowest modes not drawn, as many as Table 5.1's totals need. Everything else (feet, timing, initial
state, targets) is the starter sketch's (`control/starter.py`); for a character with mirror pairs
and two feet the gait is symmetric.
"""  # noqa: E501

from __future__ import annotations

import numpy as np

from eigengait.character.loader import Character
from eigengait.control.starter import starter_sketch
from eigengait.modal import compute_modes

DRAW_FROM = 15
PROCEDURES = {  # procedure -> (air priority, ground priority, amplitude, air total, ground total)
    1: (3, 4, 0.4, 8, 8),
    2: (2, 3, 0.3, 6, 7),
}


def _phase(rng: np.random.Generator, count: int, drawn: int, total: int, psi: float) -> dict:
    modes = sorted(
        int(m) for m in rng.choice(np.arange(1, min(DRAW_FROM, count) + 1), drawn, replace=False)
    )
    signs = rng.choice([-1.0, 1.0], drawn)
    rest = [m for m in range(1, count + 1) if m not in modes][: max(0, total - drawn)]
    return {
        "priority": {m: round(float(s * psi), 3) for m, s in zip(modes, signs)},
        "allowed": rest,
    }


def random_sketch(character: Character, reference: str, seed: int, procedure: int = 1) -> dict:
    """The sketch as a mapping (`character: reference`), drawn from `seed` by `procedure`
    (1 or 2)."""
    air_n, ground_n, amplitude, air_total, ground_total = PROCEDURES[procedure]
    sketch = starter_sketch(character, reference)
    rng = np.random.default_rng(seed)
    psi = amplitude * float(np.median(np.concatenate(list(character.stiffness.values()))))
    air = compute_modes(character, "air")
    ground = compute_modes(character, "ground", sketch["feet"][0])
    sketch["air"] = _phase(rng, air.count, air_n, air_total, psi)
    sketch["ground"] = _phase(rng, ground.count, ground_n, ground_total, psi)
    sketch["symmetric"] = len(sketch["feet"]) == 2 and character.meta.mirror is not None
    sketch["description"] = (
        f"Random sketch (thesis §5.3.4, procedure {procedure}, seed {seed}) for {character.name}: "
        f"{air_n} air and {ground_n} ground priority modes drawn among the first {DRAW_FROM}, "
        f"amplitude ±{amplitude}."
    )
    return sketch
