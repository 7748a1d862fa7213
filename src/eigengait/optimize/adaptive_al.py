"""pycma's adaptive augmented Lagrangian (Atamna et al. 2017) on the same problem, for comparison with the
thesis's method of multipliers (`--method al`).

The cyclic constraint |φᵢ| ≤ tolerance becomes the inequality pair (φᵢ − tol, −φᵢ − tol) ≤ 0; `cma`'s
`ConstrainedFitnessAL` adapts the multipliers and penalties every generation. One CMA-ES run, restarted from the
best solution with σ ← 0.7σ when it stops, until the constraint is met or the budget is spent. The population is
still evaluated as one batch: the fitness wrapper reads each candidate's outcome from a per-generation table.
"""

from __future__ import annotations

import time
import warnings

import cma
import numpy as np

from eigengait.optimize.mom import MethodOfMultipliers, merit


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


class AdaptiveAugmentedLagrangian(MethodOfMultipliers):
    """Same state, checkpoints and stopping rules as the method of multipliers; different constraint handling."""

    def _new_es(self) -> cma.CMAEvolutionStrategy:
        es = super()._new_es()
        table = _OutcomeTable(self.s.cycle_tolerance)
        with warnings.catch_warnings():      # cma warns that its optional archive package is missing
            warnings.simplefilter("ignore")
            self.state.al = cma.ConstrainedFitnessAL(table.objective, table.constraints, dimension=len(es.mean),
                                                     archives=False)
        self.state.al_table = table
        return es

    def generation(self) -> dict:
        st = self.state
        t0 = time.perf_counter()
        X = np.array(st.es.ask())
        outcomes = self.evaluate(X)
        st.al_table.rows = {x.tobytes(): o for x, o in zip(X, outcomes)}
        fitness = [st.al(x) for x in X]
        st.es.tell(list(X), fitness)
        st.al.update(st.es)
        st.al_table.rows = {}
        st.generation += 1
        st.evaluations += len(X)
        i = int(np.argmin([merit(o) for o in outcomes]))
        if st.best is None or merit(outcomes[i]) < merit(st.best):
            st.best, st.best_x = outcomes[i], X[i].copy()
        st.elapsed += time.perf_counter() - t0
        row = {"generation": st.generation, "outer": st.outer, "evaluations": st.evaluations,
               "best_cost": st.best.cost, "best_violation": st.best.violation,
               "generation_best_W": float(min(fitness)), "sigma": float(st.es.sigma), "k": 0.0,
               "lambda_norm": float(np.linalg.norm(st.al.al.lam)) if st.al.al.lam is not None else 0.0,
               "fallen": int(sum(o.fell for o in outcomes)), "seconds": st.elapsed}
        st.log.append(row)
        return row

    def end_inner_run(self) -> None:
        st = self.state
        st.sigma = max(self.s.sigma_floor, st.sigma * self.s.sigma_decay)
        st.outer += 1
        st.es = None
