"""Write docs/gallery.md: every shipped gait with its sketch, a strip of one cycle, its quality and
how much of it is still its sketch.

Usage: python scripts/gallery.py [--recorded DIR] [--gaits NAME ...]
Reads what `scripts/make_gaits.py --measure-only` recorded in DIR (default out/gait-measures: the
20-cycle plays with and without lookahead) and the strips `scripts/gait_strips.py` drew in
docs/images; plays nothing itself. With --gaits only those gaits' sections and table rows of the
existing page are rewritten (the others keep what was recorded when they were measured).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from gait_table import DEFAULT
from make_gaits import GAITS, MEASURES

from eigengait.control.controller import load_controller
from eigengait.control.library import gait_names, resolve
from eigengait.control.sketch import load_sketch

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "gallery.md"
REFERENCE = "humanoid-basic-run"  # the experiments' signatures are read against the basic run
SIGNATURES = {  # experiment gait -> (figure, how to read it off the played summary, unit)
    "humanoid-lateral-sway": ("lateral COM amplitude", lambda m: m["lateral_com_amplitude_m"], "m"),
    "humanoid-vertical-rotation": ("root yaw amplitude", lambda m: m["yaw_amplitude_deg"], "°"),
    "humanoid-skipping": (
        "touchdowns per foot per cycle",
        lambda m: min(m["touchdowns_per_cycle"].values()),
        "",
    ),
    "humanoid-crouched": ("mean root height", lambda m: m["mean_root_height_m"], "m"),
    "humanoid-legs-apart": ("stance width", lambda m: m["stance_width_m"], "m"),
    "humanoid-one-foot-hop": (
        "right (raised) foot's lowest height",
        lambda m: m["min_foot_height_m"]["right"],
        "m",
    ),
}


def _modes(phase) -> str:
    priority = ", ".join(f"{m}: {v:+.0f}" for m, v in sorted(phase.priority.items()))
    allowed = (
        "all not excluded"
        if phase.allowed is None
        else ", ".join(map(str, phase.allowed)) or "none"
    )
    return f"priority {{{priority or 'none'}}} N·m; allowed {allowed}"


def _split(split: dict | None) -> str:
    if not split or split.get("priority") is None:
        return "—"
    return " / ".join(f"{100 * split[k]:.0f} %" for k in ("priority", "allowed", "excluded"))


def _value(x, unit: str) -> str:
    return "—" if x is None else f"{x:.3g}{(' ' + unit) if unit else ''}"


def planning(lookahead) -> str:
    """How far the plans of `lookahead` reach and, where it is not the default, how hard they hold
    the target speed."""
    text = f"plans {lookahead.horizon_cycles:g} cycles long"
    if lookahead.speed_weight != DEFAULT.speed_weight:
        text += f", the speed term weighted {lookahead.speed_weight:g}"
    return text


def section(name: str, record: dict, reference: dict | None) -> str:
    controller = load_controller(resolve("gait", name))
    sketch = load_sketch(resolve("sketch", GAITS[name]))
    m = record["played"]
    planner = (
        f"with its lookahead ({planning(controller.lookahead)})"
        if m.get("lookahead")
        else "without lookahead (its event feedback in charge)"
        if controller.feedback.event is not None
        else "without lookahead (it lasts longer so)"
    )
    if record.get("activation_time"):
        planner += (
            f", its motors lagging {1000 * record['activation_time']:.0f} ms behind their commands"
        )
    survived = f"{m['cycles_completed']} of 20 cycles" + (" (fell)" if m["fell"] else "")
    lines = [
        f"## `{name}`",
        "",
        f"*Sketch `{GAITS[name]}`* ({sketch.character}, {sketch.basis} basis): "
        f"{sketch.description}",
        f"air: {_modes(sketch.air)}; ground: {_modes(sketch.ground)}; sketched period "
        f"{sketch.timing.period} s, optimized {controller.period:.3f} s.",
        "",
        f"![{name}](images/gait_{name}.png)",
        "",
        f"Played 20 cycles {planner}, no reset: {survived}, {m['mean_speed_mps']:.2f} m/s, cadence "
        f"{m['cadence_spm']:.0f} steps/min, flight {m['flight_fraction']:.2f}, stance slip "
        f"{_value(m['stance_slip_max_m'], 'm')}, pitch "
        f"{m['torso_pitch_deg'][0]:.0f}…{m['torso_pitch_deg'][1]:.0f}°, roll "
        f"{m['torso_roll_deg'][0]:.0f}…{m['torso_roll_deg'][1]:.0f}°, largest frame jump "
        f"{m['max_frame_jump_deg']:.0f}°, cost of transport {_value(m['cost_of_transport'], '')}.",
        "",
        "Torque energy in priority / allowed / excluded modes: played "
        f"{_split(m.get('energy_split'))}, pulses alone {_split(m.get('pulse_energy_split'))}; ψ "
        f"against the sketch's: cosine {_value(m.get('psi_cosine'), '')}, priority share of Σ|ψ| "
        f"{_value(m.get('psi_priority_share'), '')}.",
    ]
    if name in SIGNATURES:
        label, read, unit = SIGNATURES[name]
        against = f" (the basic run: {_value(read(reference), unit)})" if reference else ""
        lines += ["", f"Signature: {label} {_value(read(m), unit)}{against}."]
    return "\n".join(lines)


def summary_table(records: dict) -> str:
    """One row per gait: the energy split, ψ against the sketch, and every signature figure."""
    rows = [
        "| gait | played torque: priority / allowed / excluded | pulses alone | ψ cosine | "
        "priority share of Σ|ψ| | lateral COM amplitude (m) | yaw amplitude (°) | "
        "fewest touchdowns per foot per cycle | mean root height (m) | stance width (m) | "
        "highest foot's lowest height (m) |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, record in records.items():
        m = record["played"]
        touchdowns = [v for v in m["touchdowns_per_cycle"].values() if v is not None]
        lowest = [v for v in m["min_foot_height_m"].values() if v is not None]
        rows.append(
            f"| `{name}` | {_split(m.get('energy_split'))} | {_split(m.get('pulse_energy_split'))} "
            f"| {_value(m.get('psi_cosine'), '')} | {_value(m.get('psi_priority_share'), '')} "
            f"| {_value(m['lateral_com_amplitude_m'], '')} | {_value(m['yaw_amplitude_deg'], '')} "
            f"| {_value(min(touchdowns, default=None), '')} | "
            f"{_value(m['mean_root_height_m'], '')} | {_value(m['stance_width_m'], '')} | "
            f"{_value(max(lowest, default=None), '')} |"
        )
    return "\n".join(rows)


def updated(page: str, records: dict, reference: dict | None) -> str:
    """`page` with the table row and the section of each gait in `records` rewritten, signatures
    against `reference` (the basic run's played figures; None: not compared). The basic run itself
    is rewritten only with the whole page, since every signature is read against it."""
    if REFERENCE in records:
        raise SystemExit(f"{REFERENCE} is every signature's reference: rewrite the whole page")
    parts = page.rstrip("\n").split("\n\n## ")
    rows = summary_table(records).splitlines()[2:]
    for name, record in records.items():
        row = next(r for r in rows if r.startswith(f"| `{name}` |"))
        old_row = next(line for line in page.splitlines() if line.startswith(f"| `{name}` |"))
        parts = [part.replace(old_row, row) for part in parts]
        k = next(i for i, part in enumerate(parts) if part.startswith(f"`{name}`"))
        parts[k] = section(name, record, reference).removeprefix("## ")
    return "\n\n## ".join(parts) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--recorded", type=Path, default=MEASURES)
    parser.add_argument("--gaits", nargs="+", help="rewrite only these gaits' parts of the page")
    args = parser.parse_args()
    if args.gaits:
        records = {n: json.loads((args.recorded / f"{n}.json").read_text()) for n in args.gaits}
        basic = args.recorded / f"{REFERENCE}.json"
        reference = json.loads(basic.read_text())["played"] if basic.is_file() else None
        PAGE.write_text(updated(PAGE.read_text(), records, reference))
        print(f"rewrote {', '.join(args.gaits)} in {PAGE}")
        return
    records = {n: json.loads((args.recorded / f"{n}.json").read_text()) for n in gait_names()}
    reference = records.get(REFERENCE, {}).get("played")
    head = [
        "# Gallery of the shipped gaits",
        "",
        "Written by `python scripts/gallery.py` from the figures `scripts/make_gaits.py "
        "--measure-only` recorded; the strips are `scripts/gait_strips.py`'s (one cycle played as "
        "shipped, the second unless its title names a later one for a gait that settles slowly, "
        "from a fixed side camera, with the feet on the ground below). "
        "The figures are defined in the README (Playback); the energy split is "
        "`control/sketch_character.py`'s.",
        "",
        "## Does each gait keep its sketch's character?",
        "",
        "Each experiment's own figure is in its section below, against the basic run's. All of "
        "them, for every gait:",
        "",
        summary_table(records),
    ]
    PAGE.write_text(
        "\n\n".join(["\n".join(head)] + [section(n, r, reference) for n, r in records.items()])
        + "\n"
    )
    print(f"wrote {PAGE}")


if __name__ == "__main__":
    main()
