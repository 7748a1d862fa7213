"""Wall-clock from the basic-run sketch to a closed-loop gait, on this machine's cores.

Runs the two-stage optimization of `eigengait optimize basic-run` for at most `--minutes`
(default 20) and reports, from each stage's log, when the best controller's cycle violation max|φᵢ|
first fell below each tolerance, with the evaluations spent; then plays the result 20 cycles with no
reset and prints its survival and gait quality. The same process first times one closed-loop
population's evaluation as the unit cost (the baseline).
"""

from __future__ import annotations

import argparse
import csv
import tempfile
from pathlib import Path


from eigengait.control.library import resolve
from eigengait.control.sketch import load_sketch
from eigengait.optimize.mom import MomSettings
from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_parameters
from eigengait.control.playback import play
from eigengait.optimize.staged import STAGE_ONE, optimize_gait
from population_unit import population_seconds

TOLERANCES = (1.0, 0.5, 0.3, 0.2, 0.1, 0.05)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--minutes", type=float, default=20.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=0.05)
    args = parser.parse_args()
    sketch = load_sketch(resolve("sketch", "basic-run"))
    unit, size = population_seconds(sketch)
    print(f"one population of {size} candidates: {unit:.3f} s (baseline unit)")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "run"
        state = optimize_gait(
            sketch,
            folder,
            MomSettings(
                seed=args.seed,
                max_seconds=args.minutes * 60,
                inner_generations=100,
                cycle_tolerance=args.tolerance,
            ),
            progress=False,
        )
        stages = {
            "open loop, 1 cycle": list(csv.DictReader(open(folder / STAGE_ONE / "log.csv"))),
            f"closed loop, {sketch.feedback.horizon_cycles} cycles": list(
                csv.DictReader(open(folder / "log.csv"))
            ),
        }
        controller = load_controller(folder / "best_controller.json")
    print(
        f"stopped: {state.finished} after {state.elapsed:.0f} s, {state.evaluations} evaluations, "
        f"best violation {state.best.violation:.3f}, speed {state.best.mean_velocity[0]:.2f} m/s"
    )
    offset = 0.0
    for name, rows in stages.items():
        print(f"stage: {name}")
        for tol in TOLERANCES:
            hit = next((r for r in rows if float(r["best_violation"]) < tol), None)
            if hit:
                s = offset + float(hit["seconds"])
                print(
                    f"  violation < {tol:<4}: {s:6.0f} s from the sketch ({s / unit:6.0f} "
                    f"population units), {hit['evaluations']} evaluations in the stage"
                )
            else:
                print(f"  violation < {tol:<4}: not reached")
        offset += float(rows[-1]["seconds"]) if rows else 0.0
    system = gait_system(controller)
    result = play(system, to_parameters(controller, system), cycles=20)
    print("played 20 cycles, no reset:", result.summary())


if __name__ == "__main__":
    main()
