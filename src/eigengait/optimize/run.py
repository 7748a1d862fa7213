"""An optimization run folder: sketch, seed and settings, CSV log, plots, checkpoint, best
controller.

```
RUN/
  sketch.yaml          the sketch as validated
  settings.json        method, seed, optimizer settings, evaluator, versions
  checkpoint.npz       the optimizer state after the last generation, as data (resume with resume=True)
  status.json          whether the run finished, and why (a killed or crashed run stays "finished": false)
  log.csv              one row per generation
  objective.png        best objective per generation     violation.png   best cycle violation per generation
  best_controller.json the best controller so far (written every generation)
```
"""  # noqa: E501

from __future__ import annotations

import csv
import json
from dataclasses import asdict, replace
from pathlib import Path

import mujoco
import yaml
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

from eigengait import __version__
from eigengait.control.controller import save_controller, sketch_modes, to_file
from eigengait.control.lookahead import LookaheadSettings
from eigengait.control.sketch import Sketch
from eigengait.errors import UserInputError
from eigengait.optimize.evaluators import make_evaluator
from eigengait.optimize.checkpoint import load_state, save_state
from eigengait.optimize.methods import make_optimizer, method_settings
from eigengait.optimize.mom import MomState, SearchSettings
from eigengait.optimize.problem import Problem
from eigengait.outputs import check_folder, replacing, write_atomically

BUDGET_FIELDS = ("max_evaluations", "max_seconds", "max_outer", "inner_generations")
RUN_MARKERS = ("checkpoint.npz", "checkpoint.pkl", "best_controller.json")
RUN_FILES = (
    *RUN_MARKERS,
    "status.json",
    "sketch.yaml",
    "settings.json",
    "log.csv",
    "objective.png",
    "violation.png",
)


def _saved_settings(folder: Path) -> tuple[SearchSettings, str]:
    """The run's optimizer settings and evaluator, from its settings.json.

    Run folders of earlier versions keep the method among the settings, and the adaptive AL's ones a
    `penalty` that it never read; both are read as the method's own settings."""
    try:
        saved = json.loads((folder / "settings.json").read_text(encoding="utf-8"))
        fields = dict(saved["settings"])
        earlier = fields.pop("method", None)
        if earlier == "al":
            fields.pop("penalty", None)
        return method_settings(saved.get("method", earlier or "mom"), **fields), saved["evaluator"]
    except (OSError, ValueError, KeyError, TypeError, UserInputError) as exc:
        raise UserInputError(
            f"the run folder's settings.json is missing or damaged ({exc.__class__.__name__})",
            file=folder / "settings.json",
            fix="start a new run in another output folder",
        ) from None


def _check_same_run(folder: Path, sketch: Sketch, saved: SearchSettings, seed: int | None) -> None:
    """Refuse to resume with a sketch or seed other than the run's own."""
    if seed is not None and seed != saved.seed:
        raise UserInputError(
            f"the run was started with seed={saved.seed}, not seed={seed}",
            file=folder,
            field="seed",
            fix="resume without a seed, or start a new run",
        )
    try:
        own = yaml.safe_load((folder / "sketch.yaml").read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as exc:
        raise UserInputError(
            f"the run folder's sketch.yaml is missing or damaged ({exc.__class__.__name__})",
            file=folder / "sketch.yaml",
            fix="start a new run in another output folder",
        ) from None
    if own != sketch.model_dump(mode="json"):
        raise UserInputError(
            "the run was started from another sketch",
            file=folder,
            fix="resume with the run's own sketch (its sketch.yaml), or start a new run",
        )


def prepare_folder(
    folder: Path,
    sketch: Sketch,
    settings: SearchSettings,
    evaluator: str,
    resume: bool,
    seed: int | None = None,
):
    """Create or reopen a run folder; refuse to overwrite an earlier run unless resuming.

    `seed` is the seed the user asked for, if any: resuming refuses one that differs from the
    run's."""
    checkpoint = folder / "checkpoint.npz"
    if resume:
        if (folder / "checkpoint.pkl").exists() and not checkpoint.exists():
            raise UserInputError(
                "the run folder holds a pickled checkpoint from an earlier version, which is not "
                "read because a pickle can run code",
                file=folder,
                fix="start a new run in another output folder",
            )
        if not checkpoint.exists():
            raise UserInputError(
                "nothing to resume: no checkpoint.npz in the run folder",
                file=folder,
                fix="start the run without resume=True",
            )
        saved, saved_evaluator = _saved_settings(folder)
        _check_same_run(folder, sketch, saved, seed)
        budget = {k: getattr(settings, k) for k in BUDGET_FIELDS}
        return replace(saved, **budget), saved_evaluator, load_state(checkpoint)
    refuse_earlier_run(folder)
    check_folder(folder)
    write_atomically(
        folder / "sketch.yaml", yaml.safe_dump(sketch.model_dump(mode="json"), sort_keys=False)
    )
    write_atomically(
        folder / "settings.json",
        json.dumps(
            {
                "method": settings.method,
                "settings": asdict(settings),
                "evaluator": evaluator,
                "eigengait": __version__,
                "mujoco": mujoco.__version__,
            },
            indent=2,
        ),
    )
    return settings, evaluator, None


def _holds_run(folder: Path) -> bool:
    """Whether the folder holds an earlier run with something to lose (a checkpoint or a
    controller)."""
    return folder.is_dir() and any((folder / name).exists() for name in RUN_MARKERS)


def refuse_earlier_run(folder: Path) -> None:
    """Refuse to start a new run over an earlier one; the message says whether that run finished."""
    if not _holds_run(folder):
        return
    if _finished(folder):
        raise UserInputError(
            "the run folder holds a finished run and was left untouched",
            file=folder,
            fix="choose another output folder, pass force=True to start over, or resume=True "
            "with a larger budget to continue it",
        )
    raise UserInputError(
        "the run folder holds an unfinished run (interrupted or stopped by an error) and was left "
        "untouched",
        file=folder,
        fix="pass resume=True to continue it, or force=True to start over",
    )


def _finished(folder: Path) -> bool:
    try:
        return json.loads((folder / "status.json").read_text(encoding="utf-8"))["finished"] is True
    except (OSError, ValueError, KeyError, TypeError):
        return False


def clear_run(folder: Path) -> None:
    """Delete an earlier run's files, and temporary files a killed run left, from the folder
    (other files stay)."""
    if not folder.is_dir():
        return
    for path in [*(folder / name for name in RUN_FILES), *folder.glob(".*.part.*")]:
        path.unlink(missing_ok=True)


def write_status(folder: Path, state: MomState) -> None:
    """Record whether the run finished (and why) in status.json."""
    write_atomically(
        folder / "status.json",
        json.dumps(
            {
                "finished": bool(state.finished),
                "reason": state.finished or "running or interrupted",
                "generations": state.generation,
                "evaluations": state.evaluations,
            },
            indent=2,
        ),
    )


def write_log(folder: Path, rows: list[dict]) -> None:
    if not rows:
        return
    with replacing(folder / "log.csv") as temporary, open(temporary, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def write_plots(folder: Path, rows: list[dict], cycle_tolerance: float | None = None) -> None:
    """objective.png and violation.png against generation; the violation plot marks the cycle
    tolerance."""
    from eigengait.figures import agg_figure

    if not rows:
        return
    g = [r["generation"] for r in rows]
    for key, name, label in (
        ("best_cost", "objective.png", "best objective f (dimensionless, log)"),
        ("best_violation", "violation.png", "best cycle violation max|φᵢ|\n(rad, m; log)"),
    ):
        fig = agg_figure(6, 3.2, 110)
        ax = fig.add_subplot()
        ax.semilogy(
            g, [max(r[key], 1e-12) for r in rows], color="#2a6fb0", lw=1.6, label="best so far"
        )
        if key == "best_violation" and cycle_tolerance:
            ax.axhline(
                cycle_tolerance,
                color="#c0392b",
                lw=1.2,
                label=f"cycle tolerance {cycle_tolerance:g}",
            )
            low, high = ax.get_ylim()
            ax.set_ylim(min(low, cycle_tolerance / 1.5), max(high, cycle_tolerance * 1.5))
            ax.legend(fontsize=8, loc="upper right")
        for r0, r1 in zip(rows, rows[1:]):
            if r1["outer"] != r0["outer"]:
                ax.axvline(r1["generation"], color="#bbb", lw=0.8, ls="--")
        ax.set_xlabel("generation (dashed: new multiplier iteration)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        with replacing(folder / name) as temporary:
            fig.savefig(temporary)


def write_best(folder: Path, problem: Problem, state: MomState) -> None:
    if state.best_x is None:
        return
    o = state.best
    metrics = {
        "cost": o.cost,
        "cycle_violation": o.violation,
        "fell": o.fell,
        "mean_speed_mps": float(o.mean_velocity[0]),
        "mean_squared_torque": o.energy,
        "evaluations": state.evaluations,
    }
    # a gait with the SIMBICON layer plays without plans, which are made without it
    lookahead = (
        LookaheadSettings(speed=problem.sketch.targets.mean_speed)
        if problem.system.simbicon is None
        else None
    )
    best = problem.space.decode(state.best_x)
    controller = to_file(
        problem.system,
        best,
        name=folder.name,
        metrics=metrics,
        lookahead=lookahead,
        sketch=sketch_modes(problem.sketch),
    )
    save_controller(controller, folder / "best_controller.json")


def optimize(
    sketch: Sketch,
    folder: Path,
    settings: SearchSettings,
    evaluator: str = "threads",
    workers: int | None = None,
    resume: bool = False,
    progress: bool = True,
    sketch_source: str | Path | None = None,
    x_start=None,
    seed: int | None = None,
) -> MomState:
    """Run (or resume) the optimizer `settings` are for (`settings.method`) from `x_start` (default:
    the sketch's guess); checkpoints every generation. `seed` is the seed the user asked for
    explicitly, if any; a resumed run refuses a different one."""
    problem = Problem.from_sketch(sketch, sketch_source)
    settings, evaluator, state = prepare_folder(folder, sketch, settings, evaluator, resume, seed)
    state = state or MomState(x_start=problem.space.initial() if x_start is None else x_start)
    if state.x_start.shape != problem.space.initial().shape:
        raise UserInputError(
            "the checkpoint was made for another parameter space",
            file=folder / "checkpoint.npz",
            fix="start a new run in another output folder",
        )
    state.finished = ""
    write_status(folder, state)
    evaluate = make_evaluator(evaluator, problem, workers)
    mom = make_optimizer(evaluate, settings, state)
    columns = [
        TextColumn("[bold]optimizing[/]"),
        BarColumn(),
        TextColumn("gen {task.fields[gen]}"),
        TextColumn("f {task.fields[cost]}"),
        TextColumn("violation {task.fields[viol]}"),
        TimeElapsedColumn(),
    ]
    total = settings.max_evaluations
    try:
        with Progress(*columns, disable=not progress, transient=False) as bar:
            task = bar.add_task(
                "opt",
                total=total,
                gen=state.generation,
                cost="-",
                viol="-",
                completed=state.evaluations,
            )
            while (row := mom.step()) is not None:
                save_state(state, folder / "checkpoint.npz")
                write_log(folder, state.log)
                write_best(folder, problem, state)
                bar.update(
                    task,
                    completed=row["evaluations"],
                    gen=row["generation"],
                    cost=f"{row['best_cost']:.4g}",
                    viol=f"{row['best_violation']:.3g}",
                )
    finally:
        close = getattr(evaluate, "close", None)
        close and close()
    save_state(state, folder / "checkpoint.npz")
    write_plots(folder, state.log, settings.cycle_tolerance)
    write_status(folder, state)
    return state
