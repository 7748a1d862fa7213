"""Commands of the modal-locomotion pipeline: sketch, optimize, play, gaits, demo."""

from __future__ import annotations

import os
import time
from datetime import datetime
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.table import Table

from eigengait.cli.media import (
    BVH_UNITS_OPTION,
    CAMERA_OPTION,
    FPS_OPTION,
    SPEED_OPTION,
    MediaOptions,
    status_console,
    write_media,
)
from eigengait import json_text
from eigengait.inputs import check_range
from eigengait.errors import UserInputError
from eigengait.outputs import check_folder, refuse_existing, write_atomically

console = Console()
# stride + both knees a quarter period later (Kry et al. 2009 style)
DEMO_KINEMATIC_MIX = "2:1.4,15:0.8@90"
DEMO_KINEMATIC_BASE_HZ = 0.9  # snap both frequencies to multiples of 0.9 Hz so the clip loops
RESUME_OPTION = typer.Option(False, "--resume", help="Continue the run in --output.")
START_OVER_OPTION = typer.Option(
    False, "--force", help="Start over: delete an earlier run's files in --output."
)


def sketch_command(
    sketch: str = typer.Argument(..., help="Sketch file (.yaml/.json) or a shipped preset name."),
    seconds: float = typer.Option(4.0, "--seconds", help="Simulated time (s)."),
    video: Optional[Path] = typer.Option(None, "--video", help="Write a video (.mp4/.gif)."),
    fps: float = FPS_OPTION,
    speed: float = SPEED_OPTION,
    camera: str = CAMERA_OPTION,
    force: bool = typer.Option(False, "--force", help="Overwrite an existing video."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Simulate a sketch with gravity off, as the animator sees it while editing."""
    from eigengait.control.library import resolve
    from eigengait.control.sketch import load_sketch
    from eigengait.control.sketch_sim import simulate_sketch

    if seconds <= 0:
        raise UserInputError(f"--seconds must be positive, got {seconds}", field="--seconds")
    media = MediaOptions(video=video, fps=fps, speed=speed, camera=camera).check()
    refuse_existing([video], force)
    path = resolve("sketch", sketch)
    result = simulate_sketch(load_sketch(path), seconds, source=path)
    summary = {
        "sketch": str(path),
        "simulated_s": seconds,
        "wall_s": round(result.wall_seconds, 3),
        "realtime_factor": round(seconds / max(result.wall_seconds, 1e-9), 1),
        "max_joint_rotation_deg": round(result.max_joint_rotation_deg, 2),
    }
    if as_json:
        print(json_text.dumps(summary))
    else:
        console.print(
            f"simulated {seconds:.1f} s of '{path.name}' with gravity off in "
            f"{result.wall_seconds:.2f} s ({summary['realtime_factor']}× real time); largest joint "
            f"rotation {summary['max_joint_rotation_deg']}°"
        )
    write_media(result.world, result.qpos, result.fps, media, status_console(as_json))


def optimize_command(
    sketch: str = typer.Argument(..., help="Sketch file or shipped preset name."),
    output: Path = typer.Option(..., "-o", "--output", help="Run folder."),
    seed: Optional[int] = typer.Option(
        None, "--seed", help="Random seed (default 1; a resumed run keeps its own)."
    ),
    evaluations: Optional[int] = typer.Option(
        None, "--max-evaluations", help="Total simulation budget."
    ),
    minutes: Optional[float] = typer.Option(None, "--max-minutes", help="Wall-clock budget (min)."),
    generations: int = typer.Option(1000, "--inner-generations", help="Cap per inner CMA-ES run."),
    max_outer: int = typer.Option(20, "--max-outer", help="Cap on multiplier iterations."),
    tolerance: Optional[float] = typer.Option(
        None, "--cycle-tolerance", help="max|φᵢ| accepted as cyclic (default: the sketch's)."
    ),
    popsize: Optional[int] = typer.Option(None, "--popsize"),
    method: str = typer.Option(
        "mom",
        "--method",
        help="mom (thesis's method of multipliers) | al (pycma's adaptive augmented Lagrangian)",
    ),
    evaluator: str = typer.Option("threads", "--evaluator", help="threads | processes | ray"),
    workers: Optional[int] = typer.Option(
        None, "--workers", help="Threads/processes/actors (default: cores)."
    ),
    resume: bool = RESUME_OPTION,
    force: bool = START_OVER_OPTION,
):
    """Optimize a sketch into a cyclic, physically simulated gait (method of multipliers +
    CMA-ES)."""
    from eigengait.control.library import resolve
    from eigengait.control.sketch import load_sketch
    from eigengait.optimize.methods import method_settings
    from eigengait.optimize.staged import optimize_gait

    for value, option, low, high in (
        (evaluations, "--max-evaluations", 1, 1e9),
        (minutes, "--max-minutes", 0.01, 1e6),
        (generations, "--inner-generations", 1, 1e6),
        (max_outer, "--max-outer", 1, 1e4),
        (tolerance, "--cycle-tolerance", 1e-6, 1e3),
        (popsize, "--popsize", 2, 10_000),
        (workers, "--workers", 1, 1024),
    ):
        check_range(value, option, low, high)
    _refuse_force_with_resume(force, resume)
    path = resolve("sketch", sketch)
    loaded = load_sketch(path)
    tolerance = tolerance if tolerance is not None else loaded.targets.cycle_tolerance
    settings = method_settings(
        method,
        seed=1 if seed is None else seed,
        max_evaluations=evaluations,
        max_seconds=minutes * 60 if minutes else None,
        inner_generations=generations,
        max_outer=max_outer,
        cycle_tolerance=tolerance,
        popsize=popsize,
    )
    if not resume:
        _start_run(output, force)
    state = optimize_gait(
        loaded, output, settings, evaluator, workers, resume, sketch_source=path, seed=seed
    )
    best = state.best
    console.print(
        f"{state.finished}: {state.evaluations} evaluations, {state.generation} generations, "
        f"{state.elapsed:.0f} s; best cost {best.cost:.4g}, cycle violation {best.violation:.3g}, "
        f"speed {best.mean_velocity[0]:.2f} m/s"
    )
    console.print(
        f"run folder: {output} (best_controller.json, log.csv, objective.png, violation.png)"
    )


def _refuse_force_with_resume(force: bool, resume: bool) -> None:
    if force and resume:
        raise UserInputError(
            "--force and --resume do not go together",
            field="--force",
            fix="--resume continues the run in --output; --force starts it over",
        )


def _start_run(folder: Path, force: bool) -> None:
    """Before a new run: refuse an earlier run in the folder or its stage-1 folder, or with `force`
    delete its files."""
    from eigengait.optimize.run import clear_run, refuse_earlier_run
    from eigengait.optimize.staged import STAGE_ONE

    check_folder(folder)
    for run in (folder, folder / STAGE_ONE):
        if force:
            clear_run(run)
        else:
            refuse_earlier_run(run)


def play_command(
    controller: str = typer.Argument(..., help="Controller file or shipped gait name."),
    cycles: int = typer.Option(6, "--cycles", help="Cycles to play."),
    snap: bool = typer.Option(
        False,
        "--snap",
        help=(
            "Reset to the initial state at each cycle end, open loop (the thesis's playback; "
            "physically incorrect)."
        ),
    ),
    push: Optional[str] = typer.Option(
        None,
        "--push",
        help=(
            "Sideways pushes on the root body: FORCE@TIME[,...] (N along +y for 0.1 s, at s), e.g. "
            "350@1.3"
        ),
    ),
    lookahead: bool = typer.Option(
        True,
        "--lookahead/--no-lookahead",
        help=(
            "Use the controller's lookahead (sampled pulse corrections at each state start), if it "
            "has one."
        ),
    ),
    activation_time: Optional[float] = typer.Option(
        None,
        "--activation-time",
        help=(
            "Motors follow their torque commands with this first-order lag (s), instead of the "
            "controller's own."
        ),
    ),
    servo: Optional[bool] = typer.Option(
        None,
        "--servo/--no-servo",
        help=(
            "Add the swing-foot servo (control/swing_servo.py, default settings) or leave it out, "
            "instead of what the controller says."
        ),
    ),
    plans: Optional[int] = typer.Option(
        None,
        "--plans",
        help=(
            "Plans the lookahead simulates at each decision, instead of the controller's (fewer: "
            "faster, less robust; docs/locomotion.md)."
        ),
    ),
    slip_weight: Optional[float] = typer.Option(
        None,
        "--slip-weight",
        help=(
            "Weight of the lookahead's cost on touching feet that slide, instead of the "
            "controller's (0: off; higher: cleaner feet, at the price of speed and uprightness; "
            "docs/locomotion.md)."
        ),
    ),
    effort_weight: Optional[float] = typer.Option(
        None,
        "--effort-weight",
        help=(
            "Weight of the lookahead's charge on a plan's size, instead of the controller's (0: "
            "off; higher: the smallest of the plans that score alike wins; docs/locomotion.md)."
        ),
    ),
    max_tilt: Optional[float] = typer.Option(
        None,
        "--max-tilt",
        help=(
            "Degrees from upright past which a lookahead plan counts as falling, instead of the "
            "controller's (docs/locomotion.md)."
        ),
    ),
    planner_seed: Optional[int] = typer.Option(
        None,
        "--planner-seed",
        help=(
            "Seed of the lookahead's random plans, instead of the controller's (another seed: "
            "another draw of the same planner, to see how much its figures hang on it)."
        ),
    ),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    video: Optional[Path] = typer.Option(None, "--video", help="Write a video (.mp4/.gif)."),
    bvh: Optional[Path] = typer.Option(None, "--bvh", help="Write the motion as BVH."),
    fps: float = FPS_OPTION,
    speed: float = SPEED_OPTION,
    camera: str = CAMERA_OPTION,
    bvh_units: str = BVH_UNITS_OPTION,
    force: bool = typer.Option(False, "--force", help="Overwrite existing outputs."),
):
    """Play a controller on the ground with gravity, physics only; report speed, energy, survival
    and gait quality."""
    from eigengait.control.binding import gait_system
    from eigengait.control.controller import load_controller, to_parameters
    from eigengait.control.library import resolve
    from eigengait.control.playback import parse_pushes, play
    from eigengait.control.sketch_character import sketch_character
    from eigengait.control.swing_servo import ServoSettings

    if cycles < 1:
        raise UserInputError(f"--cycles must be at least 1, got {cycles}", field="--cycles")
    pushes = parse_pushes(push) if push else ()
    if pushes and snap:
        raise UserInputError(
            "--push and --snap do not go together",
            field="--push",
            fix="pushes test the gait's own balance: play without --snap",
        )
    media = MediaOptions(
        video=video, bvh=bvh, fps=fps, speed=speed, camera=camera, bvh_units=bvh_units
    ).check()
    refuse_existing([video, bvh], force)
    path = resolve("gait", controller)
    c = load_controller(path)
    if activation_time is not None:
        c = c.model_copy(update={"activation_time": activation_time})
    if servo is not None:
        c = c.model_copy(
            update={"swing_servo": (c.swing_servo or ServoSettings()) if servo else None}
        )
    check_range(plans, "--plans", 2, 4096, fix="use 2 to 4096 plans per decision (default: 96)")
    check_range(slip_weight, "--slip-weight", 0, 1000, fix="use a weight from 0 (off) to 1000")
    check_range(effort_weight, "--effort-weight", 0, 1000, fix="use a weight from 0 (off) to 1000")
    check_range(max_tilt, "--max-tilt", 1, 180, fix="use 1 to 180 degrees from upright")
    check_range(planner_seed, "--planner-seed", 0, 2**32 - 1, fix="use a seed from 0 to 2³²−1")
    overrides = {
        "seed": planner_seed,
        "samples": plans,
        "slip_weight": slip_weight,
        "effort_weight": effort_weight,
        "max_tilt_deg": max_tilt,
    }
    overrides = {k: v for k, v in overrides.items() if v is not None}
    if overrides and c.lookahead is not None:
        c = c.model_copy(update={"lookahead": c.lookahead.model_copy(update=overrides)})
    system = gait_system(c, source=path)
    planner = c.planner() if lookahead and not snap else None
    status = status_console(as_json)
    progress = (
        (lambda k, n: status.print(f"lookahead: cycle {k}/{n}")) if planner is not None else None
    )
    params = to_parameters(c, system, path)
    result = play(
        system,
        params,
        cycles,
        snap=snap,
        pushes=pushes,
        source=path,
        lookahead=planner,
        progress=progress,
    )
    summary = {
        "controller": str(path),
        "character": c.character,
        "activation_time": c.activation_time,
        "swing_servo": c.swing_servo is not None,
        "simbicon": c.simbicon is not None,
        **result.summary(),
        "lookahead_plans": None if planner is None else planner.samples,
        "lookahead_slip_weight": None if planner is None else planner.slip_weight,
        "lookahead_effort_weight": None if planner is None else planner.effort_weight,
        "lookahead_max_tilt_deg": None if planner is None else planner.max_tilt_deg,
        "lookahead_seed": None if planner is None else planner.seed,
    }
    if c.sketch is not None:
        summary.update(sketch_character(system, params, c.sketch, result.torques))
    if as_json:
        print(json_text.dumps(summary))
    else:
        table = Table(title=f"{path.name} on {c.character}")
        table.add_column("metric")
        table.add_column("value", justify="right")
        for k, v in summary.items():
            table.add_row(k, str(v))
        console.print(table)
    write_media(system.world, result.qpos, result.fps, media, status)


def harden_command(
    controller: str = typer.Argument(..., help="Controller file or shipped gait name."),
    output: Path = typer.Option(..., "-o", "--output", help="Run folder."),
    minutes: float = typer.Option(15.0, "--max-minutes", help="Wall-clock budget (min)."),
    seed: int = typer.Option(
        1, "--seed", help="Random seed of the search and of the sampled pushes."
    ),
    popsize: int = typer.Option(12, "--popsize", help="Candidates per generation."),
    copies: int = typer.Option(
        3, "--copies", help="Plays per candidate: one undisturbed, the others pushed."
    ),
    impulse: float = typer.Option(
        0.6, "--push-impulse", help="Largest sampled push (N·s per kg of body mass)."
    ),
    horizon: int = typer.Option(
        8, "--horizon", help="Cycles played at the start (grows as candidates survive)."
    ),
    max_slip: float = typer.Option(
        0.03,
        "--max-slip",
        help="Stance-foot slip penalized beyond this (m, mean per stance; 0: not penalized).",
    ),
    workers: int = typer.Option(1, "--workers", help="Simulation threads."),
    speed_weight: float = typer.Option(
        0.5,
        "--speed-weight",
        help="Cost of falling short of the target speed by all of it (falling at once costs 1).",
    ),
    assist: float = typer.Option(
        0.0,
        "--assist",
        help="Start every play with a hand on the root at this level (1: it cancels gravity's "
        "toppling moment), weakened as candidates survive (0: none).",
    ),
    sketch: str = typer.Option(
        None,
        "--sketch",
        help="Sketch file or preset the gait was made from: its timing stays within the bounds "
        "`optimize` kept it in.",
    ),
    paired_feet: bool = typer.Option(
        False,
        "--paired-feet",
        help="Ask the sketch's paired feet (targets.paired_feet) to land together "
        "(needs --sketch).",
    ),
    max_tilt: float = typer.Option(
        0.0, "--max-tilt", help="Root pitch or roll penalized beyond this (degrees; 0: not)."
    ),
    event: bool = typer.Option(
        False,
        "--event",
        help="Also search event-based feedback on the sketch's priority and allowed modes, "
        "read against its mean speed (needs --sketch; no effort term); the gait then plays "
        "without lookahead.",
    ),
    resume: bool = RESUME_OPTION,
    force: bool = START_OVER_OPTION,
):
    """Optimize a gait's survival with no reset under sampled sideways pushes (pulses, timing, hip
    feedback, optionally event feedback; foot slip, tilt and footfall pattern)."""
    from eigengait.control.binding import gait_system
    from eigengait.control.controller import load_controller, to_parameters
    from eigengait.control.library import resolve
    from eigengait.control.playback import play
    from eigengait.optimize.survival import (
        CHECKPOINT,
        StartingFigures,
        SurvivalSettings,
        event_settings,
        harden,
    )

    for value, option, low, high in (
        (minutes, "--max-minutes", 0.01, 1e6),
        (popsize, "--popsize", 4, 10_000),
        (copies, "--copies", 1, 100),
        (impulse, "--push-impulse", 0.0, 10.0),
        (horizon, "--horizon", 4, 100),
        (max_slip, "--max-slip", 0.0, 10.0),
        (max_tilt, "--max-tilt", 0.0, 180.0),
        (workers, "--workers", 1, 1024),
        (speed_weight, "--speed-weight", 0.0, 100.0),
        (assist, "--assist", 0.0, 100.0),
    ):
        check_range(value, option, low, high)
    _refuse_force_with_resume(force, resume)
    for wanted, option, why in (
        (event, "--event", "searches the feedback on the sketch's modes"),
        (paired_feet, "--paired-feet", "reads the feet from the sketch's targets"),
    ):
        if wanted and not sketch:
            raise UserInputError(
                f"{option} {why}",
                field=option,
                fix="pass --sketch with the sketch the gait was made from",
            )
    path = resolve("gait", controller)
    c = load_controller(path)
    made_from = _gait_sketch(sketch, c.character) if sketch else None
    system = gait_system(c, source=path)
    start = to_parameters(c, system, path)
    check_folder(output)
    if (output / CHECKPOINT).exists() and not (resume or force):
        raise UserInputError(
            "the folder holds an earlier survival run and was left untouched",
            file=output,
            fix="pass --resume to continue it, or add --force to start over",
        )
    settings = SurvivalSettings(
        minutes=minutes,
        seed=seed,
        popsize=popsize,
        copies=copies,
        push_impulse=(min(0.2, impulse), impulse),
        horizon=horizon,
        max_horizon=max(24, horizon),
        max_slip=max_slip or None,
        threads=workers,
        max_tilt_deg=max_tilt or None,
        speed_weight=speed_weight,
        assist=assist or None,
        paired_feet=tuple(made_from.targets.paired_feet) if paired_feet else (),
        **(event_settings(made_from) if event else {}),
    )
    before = play(system, start, cycles=20, source=path)
    figures = StartingFigures.of(before)
    planner = None if event else c.planner()
    result = harden(
        system,
        start,
        figures,
        output,
        settings,
        resume,
        c.name,
        console.print,
        lookahead=planner,
        sketch=c.sketch,
        timing=made_from.timing if made_from else None,
    )
    after = play(system, result, cycles=20)
    console.print(
        f"survival with no reset (20 cycles): {before.cycles_completed} -> "
        f"{after.cycles_completed} cycles; speed {before.mean_speed_mps:.2f} -> "
        f"{after.mean_speed_mps:.2f} m/s; mean squared torque {before.mean_squared_torque:.0f} -> "
        f"{after.mean_squared_torque:.0f} (N·m)²; stance slip {_slip_cm(before)} -> "
        f"{_slip_cm(after)}"
    )
    console.print(f"run folder: {output} (best_controller.json, log.csv, {CHECKPOINT})")


def _gait_sketch(sketch: str, character: str):
    """`sketch` (a preset or file), refused unless it is a sketch of `character`."""
    from eigengait.control.library import resolve
    from eigengait.control.sketch import load_sketch

    path = resolve("sketch", sketch)
    loaded = load_sketch(path)
    if loaded.character != character:
        raise UserInputError(
            f"the sketch is for character '{loaded.character}', the gait for '{character}'",
            file=path,
            field="--sketch",
            fix=f"pass the sketch the gait was made from (a sketch of '{character}')",
        )
    return loaded


def _slip_cm(played) -> str:
    """A played gait's `stance_slip_max_m` in cm ("n/a" without a stance)."""
    metres = played.quality.get("stance_slip_max_m")
    return "n/a" if metres is None else f"{100 * metres:.1f} cm"


def gaits_command(as_json: bool = typer.Option(False, "--json", help="Print JSON.")):
    """List the shipped optimized gaits."""
    from eigengait.control.controller import load_controller
    from eigengait.control.library import gait_names, resolve

    rows = []
    for name in gait_names():
        c = load_controller(resolve("gait", name))
        rows.append(
            {
                "name": name,
                "character": c.character,
                "feet": c.feet,
                "period_s": round(c.period, 3),
                **{
                    k: c.metrics[k] for k in ("mean_speed_mps", "cycle_violation") if k in c.metrics
                },
            }
        )
    if as_json:
        print(json_text.dumps(rows))
        return
    table = Table(title="Shipped gaits")
    for col in ("name", "character", "period (s)", "speed (m/s)", "cycle violation"):
        table.add_column(col)
    for r in rows:
        table.add_row(
            r["name"],
            r["character"],
            str(r["period_s"]),
            f"{r.get('mean_speed_mps', float('nan')):.2f}",
            f"{r.get('cycle_violation', float('nan')):.3g}",
        )
    console.print(table)


def demo_command(
    output: Path = typer.Option(
        Path("out/demo"), "--output", help="Parent folder; each demo gets a new subfolder."
    ),
    evaluations: int = typer.Option(
        200000, "--max-evaluations", help="Optimization budget (evaluations)."
    ),
    minutes: float = typer.Option(
        6.0, "--max-minutes", help="Optimization budget (wall-clock minutes)."
    ),
    harden_minutes: float = typer.Option(
        2.0,
        "--harden-minutes",
        help="Survival optimization under sampled pushes after it (minutes; 0: none).",
    ),
    seed: int = typer.Option(1, "--seed"),
):
    """The main job on the humanoid: modes -> palette -> basic-run sketch -> optimization ->
    hardening -> playback -> video, BVH."""
    from eigengait.character import load_character
    from eigengait.control.binding import gait_system
    from eigengait.control.controller import load_controller, to_parameters
    from eigengait.control.library import resolve
    from eigengait.control.playback import play
    from eigengait.control.sketch import load_sketch
    from eigengait.modal import compute_modes
    from eigengait.optimize.mom import MomSettings
    from eigengait.optimize.staged import optimize_gait
    from eigengait.optimize.survival import StartingFigures, SurvivalSettings, harden
    from eigengait.render.palette import write_palette
    from eigengait.sim import WorldOptions, build_world

    check_range(harden_minutes, "--harden-minutes", 0, 1e6)
    folder = _new_folder(output, datetime.now().strftime("run-%Y%m%d-%H%M%S"))
    t0 = time.perf_counter()
    character = load_character("humanoid")
    world = build_world(character, options=WorldOptions(gravity=False))
    modes = {phase: compute_modes(world, phase) for phase in ("air", "ground")}
    for phase, mode_set in modes.items():
        mode_set.save(folder / f"modes_{phase}.npz")
        write_palette(world, mode_set, folder / f"palette_{phase}.png")
    from eigengait.motion.modal_mix import build_mix, mix_trajectory, parse_mix

    kinematic = build_mix(
        world, modes["air"], parse_mix(DEMO_KINEMATIC_MIX), base_hz=DEMO_KINEMATIC_BASE_HZ
    )
    _, qpos = mix_trajectory(world, kinematic, seconds=4.0, fps=30.0)
    console.print(
        f"[1/5] modes and palettes: {folder}/palette_air.png, palette_ground.png; "
        f"kinematic two-mode gait (air modes {DEMO_KINEMATIC_MIX}):"
    )
    write_media(
        world, qpos, 30.0, MediaOptions(folder / "kinematic.mp4", folder / "kinematic.bvh"), console
    )
    sketch_path = resolve("sketch", "basic-run")
    sketch = load_sketch(sketch_path)
    state = optimize_gait(
        sketch,
        folder / "optimization",
        MomSettings(
            seed=seed,
            max_evaluations=evaluations,
            max_seconds=minutes * 60,
            inner_generations=100,
            cycle_tolerance=sketch.targets.cycle_tolerance,
        ),
        sketch_source=sketch_path,
    )
    console.print(
        f"[2/5] optimization ({state.finished}): cycle violation {state.best.violation:.3g}, "
        f"{state.evaluations} evaluations in {state.elapsed:.0f} s"
    )
    c = load_controller(folder / "optimization" / "best_controller.json")
    system = gait_system(c)
    params = to_parameters(c, system)
    if harden_minutes > 0:
        before = play(system, params, cycles=20)
        figures = StartingFigures.of(before)
        settings = SurvivalSettings(minutes=harden_minutes, seed=seed, threads=os.cpu_count() or 1)
        params = harden(
            system,
            params,
            figures,
            folder / "hardening",
            settings,
            progress=lambda _: None,
            timing=sketch.timing,
        )
        after = play(system, params, cycles=20)
        console.print(
            f"[3/5] hardening under sampled pushes ({harden_minutes:g} min): without lookahead it "
            f"survives {before.cycles_completed} -> {after.cycles_completed} of 20 cycles "
            f"({folder}/hardening/best_controller.json)"
        )
    planner = c.planner()
    result = play(system, params, cycles=20, lookahead=planner)
    write_atomically(folder / "playback.json", json_text.dumps(result.summary(), indent=2))
    console.print(f"[4/5] playback: {json_text.dumps(result.summary())}")
    write_media(
        system.world,
        result.qpos,
        result.fps,
        MediaOptions(folder / "gait.mp4", folder / "gait.bvh"),
        console,
    )
    console.print(f"[5/5] done in {time.perf_counter() - t0:.0f} s. Outputs in {folder}")


def _new_folder(parent: Path, name: str) -> Path:
    """A new, empty subfolder `name` of `parent` (`name-2`, `name-3`, ... if taken)."""
    check_folder(parent)
    for attempt in range(1, 100):
        folder = parent / (name if attempt == 1 else f"{name}-{attempt}")
        try:
            folder.mkdir()
            return folder
        except FileExistsError:
            continue
    raise UserInputError(
        "cannot find a free name for the demo's folder", file=parent, fix="choose another --output"
    )


def register(app: typer.Typer) -> None:
    app.command("sketch")(sketch_command)
    app.command("optimize")(optimize_command)
    app.command("play")(play_command)
    app.command("harden")(harden_command)
    app.command("gaits")(gaits_command)
    app.command("demo")(demo_command)
