"""``eigengait cloth``: run FLEX3D scripts, list the shipped examples, draw vibration modes."""

from __future__ import annotations

import re
import warnings
from contextlib import ExitStack
from pathlib import Path
from typing import Optional

import numpy as np
import typer
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn
from rich.table import Table

from eigengait.cloth.integrators import INTEGRATORS
from eigengait.cloth.library import EXAMPLES, resolve_script
from eigengait.cloth.model import script_model
from eigengait.cloth.obt import read_obt
from eigengait.cloth.output import staged_file, staged_output, write_frame, write_manifest
from eigengait.cloth.par import read_par
from eigengait.cloth.strain import DEFAULT_BOUND
from eigengait.cli.flags import for_command_line, keywords_as_flags
from eigengait.errors import EigengaitError, UserInputError
from eigengait.inputs import check_choice, check_range
from eigengait.outputs import check_output

console = Console()
errors = Console(stderr=True)


def _fail(error: EigengaitError) -> typer.Exit:
    errors.print(f"[bold red]error:[/] {for_command_line(error)}", highlight=False, soft_wrap=True)
    return typer.Exit(2)


def _warn(caught) -> None:
    """Print caught library warnings, their parameters written as this command's flags."""
    for w in caught:
        errors.print(
            f"[yellow]warning:[/] {keywords_as_flags(str(w.message))}",
            highlight=False,
            soft_wrap=True,
        )


def _progress() -> Progress:
    return Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeRemainingColumn(),
        console=errors,
    )


def examples() -> None:
    """List the dissertation's example scenes shipped with eigengait."""
    table = Table(
        "name", "scene", title="shipped FLEX3D examples (run: eigengait cloth run NAME -o DIR)"
    )
    for name, (_, description) in EXAMPLES.items():
        table.add_row(name, description)
    console.print(table)


def run(
    script: str = typer.Argument(
        ..., help="a .PAR file or a shipped example name (see 'examples')"
    ),
    output: Path = typer.Option(
        ..., "-o", "--output", help="folder for the frame set (new, empty, or --force)"
    ),
    integrator: str = typer.Option("euler", help=f"one of: {', '.join(INTEGRATORS)}"),
    video: Optional[Path] = typer.Option(None, help="MP4 path (default: DIR/<script>.mp4)"),
    duration: Optional[float] = typer.Option(
        None, help="simulate this many seconds instead of DURACAO"
    ),
    time_step: Optional[float] = typer.Option(None, "--time-step", help="override DELTA_t (s)"),
    no_gravity: bool = typer.Option(False, "--no-gravity", help="switch gravity off"),
    no_render: bool = typer.Option(False, "--no-render", help="write .OBT/.obj frames only"),
    self_collision: bool = typer.Option(
        False, "--self-collision", help="collide surfaces with themselves"
    ),
    restitution: float = typer.Option(
        0.0, help="normal restitution at contacts, 0..1 (1 = FLEX3D elastic)"
    ),
    strain_limit: float = typer.Option(
        DEFAULT_BOUND, help="largest spring strain kept (0.1 = 10 %); 0 = off"
    ),
    thickness: Optional[float] = typer.Option(
        None, help="contact gap in m (default 5 % of the spacing)"
    ),
    floor: Optional[float] = typer.Option(
        None, help="floor plane at this height (m, world z; PISO in scripts)"
    ),
    dissertation: bool = typer.Option(
        False, "--dissertation", help="FLEX3D as published: no strain limit, swept hits only"
    ),
    video_fps: float = typer.Option(
        30.0, help="video frames per second of simulated time (real-time playback)"
    ),
    force: bool = typer.Option(False, "--force", help="replace an earlier run's frame set in DIR"),
) -> None:
    """Simulate a script and write <NAME>_<frame>.OBT, obj/<NAME>_<frame>.obj, png/ frames, a
    real-time video, a contact sheet and run.json."""
    from eigengait.cloth.simulate import frame_steps, run_samples, video_steps

    try:
        path = resolve_script(script)
        parsed = read_par(path)
        obstacles = [read_obt(p) for p in parsed.obstacles]
        model = script_model(parsed, obstacles, gravity=not no_gravity)
        _check_options(
            duration, time_step, restitution, strain_limit, thickness, integrator, video_fps
        )
        h = time_step or parsed.time_step
        step_field = (
            f"line {parsed.lines.get('DELTA_T', '?')}: DELTA_t"
            if time_step is None
            else "--time-step"
        )
        total = duration or parsed.duration
        check_range(floor, "--floor", -1e6, 1e6, "m")
        floor = floor if floor is not None else parsed.floor
        frames = frame_steps(h, total, parsed.frames_per_second, str(path), step_field)
        shots = None if no_render else video_steps(h, total, video_fps)
        target = None if no_render else (video or output / f"{path.stem}.mp4")
        if target is not None and not _inside(target, output):
            check_output(target, force)
        with ExitStack() as stack:
            staging = stack.enter_context(staged_output(output, force))
            caught = stack.enter_context(warnings.catch_warnings(record=True))
            warnings.simplefilter("always")
            steps = frames if shots is None else np.union1d(frames, shots)
            samples = run_samples(
                model,
                steps,
                time_step=h,
                integrator=integrator,
                source=str(path),
                step_field=step_field,
                self_collision=self_collision or parsed.self_collision,
                restitution=restitution,
                strain_limit=strain_limit or None,
                thickness=thickness,
                floor=floor,
                dissertation=dissertation,
            )
            states = _simulate(
                model,
                samples,
                steps,
                frames,
                staging,
                f"simulating {path.name} ({integrator})",
                caught,
            )
            summary = {
                "script": str(path),
                "integrator": integrator,
                "time_step_s": h,
                "duration_s": total,
                "floor_m": floor,
                "frames": {"count": len(frames), "per_second": parsed.frames_per_second},
                "video": None,
            }
            if target is not None:
                staged = (
                    staging / target.resolve().relative_to(output.resolve())
                    if _inside(target, output)
                    else stack.enter_context(staged_file(target))
                )
                _render(model, states, frames, shots, staging, staged, path.stem, video_fps, floor)
                summary["video"] = {
                    "path": str(target),
                    "fps": video_fps,
                    "frames": len(shots),
                    "duration_s": len(shots) / video_fps,
                    "sheet": f"{path.stem}_sheet.png",
                }
            write_manifest(staging, summary)
    except EigengaitError as error:
        raise _fail(error) from None
    console.print(
        (
            f"wrote {len(frames)} frames ({parsed.frames_per_second:g} per simulated second, "
            f"{total:g} s) of {len(model.surfaces)} surface(s) to {output}"
        )
        + (
            ""
            if target is None
            else f" and the video {target}: {len(shots)} frames at {video_fps:g} fps, "
            f"{len(shots) / video_fps:.2f} s (real time)"
        )
    )


def _check_options(
    duration, time_step, restitution, strain_limit, thickness, integrator, video_fps
) -> None:
    """Raise :class:`UserInputError` for an impossible ``run`` option."""
    check_range(duration, "--duration", 1e-6, 1e6, "s")
    check_range(time_step, "--time-step", 1e-7, 1.0, "s")
    check_range(restitution, "--restitution", 0.0, 1.0)
    check_range(strain_limit, "--strain-limit", 0.0)
    check_range(thickness, "--thickness", 1e-9, unit="m")
    check_range(video_fps, "--video-fps", 1e-3, 1000, "frames/s")
    check_choice(integrator, INTEGRATORS, "integrator", "--integrator")


def _inside(path: Path, folder: Path) -> bool:
    return path.resolve().is_relative_to(folder.resolve())


def _simulate(model, samples, steps, frames, staging: Path, label: str, caught) -> dict:
    """Write the script's frames (step counts ``frames``) into ``staging`` as they come; return
    every sample as {step: (time s, positions (N, 3) m)}."""
    index = {int(step): k for k, step in enumerate(frames)}
    states = {}
    with _progress() as progress:
        task = progress.add_task(label, total=len(steps))
        for sample, step in zip(samples, steps.tolist()):
            _warn(caught), caught.clear()
            if step in index:
                write_frame(model, sample.positions, index[step], staging)
            states[step] = (sample.time, sample.positions)
            progress.advance(task)
    return states


def _render(
    model, states: dict, frames, shots, staging: Path, video: Path, name: str, fps: float, floor
) -> None:
    """PNGs of the script's frames, the video of ``shots`` at ``fps`` and the contact sheet, into
    ``staging``."""
    from eigengait.cloth.render import CAMERAS, render_run

    (staging / "png").mkdir()
    video.parent.mkdir(parents=True, exist_ok=True)
    with _progress() as progress:
        task = progress.add_task("rendering", total=len(set(frames.tolist()) | set(shots.tolist())))
        render_run(
            model,
            states,
            frames.tolist(),
            shots.tolist(),
            staging / "png",
            video,
            fps=fps,
            camera=CAMERAS.get(name, (20, -60)),
            title=name,
            floor=floor,
            sheet=staging / f"{name}_sheet.png",
            on_frame=lambda: progress.advance(task),
        )


_SIZE = re.compile(r"^(\d+)x(\d+)$")


def modes(
    target: str = typer.Argument(..., help="a .PAR file, an example name, or a size like 20x20"),
    palette: Optional[Path] = typer.Option(None, help="PNG with one tile per mode"),
    count: int = typer.Option(9, help="number of modes"),
    stretch: float = typer.Option(
        1.05, help="pre-stretch of a size-given membrane (boundary pinned)"
    ),
    spacing: float = typer.Option(1.0, help="rest spacing (m) of a size-given membrane"),
    mass: float = typer.Option(0.01, help="mass per point (kg) of a size-given membrane"),
    stiffness: float = typer.Option(100.0, help="spring constant (N/m) of a size-given membrane"),
) -> None:
    """Vibration modes: a pinned pre-stretched membrane (SIZE) or a script's surfaces hanging at
    equilibrium."""
    from eigengait.cloth.modes import draw_palette, equilibrium, membrane, vibration_modes

    try:
        if count < 1:
            raise UserInputError("--count must be at least 1.", field="--count")
        size = _SIZE.match(target)
        if size:
            rows, cols = int(size[1]), int(size[2])
            if rows < 3 or cols < 3 or stretch <= 1.0:
                raise UserInputError(
                    "a membrane needs at least 3x3 points and --stretch > 1.", field=target
                )
            model = membrane(
                rows, cols, spacing=spacing, mass=mass, stiffness=stiffness, stretch=stretch
            )
            x = model.rest_positions
        else:
            parsed = read_par(resolve_script(target))
            model = script_model(parsed, [read_obt(p) for p in parsed.obstacles])
            x = equilibrium(model)
        result = vibration_modes(model, x, count)
        table = Table(
            "mode",
            "frequency (Hz)",
            "period (s)",
            title=(
                f"{len(result.frequencies)} lowest modes ({result.zero_modes} zero modes dropped)"
            ),
        )
        for k, f in enumerate(result.frequencies, start=1):
            table.add_row(str(k), f"{f:.5g}", f"{1 / f:.4g}")
        console.print(table)
        if palette is not None:
            draw_palette(model, result, palette)
            console.print(f"palette written to {palette}")
    except EigengaitError as error:
        raise _fail(error) from None


def register(app: typer.Typer) -> None:
    """Add the `cloth` command group: examples, run, modes."""
    cloth = typer.Typer(help="The FLEX3D deformable-surface simulator.", no_args_is_help=True)
    cloth.command("examples")(examples)
    cloth.command("run")(run)
    cloth.command("modes")(modes)
    app.add_typer(cloth, name="cloth")
