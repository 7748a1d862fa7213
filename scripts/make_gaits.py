"""Regenerate the shipped optimized gaits in src/eigengait/data/gaits/ with eigengait's own
optimizer.

Usage: python scripts/make_gaits.py [GAIT ...] [--evaluations N] [--max-outer N] [--runs DIR]
[--harden-minutes M [--event]] [--harden-only | --measure-only] [--as-is] [--servo]. Each gait is a
sketch preset optimized from a fixed seed, then (with --harden-minutes) hardened against falls under
sampled pushes (`eigengait harden`, optimize/survival.py; with --event by searching event feedback,
`harden --event`, in two stages); the best controller is copied into the
package with its playback metrics. `--harden-only` hardens the shipped gaits as they are,
`--measure-only` re-measures them (`--as-is`: only with their own motor activation time;
`--servo`: each also with the swing-foot servo). Runs are kept in DIR (default out/gait-runs) and
resume if interrupted.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

from eigengait.control.binding import gait_system
from eigengait.control.controller import (
    LookaheadFile,
    load_controller,
    save_controller,
    sketch_modes,
    to_parameters,
)
from eigengait.control.gait_targets import PUSHED, targets
from eigengait.control.library import resolve
from eigengait.control.playback import play, push_robustness
from eigengait.control.sketch import load_sketch
from eigengait.control.sketch_character import sketch_character
from eigengait.control.swing_servo import ServoSettings
from eigengait.optimize.mom import MomSettings
from eigengait.optimize.staged import optimize_gait
from eigengait.optimize.survival import (
    CHECKPOINT,
    StartingFigures,
    SurvivalSettings,
    harden,
    harden_event_in_stages,
)
from eigengait.sim.build import build_fingerprint

GAITS = {
    "humanoid-basic-run": "basic-run",
    "monster-run": "monster",
    "kangaroo-hop": "kangaroo",
    "dog-trot": "dog-trot",
    "planar-walker-walk": "planar-walker",
    "humanoid-lateral-sway": "lateral-sway",
    "humanoid-vertical-rotation": "vertical-rotation",
    "humanoid-skipping": "skipping",
    "humanoid-crouched": "crouched",
    "humanoid-legs-apart": "legs-apart",
    "humanoid-one-foot-hop": "one-foot-hop",
    "humanoid-random-1": "random-1",
    "humanoid-random-2": "random-2",
    "monster-crossed-arms": "monster-crossed-arms",
    "humanoid-canonical-basis": "canonical-basis",
    "humanoid-trivial-selection": "trivial-selection",
}
# prefix of the figures of the same gait played without its lookahead
WITHOUT = "without_lookahead_"
PACKAGE = Path(__file__).resolve().parents[1] / "src" / "eigengait" / "data" / "gaits"
# s: the motor lag every gait is also measured with (docs/locomotion.md, "Motor activation")
ACTIVATION_TIME = 0.04
# each gait's full playback summaries, read by scripts/gait_table.py
MEASURES = Path("out/gait-measures")
# cycles the lookahead's plans reach when its two-cycle plans let the gait fall (docs/locomotion.md,
# "A longer look for the gaits that fall")
LONG_HORIZON = 4.0
# the plans' speed weight tried when a gait falls short of its speed target (docs/locomotion.md,
# "Holding the target speed harder")
STRONG_SPEED_WEIGHT = 10.0
CYCLES = 20  # cycles each gait is played for its figures


def make(
    gait: str,
    evaluations: int,
    runs: Path,
    seed: int,
    max_outer: int,
    minutes: float | None,
    horizon: int | None,
):
    sketch_path = resolve("sketch", GAITS[gait])
    folder = runs / gait
    resume = folder.exists()
    sketch = load_sketch(sketch_path)
    if horizon:
        sketch.feedback.horizon_cycles = horizon
    state = optimize_gait(
        sketch,
        folder,
        MomSettings(
            seed=seed,
            max_evaluations=evaluations,
            inner_generations=100,
            max_seconds=minutes * 60 if minutes else None,
            max_outer=max_outer,
            cycle_tolerance=sketch.targets.cycle_tolerance,
        ),
        resume=resume,
        sketch_source=sketch_path,
    )
    controller = load_controller(folder / "best_controller.json")
    controller.name = gait
    controller.metrics = {
        "cycle_tolerance": sketch.targets.cycle_tolerance,
        "evaluations": state.evaluations,
        "optimizer_seconds": round(state.elapsed, 1),
        "horizon_cycles": sketch.feedback.horizon_cycles,
    }
    return controller


def hardened(controller, folder: Path, minutes: float, seed: int):
    """The controller after `minutes` of survival optimization in `folder` (resumed if
    interrupted)."""
    system = gait_system(controller)
    start = to_parameters(controller, system)
    before = play(system, start, cycles=CYCLES)
    figures = StartingFigures.of(before)
    settings = SurvivalSettings(minutes=minutes, seed=seed)
    planner = controller.planner()
    resume = (folder / CHECKPOINT).exists()
    harden(
        system,
        start,
        figures,
        folder,
        settings,
        resume,
        controller.name,
        lookahead=planner,
        sketch=controller.sketch,
        timing=load_sketch(resolve("sketch", GAITS[controller.name])).timing,
    )
    return hardened_result(controller, folder / "best_controller.json", minutes)


def event_hardened(controller, folder: Path, minutes: float, seed: int):
    """The controller after `minutes` of event-feedback search in `folder`
    (`survival.harden_event_in_stages`, on every core; resumed if interrupted); it plays without
    lookahead."""
    sketch = load_sketch(resolve("sketch", GAITS[controller.name]))
    system = gait_system(controller)
    harden_event_in_stages(
        system,
        to_parameters(controller, system),
        sketch,
        folder,
        minutes,
        seed,
        os.cpu_count() or 1,
        controller.name,
        controller.sketch,
    )
    return hardened_result(controller, folder / "stage2" / "best_controller.json", minutes)


def hardened_result(controller, path: Path, minutes: float):
    """The hardened controller saved at `path`, named as `controller` and carrying its metrics, its
    `hardening_minutes` grown by `minutes` (earlier hardening of the start included)."""
    out = load_controller(path)
    spent = controller.metrics.get("hardening_minutes", 0.0) + minutes
    out.name, out.metrics = controller.name, {**controller.metrics, "hardening_minutes": spent}
    return out


def played(controller) -> dict:
    """The controller played `CYCLES` cycles with physics only, without and with its lookahead (if
    that falls, once more with plans `LONG_HORIZON` cycles long, kept if it survives longer; if it
    falls short of its speed target, once more with the plans' speed term weighted
    `STRONG_SPEED_WEIGHT`, kept if that meets more of its targets); the lookahead is kept
    (`lookahead` None otherwise) only if it survives at least as long as the pulses alone. Returns
    the figures and what was kept."""
    system = gait_system(controller)
    params = to_parameters(controller, system)

    def figures(lookahead: LookaheadFile | None) -> dict:
        """The play's summary and sketch character, with `lookahead` (None: the pulses alone)."""
        planner = lookahead.settings(controller.sketch) if lookahead is not None else None
        result = play(system, params, cycles=CYCLES, lookahead=planner)
        return {
            **result.summary(),
            **sketch_character(system, params, controller.sketch, result.torques),
        }

    alone = figures(None)
    lookahead = controller.lookahead
    if lookahead is None:  # event feedback: its pulses are what plays
        return {
            "system": system,
            "params": params,
            "alone": alone,
            "free": alone,
            "lookahead": None,
        }
    free = figures(lookahead)
    if free["cycles_completed"] < CYCLES and lookahead.horizon_cycles < LONG_HORIZON:
        longer = lookahead.model_copy(update={"horizon_cycles": LONG_HORIZON})
        further = figures(longer)
        if further["cycles_completed"] > free["cycles_completed"]:
            lookahead, free = longer, further
    if short_of_speed(controller.name, free):
        harder = lookahead.model_copy(update={"speed_weight": STRONG_SPEED_WEIGHT})
        faster = figures(harder)
        if met(controller.name, faster) > met(controller.name, free):
            lookahead, free = harder, faster
    if free["cycles_completed"] < alone["cycles_completed"]:
        lookahead, free = None, alone
    return {
        "system": system,
        "params": params,
        "alone": alone,
        "free": free,
        "lookahead": lookahead,
    }


def met(name: str, figures: dict) -> tuple[int, int]:
    """(cycles survived, targets met, pushes aside) of `figures`, compared in that order."""
    return figures["cycles_completed"], sum(targets(name, figures, None).values())


def short_of_speed(name: str, figures: dict) -> bool:
    """Whether the gait `name` has a speed target and `figures` miss it."""
    return any(
        key.startswith("speed") and not ok for key, ok in targets(name, figures, None).items()
    )


def rank(name: str, play: dict) -> tuple:
    """Longer survival first, then more pushes survived (gaits with a push target), then more of
    the locomotion targets met (`gait_targets`), then the smaller largest frame jump."""
    return (
        play["free"]["cycles_completed"],
        sum(play.get("pushes") or ()),
        sum(targets(name, play["free"], play.get("pushes")).values()),
        -(play["free"]["max_frame_jump_deg"] or 0.0),
    )


def measure(controller, as_is: bool = False, servo: bool = False) -> None:
    """Play the controller as it is and (unless `as_is`) with its motors' activation time switched
    (`ACTIVATION_TIME` when it has none, none when it has one), and (with `servo`) each of these
    with and without the swing-foot servo, each with its lookahead (given the sketch's mean speed as
    its target if it has none) and without; push the longest survivors of the gaits that have a
    push target; ship the variant that survives longest (then: the most pushes, the most targets
    met, the smaller frame jumps), with its lookahead only if that survives at least as long; record
    the figures."""
    sketch = load_sketch(resolve("sketch", GAITS[controller.name]))
    controller.sketch = sketch_modes(sketch)
    if controller.lookahead is None and controller.feedback.event is None:
        controller.lookahead = LookaheadFile(speed=sketch.targets.mean_speed)
    switched = None if controller.activation_time is not None else ACTIVATION_TIME
    taus = (controller.activation_time,) if as_is else (controller.activation_time, switched)
    servos = (None, ServoSettings()) if servo else (controller.swing_servo,)
    variants = {
        (tau, s): controller.model_copy(update={"activation_time": tau, "swing_servo": s})
        for tau in taus
        for s in servos
    }
    plays = {key: played(c) for key, c in variants.items()}
    longest = max(run["free"]["cycles_completed"] for run in plays.values())
    for key, run in plays.items():
        variants[key].lookahead = run["lookahead"]
        # only the longest survivors can be shipped, so only they are pushed
        if controller.name in PUSHED and run["free"]["cycles_completed"] == longest:
            run["pushes"] = push_robustness(
                run["system"], run["params"], lookahead=variants[key].planner()
            )
        print(
            f"{controller.name}: activation time {key[0]}, swing servo {key[1] is not None}: "
            f"{run['free']['cycles_completed']} cycles, jump {run['free']['max_frame_jump_deg']}°, "
            f"slip {run['free']['stance_slip_max_m']} m, pushes {run.get('pushes')}, "
            f"lookahead {run['lookahead'] is not None}"
        )
    ship(controller.name, variants, plays)


def ship(name: str, variants: dict, plays: dict) -> None:
    """Copy the best-ranked of the played `variants` ((activation time, servo) -> controller;
    `plays`: their figures, as `measure` collects them) into the package with its figures, and
    record every variant's figures in `MEASURES`."""
    chosen = max(plays, key=lambda key: rank(name, plays[key]))
    controller, best = variants[chosen], plays[chosen]
    alone, free, pushes = best["alone"], best["free"], best.get("pushes")
    kept = {
        k: controller.metrics[k]
        for k in (
            "cycle_tolerance",
            "evaluations",
            "optimizer_seconds",
            "horizon_cycles",
            "hardening_minutes",
        )
        if k in controller.metrics
    }
    numbers = lambda summary: {  # noqa: E731
        k: v for k, v in summary.items() if isinstance(v, (int, float, bool)) and v is not None
    }
    controller.metrics = numbers(free)
    controller.metrics.update(
        {f"{WITHOUT}{k}": v for k, v in numbers(alone).items() if k != "lookahead"}
    )
    controller.metrics.update(kept)
    controller.measured_on = build_fingerprint()
    if pushes is not None:
        controller.metrics["pushes_survived_of_5"] = sum(pushes)
    save_controller(controller, PACKAGE / f"{controller.name}.json")
    MEASURES.mkdir(parents=True, exist_ok=True)
    record = {
        "played": free,
        "without_lookahead": alone,
        "pushes": pushes,
        "activation_time": chosen[0],
        "swing_servo": chosen[1] is not None,
        "other_variants": [
            {
                "activation_time": key[0],
                "swing_servo": key[1] is not None,
                "played": plays[key]["free"],
                "pushes": plays[key].get("pushes"),
            }
            for key in plays
            if key != chosen
        ],
    }
    (MEASURES / f"{controller.name}.json").write_text(
        json.dumps(record, indent=1), encoding="utf-8"
    )
    print(json.dumps({"gait": controller.name, **controller.metrics}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("gaits", nargs="*", default=list(GAITS))
    parser.add_argument("--evaluations", type=int, default=10000)
    parser.add_argument("--runs", type=Path, default=Path("out/gait-runs"))
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--max-outer", type=int, default=20, help="multiplier iterations at most")
    parser.add_argument("--minutes", type=float, default=None, help="wall-clock budget per gait")
    parser.add_argument(
        "--horizon", type=int, default=None, help="cycles per candidate (default: the sketch's)"
    )
    parser.add_argument(
        "--harden-minutes", type=float, default=0.0, help="survival optimization after (min)"
    )
    parser.add_argument(
        "--event",
        action="store_true",
        help="harden by searching event feedback (two stages; the gait then has no lookahead)",
    )
    parser.add_argument(
        "--harden-only", action="store_true", help="harden the shipped gaits (no optimization)"
    )
    parser.add_argument(
        "--measure-only", action="store_true", help="re-measure the shipped gaits (no optimization)"
    )
    parser.add_argument(
        "--as-is",
        action="store_true",
        help="measure only the gait's own motor activation time (not also the switched one)",
    )
    parser.add_argument(
        "--servo",
        action="store_true",
        help="measure each variant also with the swing-foot servo (control/swing_servo.py)",
    )
    args = parser.parse_args()
    for gait in args.gaits:
        if args.measure_only:
            measure(load_controller(PACKAGE / f"{gait}.json"), args.as_is, args.servo)
            continue
        if args.harden_only:
            controller = load_controller(PACKAGE / f"{gait}.json")
        else:
            controller = make(
                gait,
                args.evaluations,
                args.runs,
                args.seed,
                args.max_outer,
                args.minutes,
                args.horizon,
            )
        if args.harden_minutes and args.event:
            controller = event_hardened(
                controller, args.runs / gait / "event", args.harden_minutes, args.seed
            )
        elif args.harden_minutes:
            controller = hardened(
                controller, args.runs / gait / "hardened", args.harden_minutes, args.seed
            )
        measure(controller, args.as_is, args.servo)


if __name__ == "__main__":
    main()
