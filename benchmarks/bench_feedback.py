"""Ablation of the balance feedback: the same sketch optimized with no feedback and with each mechanism.

For each setting (open loop, `hip`, `modal`, both) the sketch is optimized with the same seed and wall-clock
budget, then its best controller is played 20 cycles with no reset and pushed sideways (0.5 N·s/kg at five phases
of cycle 3, ten cycles after). Prints one row per setting: evaluations and seconds until the cycle tolerance was
met (if it was), the best violation, cycles survived, pushes survived and speed. The baseline is the open-loop row.

Usage: python benchmarks/bench_feedback.py [--sketch basic-run] [--minutes 8] [--seed 1]
"""

from __future__ import annotations

import argparse
import csv
import tempfile
from pathlib import Path

from eigengait.control.controller import load_controller, system_for, to_parameters
from eigengait.control.library import resolve
from eigengait.control.playback import play, push_robustness
from eigengait.control.sketch import load_sketch
from eigengait.optimize.mom import MomSettings
from eigengait.optimize.staged import optimize_gait

SETTINGS = {"open loop": [], "hip": ["hip"], "modal": ["modal"], "hip + modal": ["hip", "modal"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--sketch", default="basic-run")
    parser.add_argument("--minutes", type=float, default=8.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--only", nargs="*", default=list(SETTINGS))
    args = parser.parse_args()
    print(f"{args.sketch}, seed {args.seed}, {args.minutes:g} min each")
    print("| feedback | parameters | cyclic after | best violation | cycles survived (of 20) | pushes survived "
          "(of 5) | speed (m/s) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name in args.only:
        sketch = load_sketch(resolve("sketch", args.sketch))
        sketch.feedback.mechanisms = SETTINGS[name]
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(tmp) / "run"
            state = optimize_gait(sketch, folder, MomSettings(seed=args.seed, max_seconds=args.minutes * 60,
                                                         inner_generations=100,
                                                         cycle_tolerance=sketch.targets.cycle_tolerance),
                             progress=False)
            rows = list(csv.DictReader(open(folder / "log.csv")))
            controller = load_controller(folder / "best_controller.json")
        system = system_for(controller)
        params = to_parameters(controller, system)
        result = play(system, params, cycles=20)
        pushes = push_robustness(system, params)
        hit = next((r for r in rows if float(r["best_violation"]) < sketch.targets.cycle_tolerance), None)
        cyclic = f"{float(hit['seconds']):.0f} s, {hit['evaluations']} ev." if hit else "not reached"
        size = len(state.x_start)
        print(f"| {name} | {size} | {cyclic} | {state.best.violation:.3f} | {result.cycles_completed} | "
              f"{sum(pushes)} | {result.mean_speed_mps:.2f} |", flush=True)


if __name__ == "__main__":
    main()
