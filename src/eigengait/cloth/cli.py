"""``eigengait cloth``: run FLEX3D scripts, list the shipped examples, draw vibration modes."""

from __future__ import annotations

import re
import sys
import warnings
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn
from rich.table import Table

from eigengait.cloth.integrators import INTEGRATORS
from eigengait.cloth.library import EXAMPLES, resolve_script
from eigengait.cloth.model import script_model
from eigengait.cloth.obt import read_obt
from eigengait.cloth.output import staged_output, write_frame
from eigengait.cloth.par import read_par
from eigengait.cloth.strain import DEFAULT_BOUND
from eigengait.errors import UserInputError

app = typer.Typer(help="Deformable surfaces (FLEX3D, Nedel 1993): run .PAR scripts, examples, vibration modes.",
                  no_args_is_help=True, add_completion=False)
console = Console()
errors = Console(stderr=True)


def _fail(error: UserInputError) -> typer.Exit:
    errors.print(f"[bold red]error:[/] {error}", highlight=False, soft_wrap=True)
    return typer.Exit(2)


def _warn(caught) -> None:
    for w in caught:
        errors.print(f"[yellow]warning:[/] {w.message}", highlight=False, soft_wrap=True)


def _progress() -> Progress:
    return Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn(),
                    console=errors)


@app.command("examples")
def examples() -> None:
    """List the dissertation's example scenes shipped with eigengait."""
    table = Table("name", "scene", title="shipped FLEX3D examples (run: eigengait cloth run NAME -o DIR)")
    for name, (_, description) in EXAMPLES.items():
        table.add_row(name, description)
    console.print(table)


@app.command("run")
def run(script: str = typer.Argument(..., help="a .PAR file or a shipped example name (see 'examples')"),
        output: Path = typer.Option(..., "-o", "--output", help="folder for the frames"),
        integrator: str = typer.Option("euler", help=f"one of: {', '.join(INTEGRATORS)}"),
        video: Optional[Path] = typer.Option(None, help="MP4 path (default: DIR/<script>.mp4)"),
        duration: Optional[float] = typer.Option(None, help="simulate this many seconds instead of DURACAO"),
        time_step: Optional[float] = typer.Option(None, "--time-step", help="override DELTA_t (s)"),
        no_gravity: bool = typer.Option(False, "--no-gravity", help="switch gravity off"),
        no_render: bool = typer.Option(False, "--no-render", help="write .OBT/.obj frames only"),
        self_collision: bool = typer.Option(False, "--self-collision", help="collide surfaces with themselves"),
        restitution: float = typer.Option(0.0, help="normal restitution at contacts, 0..1 (1 = FLEX3D elastic)"),
        strain_limit: float = typer.Option(DEFAULT_BOUND, help="largest spring strain kept (0.1 = 10 %); 0 = off"),
        thickness: Optional[float] = typer.Option(None, help="contact gap in m (default 5 % of the spacing)"),
        floor: Optional[float] = typer.Option(None, help="floor plane at this height (m, world z; PISO in scripts)"),
        dissertation: bool = typer.Option(False, "--dissertation",
                                          help="FLEX3D as published: no strain limit, swept hits only"),
        video_fps: float = typer.Option(10.0, help="frames per second of the video")) -> None:
    """Simulate a script and write <NAME>_<frame>.OBT, obj/<NAME>_<frame>.obj, png/ frames and a video."""
    from eigengait.cloth.render import CAMERAS, render_run
    from eigengait.cloth.simulate import run_frames

    try:
        path = resolve_script(script)
        parsed = read_par(path)
        obstacles = [read_obt(p) for p in parsed.obstacles]
        model = script_model(parsed, obstacles, gravity=not no_gravity)
        if duration is not None and duration <= 0:
            raise UserInputError("--duration must be positive.", field="--duration")
        if not 0.0 <= restitution <= 1.0:
            raise UserInputError("--restitution must be between 0 and 1.", field="--restitution")
        if strain_limit < 0.0:
            raise UserInputError("--strain-limit must not be negative.", field="--strain-limit")
        if thickness is not None and thickness <= 0.0:
            raise UserInputError("--thickness must be positive.", field="--thickness")
        if integrator not in INTEGRATORS:
            raise UserInputError(f"unknown integrator '{integrator}'.", field="--integrator",
                                 fix=f"use one of: {', '.join(INTEGRATORS)}.")
        h = time_step or parsed.time_step
        step_field = f"line {parsed.lines.get('DELTA_T', '?')}: DELTA_t" if time_step is None else "--time-step"
        total = duration or parsed.duration
        count = int(total * parsed.frames_per_second + 1e-9) + 1
        positions = []
        with staged_output(output) as staging, warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            frames = run_frames(model, time_step=h, duration=total, frames_per_second=parsed.frames_per_second,
                                integrator=integrator, source=str(path), step_field=step_field,
                                self_collision=self_collision or parsed.self_collision, restitution=restitution,
                                strain_limit=strain_limit or None, thickness=thickness,
                                floor=floor if floor is not None else parsed.floor, dissertation=dissertation)
            with _progress() as progress:
                task = progress.add_task(f"simulating {path.name} ({integrator})", total=count)
                for frame in frames:
                    _warn(caught), caught.clear()
                    write_frame(model, frame.positions, frame.index, staging)
                    positions.append((frame.time, frame.positions))
                    progress.advance(task)
                if not no_render:
                    (staging / "png").mkdir()
                    target = video or output / f"{path.stem}.mp4"
                    staged_video = staging / target.name if target.parent.resolve() == output.resolve() else None
                    render_task = progress.add_task("rendering", total=len(positions))
                    render_run(model, positions, staging / "png", staged_video or target,
                               camera=CAMERAS.get(path.stem, (20, -60)), title=path.stem, fps=video_fps,
                               on_frame=lambda: progress.advance(render_task))
    except UserInputError as error:
        raise _fail(error) from None
    console.print(f"wrote {count} frames of {len(model.surfaces)} surface(s) to {output}"
                  + ("" if no_render else f" and the video {video or output / f'{path.stem}.mp4'}"))


_SIZE = re.compile(r"^(\d+)x(\d+)$")


@app.command("modes")
def modes(target: str = typer.Argument(..., help="a .PAR file, an example name, or a size like 20x20"),
          palette: Optional[Path] = typer.Option(None, help="PNG with one tile per mode"),
          count: int = typer.Option(9, help="number of modes"),
          stretch: float = typer.Option(1.05, help="pre-stretch of a size-given membrane (boundary pinned)"),
          spacing: float = typer.Option(1.0, help="rest spacing (m) of a size-given membrane"),
          mass: float = typer.Option(0.01, help="mass per point (kg) of a size-given membrane"),
          stiffness: float = typer.Option(100.0, help="spring constant (N/m) of a size-given membrane")) -> None:
    """Vibration modes: a pinned pre-stretched membrane (SIZE) or a script's surfaces hanging at equilibrium."""
    from eigengait.cloth.modes import draw_palette, equilibrium, membrane, vibration_modes

    try:
        if count < 1:
            raise UserInputError("--count must be at least 1.", field="--count")
        size = _SIZE.match(target)
        if size:
            rows, cols = int(size[1]), int(size[2])
            if rows < 3 or cols < 3 or stretch <= 1.0:
                raise UserInputError("a membrane needs at least 3x3 points and --stretch > 1.", field=target)
            model = membrane(rows, cols, spacing=spacing, mass=mass, stiffness=stiffness, stretch=stretch)
            x = model.rest_positions
        else:
            parsed = read_par(resolve_script(target))
            model = script_model(parsed, [read_obt(p) for p in parsed.obstacles])
            x = equilibrium(model)
        result = vibration_modes(model, x, count)
        table = Table("mode", "frequency (Hz)", "period (s)", title=f"{len(result.frequencies)} lowest modes "
                      f"({result.zero_modes} zero modes dropped)")
        for k, f in enumerate(result.frequencies, start=1):
            table.add_row(str(k), f"{f:.5g}", f"{1 / f:.4g}")
        console.print(table)
        if palette is not None:
            draw_palette(model, result, palette)
            console.print(f"palette written to {palette}")
    except UserInputError as error:
        raise _fail(error) from None


if __name__ == "__main__":
    app(prog_name=f"{Path(sys.executable).name} -m eigengait.cloth.cli")
