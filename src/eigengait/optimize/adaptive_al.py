"""pycma's adaptive augmented Lagrangian (Atamna et al. 2017) on the same problem, for comparison with the
thesis's method of multipliers (`--method al`).

The cyclic constraint |φᵢ| ≤ tolerance becomes the inequality pair (φᵢ − tol, −φᵢ − tol) ≤ 0; `cma`'s
`ConstrainedFitnessAL` adapts the multipliers and penalties every generation. One CMA-ES run, restarted from the
best solution with σ ← 0.7σ when it stops, until the constraint is met or the budget is spent. The population is
still evaluated as one batch: the fitness wrapper reads each candidate's outcome from a per-generation table.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import cma
import numpy as np

from eigengait.optimize.mom import MethodOfMultipliers


class _OutcomeTable:
    """Objective and constraints of the current generation's candidates, looked up by their bytes."""

    def __init__(self, tolerance: float):
        self.tolerance = tolerance
        self.rows: dict[bytes, object] = {}

    def objective(self, x) -> float:
        return self.rows[np.asarray(x, dtype=float).tobytes()].cost

    def constraints(self, x) -> list[float]:
        phi = self.rows[np.asarray(x, dtype=float).tobytes()].cycle
        return list(np.concatenate([phi - self.tolerance, -phi - self.tolerance]))


def _quiet_constrained_fitness(table: _OutcomeTable, dimension: int) -> cma.ConstrainedFitnessAL:
    """`ConstrainedFitnessAL` without pycma's log files: its AugmentedLagrangian makes loggers (and an
    `outcmaes/` folder in the working directory) when built; drop them and remove the folder if it is new."""
    folder = Path("outcmaes")
    existed = folder.exists()
    with warnings.catch_warnings():  # cma warns that its optional archive package is missing
        warnings.simplefilter("ignore")
        fitness = cma.ConstrainedFitnessAL(
            table.objective, table.constraints, dimension=dimension, logging=False, archives=False
        )
        fitness.al.logging = 0
        fitness.al._init_()
    if not existed and folder.is_dir() and not any(folder.iterdir()):
        folder.rmdir()
    return fitness


class AdaptiveAugmentedLagrangian(MethodOfMultipliers):
    """Same state, checkpoints and stopping rules as the method of multipliers; different constraint handling."""

    def _new_es(self) -> cma.CMAEvolutionStrategy:
        es = super()._new_es()
        table = _OutcomeTable(self.s.cycle_tolerance)
        self.state.al = _quiet_constrained_fitness(table, len(es.mean))
        self.state.al_table = table
        return es

    def fitness(self, X: np.ndarray, outcomes: list) -> list[float]:
        """pycma's adaptive AL fitness; its multipliers and penalties update after every generation."""
        st = self.state
        st.al_table.rows = {x.tobytes(): o for x, o in zip(X, outcomes)}
        values = [st.al(x) for x in X]
        st.al_table.rows = {}
        return values

    def multipliers(self, like: np.ndarray) -> np.ndarray:
        lam = self.state.al.al.lam if getattr(self.state, "al", None) is not None else None
        return np.zeros(1) if lam is None else np.asarray(lam)

    def tell(self, X: np.ndarray, outcomes: list) -> list[float]:
        W = super().tell(X, outcomes)
        self.state.al.update(self.state.es)
        return W

    def end_inner_run(self) -> None:
        st = self.state
        st.sigma = max(self.s.sigma_floor, st.sigma * self.s.sigma_decay)
        st.outer += 1
        st.es = None
        st.history = []
