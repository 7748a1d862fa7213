"""Ablation of the balance feedback: one open-loop gait, then the closed-loop stage with each
mechanism.

Stage 1 (open loop, one cycle) runs once for `--stage1-minutes`; from its best, stage 2 (five
cycles, no reset) runs for `--minutes` with no feedback, `hip`, `modal` and both, same seed. Each
result is played 20 cycles with no reset and pushed sideways (0.5 N·s/kg at five phases of cycle 3,
ten cycles after). One row per setting: stage-2 parameters, best cycle violation, when the tolerance
was met, cycles survived, pushes survived, speed. The open-loop row is the baseline.

Usage: python benchmarks/bench_feedback.py [--sketch kangaroo] [--stage1-minutes 6] [--minutes 6]
[--seed 1]
"""

from __future__ import annotations

import argparse
import csv
import tempfile
from pathlib import Path

from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_parameters
from eigengait.control.library import resolve
from eigengait.control.playback import play, push_robustness
from eigengait.control.sketch import load_sketch
from eigengait.optimize.mom import MomSettings
from eigengait.optimize.run import optimize
from eigengait.optimize.staged import closed_loop_stage, open_loop_sketch

SETTINGS = {"open loop": [], "hip": ["hip"], "modal": ["modal"], "hip + modal": ["hip", "modal"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--sketch", default="kangaroo")
    parser.add_argument("--stage1-minutes", type=float, default=6.0)
    parser.add_argument("--minutes", type=float, default=6.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--only", nargs="*", default=list(SETTINGS))
    args = parser.parse_args()
    sketch = load_sketch(resolve("sketch", args.sketch))
    settings = MomSettings(
        seed=args.seed, inner_generations=100, cycle_tolerance=sketch.targets.cycle_tolerance
    )
    with tempfile.TemporaryDirectory() as tmp:
        first = optimize(
            open_loop_sketch(sketch),
            Path(tmp) / "open-loop",
            MomSettings(**{**settings.__dict__, "max_seconds": args.stage1_minutes * 60}),
            progress=False,
        )
        print(
            f"{args.sketch}, seed {args.seed}: stage 1 {first.elapsed:.0f} s, {first.evaluations} "
            f"evaluations, violation {first.best.violation:.3f}; stage 2 {args.minutes:g} min per "
            "setting"
        )
        print(
            "| feedback | gains | best violation | cyclic after | cycles survived (of 20) | "
            "pushes survived (of 5) | speed (m/s) |"
        )
        print("|---|---:|---:|---:|---:|---:|---:|")
        for name in args.only:
            variant = sketch.model_copy(deep=True)
            variant.feedback.mechanisms = SETTINGS[name]
            folder = Path(tmp) / name.replace(" ", "")
            state = closed_loop_stage(
                variant,
                folder,
                MomSettings(**{**settings.__dict__, "max_seconds": args.minutes * 60}),
                first,
                progress=False,
            )
            rows = list(csv.DictReader(open(folder / "log.csv")))
            controller = load_controller(folder / "best_controller.json")
            system = gait_system(controller)
            params = to_parameters(controller, system)
            result = play(system, params, cycles=20)
            pushes = push_robustness(system, params)
            hit = next(
                (r for r in rows if float(r["best_violation"]) < sketch.targets.cycle_tolerance),
                None,
            )
            cyclic = f"{float(hit['seconds']):.0f} s" if hit else "not reached"
            gains = len(state.x_start) - len(first.x_start)
            print(
                f"| {name} | {gains} | {state.best.violation:.3f} | {cyclic} | "
                f"{result.cycles_completed} | {sum(pushes)} | {result.mean_speed_mps:.2f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
