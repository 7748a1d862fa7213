"""Method of multipliers around CMA-ES (thesis §4.4), with checkpoints after every generation.

Outer loop: W(x, λ, k) = f(x) + λᵀφ(x) + k φᵀφ; each inner CMA-ES run minimizes W; then λ ← λ +
2kφ(x*). The first inner run uses λ = 0, k = 0, later ones k = `penalty`. σ₀ = 0.3 then σ ← 0.7σ per
inner run (floor 0.001). An inner run stops at stopTolX 1e-4 or its generation cap; the outer loop
stops when every |φ_i| is below the tolerance, after `max_outer` inner runs, or when the
evaluation/time budget is spent.

`ConstrainedSearch` is what the method of multipliers shares with pycma's adaptive augmented
Lagrangian (`optimize.adaptive_al`): restarted inner CMA-ES runs, their state and checkpoint replay,
and the stopping rules.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, ClassVar

import cma
import numpy as np

from eigengait.optimize.evaluate import Outcome


@dataclass
class CmaOptions:
    """The options of every inner CMA-ES run (pycma's option names in brackets); parameters are
    normalized to [0, 1]."""

    seed: int = 1  # [seed] of the first inner run; the i-th later one uses seed + i
    sigma0: float = 0.3  # step size of the first inner run
    sigma_decay: float = 0.7  # each later inner run starts with the previous step size times this
    sigma_floor: float = 0.001  # smallest step size an inner run starts with
    tol_x: float = 1e-4  # [tolx] an inner run stops when its steps in x are all below this
    tol_fun: float = 0.0  # [tolfun] ... or when its recent fitness range is below this (0: never)
    # [tolflatfitness] ... or after this many generations of flat fitness
    tol_flat_fitness: int = 1000
    inner_generations: int = 1000  # [maxiter] ... or after this many generations
    popsize: int | None = None  # [popsize] candidates per generation (None: pycma's 4 + 3 ln n)

    def pycma_options(self, run: int) -> dict:
        """pycma's options of inner run `run` (0 for the first), bounded to [0, 1] and silent."""
        opts = {
            "bounds": [0, 1],
            "seed": self.seed + run,
            "tolx": self.tol_x,
            "maxiter": self.inner_generations,
            "verbose": -9,
            "verb_log": 0,
            "verb_disp": 0,
            "tolfun": self.tol_fun,
            "tolflatfitness": self.tol_flat_fitness,
        }
        if self.popsize:
            opts["popsize"] = self.popsize
        return opts


@dataclass
class SearchSettings(CmaOptions):
    """The inner runs' options and the outer loop's stopping rules, read by both constrained
    methods."""

    max_outer: int = 20  # inner runs at most
    cycle_tolerance: float = 0.2  # |φ_i| below this on every component: cyclic
    max_evaluations: int | None = None
    max_seconds: float | None = None


@dataclass
class MomSettings(SearchSettings):
    """The method of multipliers: the shared search settings plus its penalty."""

    method: ClassVar[str] = "mom"
    penalty: float = 0.1  # k after the first inner run


@dataclass
class MomState:
    """Everything needed to resume: multipliers, penalty, best so far, counters, and the current
    inner run as data (its start point and every generation's candidates and outcomes; see
    `optimize.checkpoint`). The CMA object `es` and the adaptive AL's fitness `al` are not saved:
    they are rebuilt by replaying that data."""

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
    # adaptive AL only: its fitness, with pycma's multipliers and penalties
    al: object | None = None


def merit(o: Outcome) -> float:
    """Ranks candidates for 'best so far': objective with soft constraints plus the cycle
    violation."""
    return o.cost + 1e3 * float(o.cycle @ o.cycle)


def augmented(o: Outcome, lam: np.ndarray, k: float) -> float:
    return o.cost + float(lam @ o.cycle) + k * float(o.cycle @ o.cycle)


class ConstrainedSearch:
    """Inner CMA-ES runs, each from the best solution so far, minimizing a fitness that handles the
    cyclic constraint; subclasses define that fitness and what changes between inner runs."""

    def __init__(
        self,
        evaluate: Callable[[np.ndarray], list[Outcome]],
        settings: SearchSettings,
        state: MomState,
    ):
        self.evaluate, self.s, self.state = evaluate, settings, state
        if state.generation == 0:  # a new search; a resumed one keeps its σ
            state.sigma = settings.sigma0

    def _new_es(self) -> cma.CMAEvolutionStrategy:
        st = self.state
        return cma.CMAEvolutionStrategy(
            np.clip(st.inner_start, 0, 1), st.sigma, self.s.pycma_options(st.outer)
        )

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
        """What CMA-ES minimizes this generation."""
        raise NotImplementedError

    def multipliers(self, like: np.ndarray) -> np.ndarray:
        """The current Lagrange multipliers (logged as their norm); `like` is a constraint
        vector."""
        raise NotImplementedError

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
        """Rebuild the CMA object of a resumed inner run by telling it the recorded generations
        again."""
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
        """The next inner run's σ; subclasses update their multipliers first."""
        st = self.state
        st.sigma = max(self.s.sigma_floor, st.sigma * self.s.sigma_decay)
        st.outer += 1
        st.es = None
        st.history = []

    def step(self) -> dict | None:
        """Advance by one generation (starting or ending inner runs as needed); None when
        finished."""
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


class MethodOfMultipliers(ConstrainedSearch):
    """The thesis's method of multipliers: W with fixed λ and k per inner run, both updated between
    runs."""

    s: MomSettings

    def fitness(self, X: np.ndarray, outcomes: list[Outcome]) -> list[float]:
        """The augmented Lagrangian W."""
        lam = self.multipliers(outcomes[0].cycle)
        return [augmented(o, lam, self.state.k) for o in outcomes]

    def multipliers(self, like: np.ndarray) -> np.ndarray:
        return self.state.lam if self.state.lam is not None else np.zeros_like(like)

    def end_inner_run(self) -> None:
        """Multiplier update, then the next inner run's k and σ."""
        st = self.state
        phi = st.best.cycle
        st.lam = (st.lam if st.lam is not None else np.zeros_like(phi)) + 2 * st.k * phi
        st.k = self.s.penalty
        super().end_inner_run()
