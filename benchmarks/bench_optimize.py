"""Wall-clock from a sketch (default basic-run) to a closed-loop gait, on this machine's cores.

Runs the two-stage optimization of `eigengait optimize SKETCH` for at most `--minutes` (default
20) and reports, from each stage's log, when the best controller's cycle violation max|φᵢ| first
fell below each tolerance, with the evaluations spent; then plays the result 20 cycles with no
reset and prints its survival, gait quality and the shipped gait `--gait`'s targets it meets. With
`--event-minutes M` the result's event feedback is then searched for M minutes in two stages
(`survival.harden_event_in_stages`, as `scripts/make_gaits.py --event` does) and the same is
printed again after it, with the wall-clock from the sketch. The same process first times one
closed-loop population's evaluation as the unit cost (the baseline).

Usage: python benchmarks/bench_optimize.py [--sketch dog-trot --gait dog-trot] [--minutes 20]
[--event-minutes 36]
"""

from __future__ import annotations

import argparse
import csv
import os
import tempfile
import time
from pathlib import Path


from eigengait.control.library import resolve
from eigengait.control.sketch import load_sketch
from eigengait.optimize.mom import MomSettings
from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_parameters
from eigengait.control.gait_targets import PUSHED, targets
from eigengait.control.playback import play, push_robustness
from eigengait.optimize.survival import harden_event_in_stages
from eigengait.optimize.staged import STAGE_ONE, optimize_gait
from population_unit import population_seconds

TOLERANCES = (1.0, 0.5, 0.3, 0.2, 0.1, 0.05)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--minutes", type=float, default=20.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=0.05)
    parser.add_argument("--sketch", default="basic-run", help="sketch preset or file")
    parser.add_argument(
        "--gait", default="humanoid-basic-run", help="shipped gait whose targets are checked"
    )
    parser.add_argument("--event-minutes", type=float, default=0.0, help="event search after")
    args = parser.parse_args()
    sketch = load_sketch(resolve("sketch", args.sketch))
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
        system = gait_system(controller)
        params = to_parameters(controller, system)
        report("optimized", system, params, args.gait, state.elapsed)
        if args.event_minutes:
            t0 = time.perf_counter()
            params = harden_event_in_stages(
                system,
                params,
                sketch,
                Path(tmp) / "event",
                args.event_minutes,
                args.seed,
                os.cpu_count() or 1,
                progress=lambda _: None,
            )
            elapsed = state.elapsed + time.perf_counter() - t0
            report("event feedback searched", system, params, args.gait, elapsed)
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


def report(label: str, system, params, gait: str, seconds: float) -> None:
    """Play `params` 20 cycles with no reset (pushed when `gait` has a push target) and print its
    summary and `gait`'s targets met, `seconds` from the sketch."""
    summary = play(system, params, cycles=20).summary()
    pushes = push_robustness(system, params) if gait in PUSHED else None
    met = targets(gait, summary, pushes)
    print(f"{label}, {seconds:.0f} s from the sketch; played 20 cycles, no reset:", summary)
    print(f"  {gait}'s targets met: {sum(met.values())} of {len(met)}; not met:", end=" ")
    print(", ".join(k for k, ok in met.items() if not ok) or "none")


if __name__ == "__main__":
    main()
