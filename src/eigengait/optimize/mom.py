"""Method of multipliers around CMA-ES (thesis §4.4), with checkpoints after every generation.

Outer loop: W(x, λ, k) = f(x) + λᵀφ(x) + k φᵀφ; each inner CMA-ES run minimizes W; then λ ← λ + 2kφ(x*).
The first inner run uses λ = 0, k = 0, later ones k = `penalty`. σ₀ = 0.3 then σ ← 0.7σ per inner run (floor
0.001). An inner run stops at stopTolX 1e-4 or its generation cap; the outer loop stops when every |φ_i| is below
the tolerance, after `max_outer` inner runs, or when the evaluation/time budget is spent.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import cma
import numpy as np

from eigengait.optimize.evaluate import Outcome


@dataclass
class MomSettings:
    seed: int = 1
    sigma0: float = 0.3
    sigma_decay: float = 0.7
    sigma_floor: float = 0.001
    penalty: float = 0.1  # k after the first inner run
    tol_x: float = 1e-4
    inner_generations: int = 1000
    max_outer: int = 20
    cycle_tolerance: float = 0.2  # |φ_i| below this on every component: cyclic
    popsize: int | None = None  # CMA default 4 + 3 ln n
    max_evaluations: int | None = None
    max_seconds: float | None = None
    method: str = "mom"  # "mom" (the thesis's) or "al" (pycma's adaptive augmented Lagrangian)

    def __post_init__(self):
        if self.method not in ("mom", "al"):
            from eigengait.errors import UserInputError

            raise UserInputError(
                f"unknown method '{self.method}'", field="method", fix="use method='mom' or method='al'"
            )


@dataclass
class MomState:
    """Everything needed to resume: multipliers, penalty, best so far, counters, and the current inner run as
    data (its start point and every generation's candidates and outcomes, from which the CMA object is rebuilt by
    replaying them; see `optimize.checkpoint`)."""

    x_start: np.ndarray
    outer: int = 0
    sigma: float = 0.3
    k: float = 0.0
    lam: np.ndarray | None = None
    es: object | None = None
    generation: int = 0
    evaluations: int = 0
    elapsed: float = 0.0
    best_x: np.ndarray | None = None
    best: Outcome | None = None
    finished: str = ""
    log: list[dict] = field(default_factory=list)
    inner_start: np.ndarray | None = None
    history: list[tuple[np.ndarray, list[Outcome]]] = field(default_factory=list)


def merit(o: Outcome) -> float:
    """Ranks candidates for 'best so far': objective with soft constraints plus the cycle violation."""
    return o.cost + 1e3 * float(o.cycle @ o.cycle)


def augmented(o: Outcome, lam: np.ndarray, k: float) -> float:
    return o.cost + float(lam @ o.cycle) + k * float(o.cycle @ o.cycle)


class MethodOfMultipliers:
    def __init__(self, evaluate: Callable[[np.ndarray], list[Outcome]], settings: MomSettings, state: MomState):
        self.evaluate, self.s, self.state = evaluate, settings, state
        if state.lam is None:
            state.sigma = settings.sigma0

    def _new_es(self) -> cma.CMAEvolutionStrategy:
        st = self.state
        opts = {
            "bounds": [0, 1],
            "seed": self.s.seed + st.outer,
            "tolx": self.s.tol_x,
            "maxiter": self.s.inner_generations,
            "verbose": -9,
            "verb_log": 0,
            "verb_disp": 0,
            "tolfun": 0,
            "tolflatfitness": 1000,
        }
        if self.s.popsize:
            opts["popsize"] = self.s.popsize
        return cma.CMAEvolutionStrategy(np.clip(st.inner_start, 0, 1), st.sigma, opts)

    def budget_left(self) -> bool:
        st, s = self.state, self.s
        if s.max_evaluations is not None and st.evaluations >= s.max_evaluations:
            st.finished = "evaluation budget spent"
            return False
        if s.max_seconds is not None and st.elapsed >= s.max_seconds:
            st.finished = "time budget spent"
            return False
        return True

    def fitness(self, X: np.ndarray, outcomes: list[Outcome]) -> list[float]:
        """What CMA-ES minimizes this generation: the augmented Lagrangian W."""
        st = self.state
        lam = self.multipliers(outcomes[0].cycle)
        return [augmented(o, lam, st.k) for o in outcomes]

    def multipliers(self, like: np.ndarray) -> np.ndarray:
        return self.state.lam if self.state.lam is not None else np.zeros_like(like)

    def generation(self) -> dict:
        """One CMA generation of the current inner run; returns its log row."""
        st = self.state
        t0 = time.perf_counter()
        X = np.array(st.es.ask())
        outcomes = self.evaluate(X)
        W = self.tell(X, outcomes)
        st.history.append((X, outcomes))
        st.generation += 1
        st.evaluations += len(X)
        i = int(np.argmin([merit(o) for o in outcomes]))
        if st.best is None or merit(outcomes[i]) < merit(st.best):
            st.best, st.best_x = outcomes[i], X[i].copy()
        st.elapsed += time.perf_counter() - t0
        row = {
            "generation": st.generation,
            "outer": st.outer,
            "evaluations": st.evaluations,
            "best_cost": st.best.cost,
            "best_violation": st.best.violation,
            "generation_best_W": float(min(W)),
            "sigma": float(st.es.sigma),
            "k": st.k,
            "lambda_norm": float(np.linalg.norm(self.multipliers(outcomes[0].cycle))),
            "fallen": int(sum(o.fell for o in outcomes)),
            "seconds": st.elapsed,
        }
        st.log.append(row)
        return row

    def tell(self, X: np.ndarray, outcomes: list[Outcome]) -> list[float]:
        """Pass one generation's outcomes to CMA-ES; returns the fitness values it was given."""
        W = self.fitness(X, outcomes)
        self.state.es.tell(list(X), W)
        return W

    def start_inner_run(self) -> None:
        """A new CMA-ES run from the best solution so far (or the start point)."""
        st = self.state
        st.inner_start = (st.best_x if st.best_x is not None else st.x_start).copy()
        st.history = []
        st.es = self._new_es()

    def replay(self) -> None:
        """Rebuild the CMA object of a resumed inner run by telling it the recorded generations again."""
        st = self.state
        st.es = self._new_es()
        for X, outcomes in st.history:
            asked = np.array(st.es.ask())
            if asked.shape != X.shape or not np.array_equal(asked, X):
                from eigengait.errors import UserInputError

                raise UserInputError(
                    "the checkpoint does not replay to the same candidates",
                    fix="resume with the same eigengait and cma versions, or start a new run",
                )
            self.tell(X, outcomes)

    def end_inner_run(self) -> None:
        """Multiplier update and the next inner run's σ and k."""
        st, s = self.state, self.s
        phi = st.best.cycle
        st.lam = (st.lam if st.lam is not None else np.zeros_like(phi)) + 2 * st.k * phi
        st.k = s.penalty
        st.sigma = max(s.sigma_floor, st.sigma * s.sigma_decay)
        st.outer += 1
        st.es = None
        st.history = []

    def step(self) -> dict | None:
        """Advance by one generation (starting or ending inner runs as needed); None when finished."""
        st, s = self.state, self.s
        if st.finished:
            return None
        if st.best is not None and not st.best.fell and st.best.violation < s.cycle_tolerance:
            st.finished = "cyclic"
            return None
        if not self.budget_left():
            return None
        if st.es is None and st.history:
            self.replay()
        if st.es is None:
            if st.outer >= s.max_outer:
                st.finished = "outer iteration limit"
                return None
            self.start_inner_run()
        row = self.generation()
        if st.es.stop():
            self.end_inner_run()
        return row
