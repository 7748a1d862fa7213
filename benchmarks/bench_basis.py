"""Do vibration modes make gaits better or faster to get than plain joint torques? The thesis's
comparisons, measured.

For each character's preset sketch (humanoid `basic-run`, `monster`, `dog-trot`) four search spaces
are optimized by the same two-stage optimizer (`optimize/staged.py`), at the same evaluation budget
and from the same seeds:

| variant | torque basis | priority modes (ψ kept ≥ the sketch's) | optimized |
|---|---|---|---|
| `modal` | modes | the preset's | the preset's priority + allowed modes |
| `priority-only` | modes | the preset's | the priority modes alone |
| `trivial` | modes | the preset's ψ values moved onto the lowest modes (1, 2, …) | the lowest 12 modes |
| `canonical` | one torque per joint dof | none | every dof |

Timing, initial state, targets, feedback and horizon stay the preset's. Each run's best controller
is then played 20 cycles with no reset and no lookahead (cycles survived, speed, cost of transport)
and, when it survives 3 cycles, pushed sideways with 0.5 N·s/kg at 5 phases of cycle 3
(`control/playback.push_robustness`); speed and cost of transport are given for the runs that
survive the 5-cycle horizon. From each run's logs:
evaluations and seconds until the best candidate first survives the whole horizon (stage 2's best
cycle violation below the fall marker), and until that violation is below 0.5.

Usage: python benchmarks/bench_basis.py [--evaluations N] [--seeds K] [--characters …] [--out DIR]
Runs are kept in DIR (default out/bench_basis) and skipped when done, so an interrupted benchmark
resumes. It prints the table, writes DIR/table.md, the convergence figure
docs/images/evidence_convergence.png and the measured part of docs/evidence.md; the wall time and
the runs' summed optimization time are printed. The baseline (same process) is one population
evaluation of the humanoid's modal sketch, so the seconds can be read as population units on another
machine.
"""  # noqa: E501

from __future__ import annotations

import argparse
import csv
import json
import time
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_parameters  # noqa: E402
from eigengait.control.library import resolve  # noqa: E402
from eigengait.control.playback import play, push_robustness  # noqa: E402
from eigengait.control.sketch import PhaseSketch, Sketch, load_sketch  # noqa: E402
from eigengait.optimize.evaluate import FALLEN_CYCLE_ERROR  # noqa: E402
from eigengait.optimize.mom import MomSettings  # noqa: E402
from eigengait.optimize.staged import OPEN_LOOP_SHARE, STAGE_ONE, optimize_gait  # noqa: E402
from population_unit import population_seconds  # noqa: E402

CHARACTERS = {"humanoid": "basic-run", "monster": "monster", "dog": "dog-trot"}
VARIANTS = ("modal", "priority-only", "trivial", "canonical")
TRIVIAL_MODES = 12
# cycles: the presets' optimization horizon; a run "survives" when its gait plays this long
HORIZON = 5
NEAR_CYCLIC = 0.5  # cycle violation a run must reach for the second "time to" figure
ROOT = Path(__file__).resolve().parents[1]
FIGURE = ROOT / "docs" / "images" / "evidence_convergence.png"
PAGE = ROOT / "docs" / "evidence.md"


def variant(sketch: Sketch, name: str) -> Sketch:
    """The preset sketch with the search space of `name` (see the module's table)."""
    if name == "modal":
        return sketch
    if name == "canonical":
        return sketch.model_copy(
            update={"basis": "canonical", "air": PhaseSketch(), "ground": PhaseSketch()}
        )
    phases = {}
    for phase in ("air", "ground"):
        chosen = sketch.phase(phase)
        if name == "priority-only":
            phases[phase] = PhaseSketch(priority=chosen.priority, allowed=[])
        else:  # trivial
            values = [chosen.priority[m] for m in sorted(chosen.priority)]
            phases[phase] = PhaseSketch(
                priority={k + 1: v for k, v in enumerate(values)},
                allowed=list(range(1, TRIVIAL_MODES + 1)),
            )
    return sketch.model_copy(update=phases)


def curve(folder: Path) -> list[tuple[int, float, float, str]]:
    """(evaluations from the start, seconds from the start, best cycle violation, stage) of every
    logged generation."""
    points, evaluations, seconds = [], 0, 0.0
    for stage, log in (
        ("open loop", folder / STAGE_ONE / "log.csv"),
        ("closed loop", folder / "log.csv"),
    ):
        if not log.exists():
            continue
        rows = list(csv.DictReader(log.open()))
        for r in rows:
            points.append(
                (
                    evaluations + int(r["evaluations"]),
                    seconds + float(r["seconds"]),
                    float(r["best_violation"]),
                    stage,
                )
            )
        if rows:
            evaluations += int(rows[-1]["evaluations"])
            seconds += float(rows[-1]["seconds"])
    return points


def first_below(points, threshold: float, stage: str = "closed loop"):
    """(evaluations, seconds) of the first generation of `stage` whose best violation is below
    `threshold`."""
    return next(((e, s) for e, s, v, st in points if st == stage and v < threshold), (None, None))


def run_one(sketch: Sketch, folder: Path, evaluations: int, seed: int) -> dict:
    """Optimize, play and push one run; the figures are saved in folder/result.json (reused when
    present)."""
    done = folder / "result.json"
    if done.exists():
        return json.loads(done.read_text())
    settings = MomSettings(seed=seed, max_evaluations=evaluations, inner_generations=100)
    resume = (folder / STAGE_ONE / "checkpoint.npz").exists()
    start = time.perf_counter()
    optimize_gait(sketch, folder, settings, resume=resume, progress=False)
    seconds = time.perf_counter() - start
    controller = load_controller(folder / "best_controller.json")
    system = gait_system(controller)
    params = to_parameters(controller, system)
    played = play(system, params, cycles=20)
    pushes = push_robustness(system, params) if played.cycles_completed >= 3 else [False] * 5
    points = curve(folder)
    survives = first_below(points, FALLEN_CYCLE_ERROR)
    near = first_below(points, NEAR_CYCLIC)
    # speed and cost of a gait that falls early say little
    lasted = played.cycles_completed >= HORIZON
    result = {
        "seconds": round(seconds, 1),
        "cycles_survived": played.cycles_completed,
        "speed_mps": round(played.mean_speed_mps, 3) if lasted else None,
        "cost_of_transport": (
            round(played.cost_of_transport, 3)
            if lasted and np.isfinite(played.cost_of_transport)
            else None
        ),
        "pushes_survived": int(sum(pushes)),
        "final_violation": points[-1][2] if points else None,
        "evaluations_to_survive_horizon": survives[0],
        "seconds_to_survive_horizon": survives[1],
        "evaluations_to_near_cyclic": near[0],
        "seconds_to_near_cyclic": near[1],
        "curve": [(e, v) for e, _, v, _ in points],
    }
    done.write_text(json.dumps(result))
    return result


def spread(values) -> str:
    """Median [min–max] of the finite values, and how many there were if some are missing."""
    v = np.array([x for x in values if x is not None and np.isfinite(x)], float)
    if not v.size:
        return "—"
    text = f"{np.median(v):.3g} [{v.min():.3g}–{v.max():.3g}]"
    return text if len(v) == len(values) else f"{text} ({len(v)}/{len(values)})"


def table(results: dict) -> str:
    lines = [
        "| character | variant | survives the 5-cycle horizon | cycles survived (of 20) | "
        "pushes survived (of 5) | evaluations to survive the horizon | seconds to it | "
        "evaluations to violation < 0.5 | final violation | speed (m/s) | cost of transport |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for (character, name), runs in results.items():
        ok = sum(r["cycles_survived"] >= HORIZON for r in runs)
        lines.append(
            f"| {character} | {name} | {ok} of {len(runs)} | "
            f"{spread([r['cycles_survived'] for r in runs])} | "
            f"{spread([r['pushes_survived'] for r in runs])} "
            f"| {spread([r['evaluations_to_survive_horizon'] for r in runs])} "
            f"| {spread([r['seconds_to_survive_horizon'] for r in runs])} "
            f"| {spread([r['evaluations_to_near_cyclic'] for r in runs])} "
            f"| {spread([r['final_violation'] for r in runs])} | "
            f"{spread([r['speed_mps'] for r in runs])} | "
            f"{spread([r['cost_of_transport'] for r in runs])} |"
        )
    return "\n".join(lines)


def figure(results: dict, evaluations: int) -> None:
    characters = list(dict.fromkeys(c for c, _ in results))
    fig, axes = plt.subplots(1, len(characters), figsize=(5 * len(characters), 4), squeeze=False)
    grid = np.linspace(0, evaluations, 60)
    for ax, character in zip(axes[0], characters):
        for name in VARIANTS:
            runs = results.get((character, name), [])
            if not runs:
                continue
            rows = []
            for r in runs:
                e, v = (
                    np.array(r["curve"], float).T
                    if r["curve"]
                    else (np.zeros(1), np.full(1, np.nan))
                )
                index = np.searchsorted(e, grid, side="right") - 1
                rows.append(np.where(index >= 0, v[np.clip(index, 0, None)], np.nan))
            rows = np.array(rows)
            with warnings.catch_warnings():  # grid points before a run's first generation are NaN
                warnings.simplefilter("ignore", RuntimeWarning)
                low, middle, high = np.nanmin(rows, 0), np.nanmedian(rows, 0), np.nanmax(rows, 0)
            line = ax.plot(grid, middle, label=name)[0]
            ax.fill_between(grid, low, high, color=line.get_color(), alpha=0.12)
        ax.set_yscale("log")
        ax.set_title(f"{character} ({CHARACTERS[character]})")
        ax.set_xlabel("evaluations")
        ax.axhline(FALLEN_CYCLE_ERROR, color="grey", lw=0.6, ls=":")
        ax.axvline(OPEN_LOOP_SHARE * evaluations, color="grey", lw=0.6, ls="--")
    axes[0][0].set_ylabel("best cycle violation (median, min–max band)")
    axes[0][0].legend(fontsize=8)
    fig.suptitle(
        "Best cycle violation against evaluations: open loop (1 cycle), then from the dashed line "
        f"closed loop (5 cycles); {FALLEN_CYCLE_ERROR:g} marks a best candidate that falls"
    )
    fig.tight_layout()
    FIGURE.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(FIGURE, dpi=100)


BEGIN, END = "<!-- measured: written by benchmarks/bench_basis.py -->", "<!-- end of measured -->"


def page(markdown_table: str, evaluations: int, seeds: int, spent: float, unit: float) -> str:
    """docs/evidence.md with its measured part replaced (the reading around it is kept)."""
    measured = f"""{BEGIN}
Written by `python benchmarks/bench_basis.py --evaluations {evaluations} --seeds {seeds}`: {spent / 60:.0f} min of
optimization over the runs, plus their plays and pushes (one population evaluation of the humanoid's modal sketch
took {unit:.2f} s in the same process). Median [min–max] over the seeds; "(k/n)" when only k of the n runs reached
that point.

{markdown_table}

![convergence](images/evidence_convergence.png)
{END}"""  # noqa: E501
    if PAGE.exists() and BEGIN in (text := PAGE.read_text()):
        return text[: text.index(BEGIN)] + measured + text[text.index(END) + len(END) :]
    return f"# Evidence: modes against plain joint torques\n\n{measured}\n"


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--evaluations", type=int, default=600)
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--characters", nargs="*", default=list(CHARACTERS))
    parser.add_argument("--variants", nargs="*", default=list(VARIANTS))
    parser.add_argument("--out", type=Path, default=ROOT / "out" / "bench_basis")
    args = parser.parse_args()
    wall = time.perf_counter()
    unit, size = population_seconds(load_sketch(resolve("sketch", "basic-run")))
    print(f"baseline: one population of {size} humanoid candidates, 5 cycles: {unit:.2f} s")
    results: dict = {}
    # seed-major, so a partial run still compares every variant
    for seed in range(1, args.seeds + 1):
        for character in args.characters:
            preset = load_sketch(resolve("sketch", CHARACTERS[character]))
            for name in args.variants:
                folder = args.out / character / name / f"seed{seed}"
                r = run_one(variant(preset, name), folder, args.evaluations, seed)
                results.setdefault((character, name), []).append(r)
                print(
                    f"{character} {name} seed {seed}: {r['cycles_survived']} cycles, "
                    f"{r['pushes_survived']} pushes, violation {r['final_violation']:.3g}, "
                    f"{r['seconds']:.0f} s",
                    flush=True,
                )
    ordered = {
        (c, n): results[(c, n)] for c in args.characters for n in args.variants if (c, n) in results
    }
    markdown = table(ordered)
    print(markdown)
    (args.out / "table.md").write_text(markdown + "\n")
    figure(ordered, args.evaluations)
    # also right when runs were reused
    spent = sum(r["seconds"] for runs in ordered.values() for r in runs)
    PAGE.write_text(page(markdown, args.evaluations, args.seeds, spent, unit))
    print(
        f"wall time: {(time.perf_counter() - wall) / 60:.1f} min; optimization time over the runs "
        f"{spent / 60:.1f} min"
    )


if __name__ == "__main__":
    main()
