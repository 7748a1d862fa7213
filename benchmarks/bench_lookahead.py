"""Lookahead on the shipped gaits: survival, gait quality, pushes and its cost against playing
without it.

Each shipped gait plays `--cycles` cycles with no reset, without its lookahead (the pulses and the
reflex feedback as optimized) and with it, then with it under the issue's push test (0.5 N·s/kg
sideways at five evenly spaced phases of cycle 3, ten cycles after). One row per gait and setting:
cycles survived, speed, flight fraction, cadence, mean stance slip, largest frame jump, torso pitch
and roll, pushes survived, and the wall time as a multiple of the played (simulated) time, the cost
of the decisions. `--seeds N` plays the lookahead with N planner seeds to show how much survival
hangs on one; `--feedback` plays each seed once more with the controller's balance feedback inside
the plans and the played motion (`LookaheadSettings.feedback`), the ablation of docs/locomotion.md;
`--min-mass-share S` plays each seed once more with the plans' torque on the light limbs scaled by
their subtree's share of the body's mass over S (`LookaheadSettings.min_mass_share`, 0: every joint
in full; docs/locomotion.md, "Light limbs planned in proportion to their mass").

Usage: python benchmarks/bench_lookahead.py [GAIT ...] [--cycles 20] [--seeds 1] [--feedback]
[--min-mass-share S] [--no-pushes]
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_parameters
from eigengait.control.library import gait_names, resolve
from eigengait.control.playback import play, push_robustness


def row(name: str, setting: str, result, wall: float, pushes: list[bool] | None) -> str:
    q = result.quality
    # a foot that never stood has no slip (None)
    slips = [v for v in q.get("stance_slip_m", {}).values() if v is not None]
    slip = np.mean(slips or [np.nan])
    played = len(result.qpos) / result.fps
    return (
        f"| {name} | {setting} | {result.cycles_completed} | {result.mean_speed_mps:.2f} | "
        f"{q.get('flight_fraction', float('nan')):.2f} | {q.get('cadence_spm', float('nan')):.0f} "
        f"| {slip:.3f} | {q.get('max_frame_jump_deg', float('nan')):.1f} | "
        f"{q.get('torso_pitch_deg')} | {q.get('torso_roll_deg')} | "
        f"{'-' if pushes is None else f'{sum(pushes)}/{len(pushes)}'} | "
        f"{wall / max(played, 1e-9):.1f}× |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("gaits", nargs="*", default=gait_names())
    parser.add_argument("--cycles", type=int, default=20)
    parser.add_argument("--seeds", type=int, default=1)
    parser.add_argument(
        "--feedback", action="store_true", help="also play with feedback inside the lookahead"
    )
    parser.add_argument(
        "--min-mass-share",
        type=float,
        default=None,
        help="also play with the light limbs planned in proportion to their mass over S",
    )
    parser.add_argument("--no-pushes", action="store_true")
    args = parser.parse_args()
    print(
        "| gait | setting | cycles | speed m/s | flight | cadence /min | stance slip m | "
        "max frame jump ° | torso pitch ° | torso roll ° | pushes | wall / played |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|---|---|---:|---:|")
    for name in args.gaits:
        controller = load_controller(resolve("gait", name))
        system = gait_system(controller)
        params = to_parameters(controller, system)
        t0 = time.perf_counter()
        alone = play(system, params, cycles=args.cycles)
        print(row(name, "without lookahead", alone, time.perf_counter() - t0, None), flush=True)
        if controller.lookahead is None:
            continue
        planned = controller.lookahead.min_mass_share
        shares = (planned,) if args.min_mass_share is None else (planned, args.min_mass_share)
        feedbacks = (False, True) if args.feedback else (controller.lookahead.feedback,)
        for seed in range(args.seeds):
            for feedback in feedbacks:
                for share in shares:
                    planner = dataclasses.replace(
                        controller.planner(), seed=seed, feedback=feedback, min_mass_share=share
                    )
                    t0 = time.perf_counter()
                    result = play(system, params, cycles=args.cycles, lookahead=planner)
                    wall = time.perf_counter() - t0
                    pushes = (
                        None
                        if args.no_pushes
                        else push_robustness(system, params, lookahead=planner)
                    )
                    label = (
                        f"lookahead{' + feedback' if feedback else ''}"
                        f"{f', light limbs planned by mass share / {share}' if share else ''}"
                        f" (seed {seed})"
                    )
                    print(row(name, label, result, wall, pushes), flush=True)


if __name__ == "__main__":
    main()
