"""pycma's adaptive augmented Lagrangian (Atamna et al. 2017) on the same problem, for comparison
with the thesis's method of multipliers (method "al").

The cyclic constraint |φᵢ| ≤ tolerance becomes the inequality pair (φᵢ − tol, −φᵢ − tol) ≤ 0;
`cma`'s `ConstrainedFitnessAL` adapts the multipliers and penalties every generation. One CMA-ES
run, restarted from the best solution with σ ← 0.7σ when it stops, until the constraint is met or
the budget is spent. The population is still evaluated as one batch: the fitness reads each
candidate's outcome from the generation's outcomes.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import cma
import numpy as np

from eigengait.optimize.evaluate import Outcome
from eigengait.optimize.mom import ConstrainedSearch, SearchSettings


@dataclass
class AlSettings(SearchSettings):
    """pycma's adaptive augmented Lagrangian: the shared search settings only (it adapts its own
    multipliers and penalties, so it has no `penalty`)."""

    method: ClassVar[str] = "al"


class AdaptiveFitness:
    """pycma's `ConstrainedFitnessAL` for a batch-evaluated generation: each candidate's objective
    and constraints are looked up (by the candidate's bytes) in that generation's outcomes."""

    def __init__(self, tolerance: float, dimension: int):
        self.tolerance = tolerance
        self.rows: dict[bytes, Outcome] = {}
        self.constrained = self._quiet(dimension)

    def _quiet(self, dimension: int) -> cma.ConstrainedFitnessAL:
        """Without pycma's log files: building its AugmentedLagrangian makes an `outcmaes/` folder
        in the working directory, which is removed again if it is new and empty; logging is off, so
        nothing is written there."""
        folder = Path("outcmaes")
        existed = folder.exists()
        with warnings.catch_warnings():  # cma warns that its optional archive package is missing
            warnings.simplefilter("ignore")
            fitness = cma.ConstrainedFitnessAL(
                self._objective, self._constraints, dimension=dimension, archives=False
            )
            fitness.al.logging = 0
        if not existed and folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()
        return fitness

    def _objective(self, x) -> float:
        return self.rows[np.asarray(x, dtype=float).tobytes()].cost

    def _constraints(self, x) -> list[float]:
        phi = self.rows[np.asarray(x, dtype=float).tobytes()].cycle
        return list(np.concatenate([phi - self.tolerance, -phi - self.tolerance]))

    def __call__(self, X: np.ndarray, outcomes: list[Outcome]) -> list[float]:
        """The penalized fitness of every candidate of the generation."""
        self.rows = {x.tobytes(): o for x, o in zip(X, outcomes)}
        values = [self.constrained(x) for x in X]
        self.rows = {}
        return values

    def update(self, es: cma.CMAEvolutionStrategy) -> None:
        """Adapt the multipliers and penalties after the generation was told to `es`."""
        self.constrained.update(es)

    @property
    def multipliers(self) -> np.ndarray:
        """pycma's Lagrange multipliers, one per inequality (one zero before the first update)."""
        lam = self.constrained.al.lam
        return np.zeros(1) if lam is None else np.asarray(lam)


class AdaptiveAugmentedLagrangian(ConstrainedSearch):
    """Same state, checkpoints and stopping rules as the method of multipliers; different constraint
    handling."""

    s: AlSettings

    def _new_es(self) -> cma.CMAEvolutionStrategy:
        es = super()._new_es()
        self.state.al = AdaptiveFitness(self.s.cycle_tolerance, len(es.mean))
        return es

    def fitness(self, X: np.ndarray, outcomes: list[Outcome]) -> list[float]:
        """pycma's adaptive AL fitness; its multipliers and penalties update after every
        generation."""
        return self.state.al(X, outcomes)

    def multipliers(self, like: np.ndarray) -> np.ndarray:
        return self.state.al.multipliers

    def tell(self, X: np.ndarray, outcomes: list[Outcome]) -> list[float]:
        W = super().tell(X, outcomes)
        self.state.al.update(self.state.es)
        return W
