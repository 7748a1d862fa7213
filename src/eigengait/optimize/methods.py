"""The constrained optimizers by name: the thesis's method of multipliers or pycma's adaptive augmented
Lagrangian."""

from __future__ import annotations

from typing import Callable

import numpy as np

from eigengait.optimize.adaptive_al import AdaptiveAugmentedLagrangian
from eigengait.optimize.evaluate import Outcome
from eigengait.optimize.mom import MethodOfMultipliers, MomSettings, MomState


def make_optimizer(
    evaluate: Callable[[np.ndarray], list[Outcome]], settings: MomSettings, state: MomState
) -> MethodOfMultipliers:
    """The constrained optimizer named by `settings.method` ("mom" or "al")."""
    kind = AdaptiveAugmentedLagrangian if settings.method == "al" else MethodOfMultipliers
    return kind(evaluate, settings, state)
