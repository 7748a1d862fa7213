"""The constrained optimizers by name: the thesis's method of multipliers ("mom") or pycma's
adaptive augmented Lagrangian ("al"), each with its own settings class."""

from __future__ import annotations

from typing import Callable

import numpy as np

from eigengait.errors import UserInputError
from eigengait.optimize.adaptive_al import AdaptiveAugmentedLagrangian, AlSettings
from eigengait.optimize.evaluate import Outcome
from eigengait.optimize.mom import (
    ConstrainedSearch,
    MethodOfMultipliers,
    MomSettings,
    MomState,
    SearchSettings,
)

METHODS = {
    MomSettings.method: (MomSettings, MethodOfMultipliers),
    AlSettings.method: (AlSettings, AdaptiveAugmentedLagrangian),
}


def method_settings(method: str, **fields) -> SearchSettings:
    """The settings of the optimizer named `method`; a field it does not read is a `TypeError`."""
    if method not in METHODS:
        raise UserInputError(
            f"unknown method '{method}'", field="method", fix="use method='mom' or method='al'"
        )
    return METHODS[method][0](**fields)


def make_optimizer(
    evaluate: Callable[[np.ndarray], list[Outcome]], settings: SearchSettings, state: MomState
) -> ConstrainedSearch:
    """The constrained optimizer the settings are for (`settings.method`)."""
    return METHODS[settings.method][1](evaluate, settings, state)
