"""`eigengait palette` and `eigengait animate`: look at a character's modes and animate mixes of
them.

Mode numbers start at 1 for the lowest non-rigid mode. Outputs that already exist are left untouched
unless --force is given.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from eigengait.cli.character import PARTNER_OPTION, RELAX_OPTION
from eigengait.cli.media import BVH_UNITS_OPTION, CAMERA_OPTION, SPEED_OPTION, MediaOptions
from eigengait.errors import UserInputError
from eigengait.inputs import check_range
from eigengait.outputs import refuse_existing, require_suffix
from eigengait.modal.shape_kinematics import DEFAULT_MAX_ROTATION_DEG

console = Console()

MIX_HELP = (
    "Modes to mix: MODE:AMPLITUDE or MODE:AMPLITUDE@PHASE_DEGREES, comma separated, e.g. "
    "'1:0.5,3:0.3@90'. MODE is the mode number (1 = lowest frequency); AMPLITUDE is relative to "
    "the equal-energy default (1 = every mode the same energy, the widest mode turning a joint "
    "--angle degrees); PHASE is the phase of the sine in degrees (default 0)."
)


def _world_and_modes(
    character: str,
    phase: str,
    foot: Optional[str],
    relax: Optional[str],
    partners: Optional[list[str]],
):
    from eigengait.character import load_character
    from eigengait.character.relax import parse_relax_argument
    from eigengait.modal import compute_modes
    from eigengait.sim.world import WorldOptions, build_world

    world = build_world(
        load_character(character), parse_relax_argument(relax), WorldOptions(gravity=False)
    )
    return world, compute_modes(world, phase, foot, partners=partners or ())


def palette_command(
    character: str = typer.Argument(..., help="Built-in name or MJCF path."),
    phase: str = typer.Option(
        "air", "--phase", help="air (free body) or ground (stance toe pinned)."
    ),
    foot: Optional[str] = typer.Option(None, "--foot", help="Stance foot for the ground phase."),
    partners: Optional[list[str]] = PARTNER_OPTION,
    relax: Optional[str] = RELAX_OPTION,
    output: Path = typer.Option(Path("palette.png"), "-o", "--output", help="PNG file to write."),
    count: Optional[int] = typer.Option(None, "--modes", help="Show modes 1..N (default: all)."),
    columns: Optional[int] = typer.Option(
        None, "--columns", min=1, help="Tiles per row (default: about square)."
    ),
    tile: int = typer.Option(240, "--tile", min=32, max=2048, help="Tile size in pixels (even)."),
    angle: float = typer.Option(
        DEFAULT_MAX_ROTATION_DEG, "--angle", help="Peak joint rotation shown, degrees."
    ),
    force: bool = typer.Option(False, "--force", help="Overwrite an existing file."),
):
    """Palette image: one tile per mode, its −A and +A extremes over the relax pose, with
    frequencies."""
    from eigengait.render.palette import write_palette

    require_suffix(output, (".png",), "--output")
    check_range(angle, "--angle", 0.1, 180, "degrees")
    refuse_existing([output], force)
    world, modes = _world_and_modes(character, phase, foot, relax, partners)
    image = write_palette(world, modes, output, count, columns, tile, angle)
    console.print(
        f"wrote {output} ({image.shape[1]}×{image.shape[0]} px, {count or modes.count} modes)"
    )


def animate_command(
    character: str = typer.Argument(..., help="Built-in name or MJCF path."),
    mix: str = typer.Option(..., "--mix", help=MIX_HELP),
    phase: str = typer.Option(
        "air", "--phase", help="air (free body) or ground (stance toe pinned)."
    ),
    foot: Optional[str] = typer.Option(None, "--foot", help="Stance foot for the ground phase."),
    partners: Optional[list[str]] = PARTNER_OPTION,
    relax: Optional[str] = RELAX_OPTION,
    seconds: float = typer.Option(4.0, "--seconds", help="Duration in seconds."),
    fps: float = typer.Option(30.0, "--fps", help="Frames per second of the video and the BVH."),
    angle: float = typer.Option(
        DEFAULT_MAX_ROTATION_DEG,
        "--angle",
        help="Joint rotation (degrees) of the widest mode at relative amplitude 1.",
    ),
    base_hz: Optional[float] = typer.Option(
        None,
        "--base-hz",
        help="Move each mode's frequency to the nearest multiple of this "
        "(Hz), so the motion loops every 1/base-hz seconds.",
    ),
    video: Optional[Path] = typer.Option(
        None, "--video", help="Video to write: .mp4 (H.264) or .gif."
    ),
    bvh: Optional[Path] = typer.Option(
        None, "--bvh", help="BVH file to write (y-up; unit: --bvh-units)."
    ),
    bvh_units: str = BVH_UNITS_OPTION,
    speed: float = SPEED_OPTION,
    camera: str = CAMERA_OPTION,
    width: int = typer.Option(640, "--width", help="Video width in pixels (even)."),
    height: int = typer.Option(480, "--height", help="Video height in pixels (even)."),
    force: bool = typer.Option(False, "--force", help="Overwrite existing files."),
):
    """Kinematic mode animation: x(t) = Σ A_i φ_i sin(2π f_i t + ϕ_i) about the relax pose (no
    physics).

    Example: eigengait animate humanoid --mix "2:1,11:0.5@90" --video run.mp4 --bvh run.bvh
    """
    from eigengait.motion.bvh_export import write_trajectory_bvh
    from eigengait.modal.shape_kinematics import joint_rotations
    from eigengait.motion.modal_mix import build_mix, mix_trajectory, parse_mix
    from eigengait.render.video import CameraView, render_video

    if video is None and bvh is None:
        raise UserInputError(
            "nothing to write",
            field="--video/--bvh",
            fix="give --video out.mp4 and/or --bvh out.bvh",
        )
    require_suffix(video, (".mp4", ".gif"), "--video")
    require_suffix(bvh, (".bvh",), "--bvh")
    MediaOptions(video, bvh, fps, speed, camera, bvh_units).check()
    check_range(angle, "--angle", 0.1, 180, "degrees")
    check_range(seconds, "--seconds", 0.01, 3600, "s")
    check_range(base_hz, "--base-hz", 0.01, 100, "Hz")
    refuse_existing([video, bvh], force)
    terms = parse_mix(mix)
    world, modes = _world_and_modes(character, phase, foot, relax, partners)
    modal_mix = build_mix(world, modes, terms, angle, base_hz)
    times, qpos = mix_trajectory(world, modal_mix, seconds, fps)

    table = Table(title=f"{modes.character} — {modes.phase}-phase mix")
    for col in (
        "mode",
        "frequency (Hz)",
        "relative amplitude",
        "A (√kg·m)",
        "peak joint rotation (°)",
        "phase (°)",
    ):
        table.add_column(col, justify="right")
    peaks = joint_rotations(world, modal_mix.shapes * modal_mix.amplitudes).max(axis=0)
    for term, f, a, peak in zip(terms, modal_mix.frequencies_hz, modal_mix.amplitudes, peaks):
        table.add_row(
            str(term.mode),
            f"{f:.3f}",
            f"{term.amplitude:g}",
            f"{a:.4f}",
            f"{np.rad2deg(peak):.1f}",
            f"{term.phase_deg:g}",
        )
    period = modal_mix.period()
    table.caption = (
        f"loops every {period:.3f} s"
        if period
        else "frequencies are not commensurate: no exact loop"
    )
    console.print(table)

    if video is not None:
        start = time.perf_counter()
        frames = render_video(
            world,
            qpos,
            fps,
            video,
            width,
            height,
            CameraView(follow=camera == "follow"),
            progress=True,
            fps=fps,
            speed=speed,
        )
        elapsed = time.perf_counter() - start
        console.print(
            f"wrote {video} ({frames} frames, {width}×{height}, {frames / elapsed:.1f} frames/s)"
        )
    if bvh is not None:
        clip = write_trajectory_bvh(world, qpos, fps, bvh, units=bvh_units)
        console.print(f"wrote {bvh} ({clip.n_frames} frames, {len(clip.joints)} joints)")


def register(app: typer.Typer) -> None:
    """Add the `palette` and `animate` commands to the `eigengait` app."""
    app.command("palette")(palette_command)
    app.command("animate")(animate_command)
