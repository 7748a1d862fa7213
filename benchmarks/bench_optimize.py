"""Wall-clock from the basic-run sketch to a cyclic gait, on this machine's cores.

Runs `eigengait optimize basic-run` for at most `--minutes` (default 10) and reports, from the run's log, when the
best controller's cycle violation max|φᵢ| first fell below each tolerance, with the evaluations spent. The same
process first times one population's evaluation as the unit cost (the baseline).
"""

from __future__ import annotations

import argparse
import csv
import tempfile
import time
from pathlib import Path

import numpy as np

from eigengait.control.library import resolve
from eigengait.control.sketch import load_sketch
from eigengait.optimize.evaluate import BatchEvaluator
from eigengait.optimize.mom import MomSettings
from eigengait.optimize.problem import Problem
from eigengait.optimize.run import optimize

TOLERANCES = (1.0, 0.5, 0.3, 0.2, 0.1, 0.05)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=0.05)
    args = parser.parse_args()
    sketch = load_sketch(resolve("sketch", "basic-run"))
    problem = Problem.from_sketch(sketch)
    evaluator = BatchEvaluator(problem.system, problem.space, sketch.targets)
    X = np.tile(problem.space.initial(), (4 + int(3 * np.log(problem.space.size)), 1))
    start = time.perf_counter()
    evaluator.evaluate(X)
    unit = time.perf_counter() - start
    print(f"one population of {len(X)} candidates: {unit:.3f} s (baseline unit)")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "run"
        state = optimize(sketch, folder, MomSettings(seed=args.seed, max_seconds=args.minutes * 60,
                                                     inner_generations=100, cycle_tolerance=args.tolerance),
                         progress=False)
        rows = list(csv.DictReader(open(folder / "log.csv")))
    print(f"stopped: {state.finished} after {state.elapsed:.0f} s, {state.evaluations} evaluations, "
          f"best violation {state.best.violation:.3f}, speed {state.best.mean_velocity[0]:.2f} m/s")
    for tol in TOLERANCES:
        hit = next((r for r in rows if float(r["best_violation"]) < tol), None)
        if hit:
            s = float(hit["seconds"])
            print(f"violation < {tol:<4}: {s:6.0f} s ({s / unit:6.0f} population units), "
                  f"{hit['evaluations']} evaluations")
        else:
            print(f"violation < {tol:<4}: not reached in {args.minutes:g} min")


if __name__ == "__main__":
    main()
