"""Play every shipped gait 20 cycles with physics only and print its quality against the locomotion
targets.

Usage: python scripts/gait_table.py [--recorded DIR] [GAIT ...] (prints a Markdown table and,
below it, each failed target; the swing clearance column is the lowest of the feet's mean swing
clearances, "none" when a foot never lifts). Each gait is played with its lookahead and pushed, or,
with --recorded, read from what `scripts/make_gaits.py --measure-only` recorded in DIR
(out/gait-measures).
The targets are `control/gait_targets.py`'s (docs/locomotion.md).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from eigengait.control.binding import gait_system
from eigengait.control.controller import LookaheadFile, load_controller, to_parameters
from eigengait.control.library import gait_names, resolve
from eigengait.control.gait_targets import targets
from eigengait.control.playback import play, push_robustness

DEFAULT = LookaheadFile(speed=0.0)


def lookahead_label(lookahead: LookaheadFile) -> str:
    """The gait table's label for `lookahead`: the plans' length and speed weight where they are not
    the defaults."""
    notes = []
    if lookahead.horizon_cycles != DEFAULT.horizon_cycles:
        notes.append(f"{lookahead.horizon_cycles:g} cycles")
    if lookahead.speed_weight != DEFAULT.speed_weight:
        notes.append(f"speed weight {lookahead.speed_weight:g}")
    return "lookahead" + (f" ({', '.join(notes)})" if notes else "")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("gaits", nargs="*", help="shipped gait names (default: all)")
    parser.add_argument("--recorded", type=Path, default=None)
    args = parser.parse_args()
    print(
        "| gait | played with | cycles | speed (m/s) | cadence (steps/min) | flight | "
        "swing clearance (m) | stance slip (m) | pitch (°) | roll (°) | max jump (°) | "
        "mean τ² ((N·m)²) | pushes (of 5) | targets met |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|---|---|---:|---:|---:|---|")
    failures = []
    for name in args.gaits or gait_names():
        controller = load_controller(resolve("gait", name))
        if args.recorded is not None:
            record = json.loads((args.recorded / f"{name}.json").read_text(encoding="utf-8"))
            m, pushes, lag = record["played"], record["pushes"], record.get("activation_time")
        else:
            system = gait_system(controller)
            params = to_parameters(controller, system)
            planner, lag = controller.planner(), controller.activation_time
            m = play(system, params, cycles=20, lookahead=planner).summary()
            pushes = push_robustness(system, params, lookahead=planner)
        met = targets(name, m, pushes)
        failures += [f"{name}: {k}" for k, ok in met.items() if not ok]
        pushed = "—" if pushes is None else sum(pushes)
        pitch = "{:.0f} … {:.0f}".format(*m["torso_pitch_deg"])
        roll = "{:.0f} … {:.0f}".format(*m["torso_roll_deg"])
        lifts = list(m["swing_clearance_m"].values())
        clearance = "none" if None in lifts else f"{min(lifts):.3f}"
        alone = "pulses, event feedback" if controller.feedback.event else "pulses"
        control = (lookahead_label(controller.lookahead) if m["lookahead"] else alone) + (
            f", {lag * 1000:.0f} ms lag" if lag else ""
        )
        print(
            f"| `{name}` | {control} | {m['cycles_completed']}{' (fell)' if m['fell'] else ''} | "
            f"{m['mean_speed_mps']:.2f} | "
            f"{m['cadence_spm']:.0f} | {m['flight_fraction']:.2f} | {clearance} | "
            f"{m['stance_slip_max_m']} | {pitch} | {roll} | {m['max_frame_jump_deg']:.1f} | "
            f"{m['mean_squared_torque']:.0f} | {pushed} | {sum(met.values())} of {len(met)} |"
        )
    print()
    for f in failures:
        print("not met:", f)


if __name__ == "__main__":
    main()
