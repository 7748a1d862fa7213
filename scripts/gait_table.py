"""Play every shipped gait 20 cycles with physics only and print its quality against the locomotion
targets.

Usage: python scripts/gait_table.py [--recorded DIR] (prints a Markdown table and, below it, each
failed target; the swing clearance column is the lowest of the feet's mean swing clearances, "none"
when a foot never lifts). Each gait is played with its lookahead and pushed, or, with --recorded,
read from what `scripts/make_gaits.py --measure-only` recorded in DIR (out/gait-measures).
Targets (docs/locomotion.md): every gait 20 cycles without falling, no joint jump over 15° and no
root jump over 6 cm between 60 Hz frames, stance slip ≤ 3 cm, root pitch and roll within ±30°; per
gait a speed, flight and cadence or footfall pattern; the run and the trot survive 4 of 5 sideways
pushes of 0.5 N·s/kg in cycle 3.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_parameters
from eigengait.control.library import gait_names, resolve
from eigengait.control.playback import play, push_robustness


def _phase_gap(a: float, b: float) -> float:
    d = abs(a - b) % 1.0
    return min(d, 1.0 - d)


def targets(name: str, m: dict, pushes: list[bool]) -> dict[str, bool]:
    tilt = max(abs(v) for v in m["torso_pitch_deg"] + m["torso_roll_deg"])
    out = {
        "20 cycles": m["cycles_completed"] == 20 and not m["fell"],
        "jump ≤ 15°": (m["max_frame_jump_deg"] or 0) <= 15,
        "root jump ≤ 6 cm": (m["max_root_jump_m"] or 0) <= 0.06,
        "slip ≤ 3 cm": m["stance_slip_max_m"] is not None and m["stance_slip_max_m"] <= 0.03,
        "tilt ≤ 30°": tilt <= 30,
    }
    speed, flight = m["mean_speed_mps"], m["flight_fraction"]
    if name == "humanoid-basic-run":
        out.update(
            {
                "speed ≥ 1.2": speed >= 1.2,
                "flight ≥ 0.10": flight >= 0.10,
                "cadence 140–200": m["cadence_spm"] is not None and 140 <= m["cadence_spm"] <= 200,
            }
        )
    elif name == "monster-run":
        out.update({"speed ≥ 1.2": speed >= 1.2, "flight > 0": flight > 0})
    elif name == "kangaroo-hop":
        out.update({"speed ≥ 0.8": speed >= 0.8, "flight ≥ 0.15": flight >= 0.15})
    elif name == "dog-trot":
        f = m["footfall"]
        known = None not in f.values()
        out.update(
            {
                "speed ≥ 0.5": speed >= 0.5,
                "diagonal pairs together": known
                and _phase_gap(f["front_left"], f["rear_right"]) <= 0.1
                and _phase_gap(f["front_right"], f["rear_left"]) <= 0.1,
                "pairs half a cycle apart": known
                and abs(_phase_gap(f["front_left"], f["front_right"]) - 0.5) <= 0.15,
            }
        )
    if name in ("humanoid-basic-run", "dog-trot"):
        out["pushes ≥ 4/5"] = pushes is not None and sum(pushes) >= 4
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--recorded", type=Path, default=None)
    args = parser.parse_args()
    print(
        "| gait | played with | cycles | speed (m/s) | cadence (steps/min) | flight | "
        "swing clearance (m) | stance slip (m) | pitch (°) | roll (°) | max jump (°) | "
        "mean τ² ((N·m)²) | pushes (of 5) | targets met |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|---|---|---:|---:|---:|---|")
    failures = []
    for name in gait_names():
        if args.recorded is not None:
            record = json.loads((args.recorded / f"{name}.json").read_text(encoding="utf-8"))
            m, pushes, lag = record["played"], record["pushes"], record.get("activation_time")
        else:
            controller = load_controller(resolve("gait", name))
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
        control = ("lookahead" if m["lookahead"] else "pulses") + (
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
