"""`eigengait balance`: stand in a pose with no motion capture and recover from sideways pushes.

The chapter's reference-free mode (control/balance/standing.py): the tracker holds the standing
pose.
"""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional

import typer

from eigengait import json_text
from eigengait.cli.balance_options import (
    CONTROLLER_OPTION,
    FOOT_FRICTION_OPTION,
    FOOT_HEIGHT_OPTION,
    FOOT_RADIUS_OPTION,
    ROBUSTNESS_OPTION,
    balance_settings,
)
from eigengait.cli.media import (
    CAMERA_OPTION,
    FPS_OPTION,
    SPEED_OPTION,
    MediaOptions,
    status_console,
    write_media,
)
from eigengait.errors import UserInputError
from eigengait.inputs import check_range
from eigengait.outputs import refuse_existing

MAX_DURATION_S = 600.0
PUSH_HELP = (
    "Sideways push on the root body, as for `play`: FORCE@TIME[,...] (N along +y for 0.1 s, at s), "
    "e.g. 350@1.0; repeat the option or separate pushes with commas."
)


def register(app: typer.Typer) -> None:
    """Add the `balance` command to the CLI."""

    @app.command("balance")
    def balance_command(
        character: str = typer.Argument(
            ..., help="Built-in character name or MJCF path (e.g. walker)."
        ),
        pose: str = typer.Option(
            "default", "--pose", help="Relax pose to stand in: default or a sidecar preset."
        ),
        robustness: float = ROBUSTNESS_OPTION,
        controller: str = CONTROLLER_OPTION,
        foot_radius: float = FOOT_RADIUS_OPTION,
        foot_height: float = FOOT_HEIGHT_OPTION,
        foot_friction: float = FOOT_FRICTION_OPTION,
        push: Optional[List[str]] = typer.Option(None, "--push", help=PUSH_HELP),
        duration: float = typer.Option(3.0, "--duration", help="Simulated time (s)."),
        video: Optional[Path] = typer.Option(
            None, "--video", help="Write the simulated motion to this .mp4 or .gif."
        ),
        fps: float = FPS_OPTION,
        speed: float = SPEED_OPTION,
        camera: str = CAMERA_OPTION,
        force: bool = typer.Option(False, "--force", help="Overwrite an existing --video file."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Stand in a pose with no motion capture and recover from sideways pushes (balance
        controller)."""
        from eigengait.character import load_character
        from eigengait.control.balance.pushes import sideways_pushes
        from eigengait.control.balance.standing import stand
        from eigengait.control.balance.tracker import TrackerSettings, check_controller
        from eigengait.motion.tracking import measure_simulated_feet
        from eigengait.sim.world import build_world

        foot = balance_settings(robustness, foot_radius, foot_height, foot_friction)
        check_controller(controller)
        check_range(duration, "--duration", 0.01, MAX_DURATION_S, unit="s")
        media = MediaOptions(video=video, fps=fps, speed=speed, camera=camera).check()
        refuse_existing([video], force)
        loaded = load_character(character, stiffness="auto")  # the tracker's springs are off
        _check_pose(loaded, pose)
        world = build_world(loaded, pose)
        pushes = sideways_pushes(push or [], world.model.body(world.root_body).name)
        late = [p for p in pushes if p.time_s >= duration]
        if late:
            raise UserInputError(
                f"push at {late[0].time_s:g} s comes after the end of the run ({duration:g} s)",
                field="--push",
                fix="give a push time below --duration, or a longer --duration",
            )
        settings = TrackerSettings(controller=controller, **foot)
        result = stand(world, robustness, duration, pushes, settings)
        run = result.tracking
        measure_simulated_feet(world, run)
        write_media(world, run.qpos, 1.0 / run.frame_time, media, status_console(as_json))
        summary = {
            "character": loaded.name,
            "pose": pose,
            "controller": controller,
            **result.summary(),
            **foot,
        }
        if as_json:
            typer.echo(json_text.dumps(summary))
            return
        state = f"fell at {run.fall_time_s:.2f} s" if run.fell else "did not fall"
        typer.echo(
            f"{loaded.name} stood {run.duration_s:.2f} s of {duration:g} s in pose '{pose}' "
            f"({state}); pushes survived {result.pushes_survived} of {len(pushes)}; COM error "
            f"{run.com_error_m:.3f} m, foot skate {run.foot_skate_m:.3f} m per stance, mean "
            f"artificial torque {run.artificial_torque:.1f} N·m (robustness {robustness:g}, "
            f"{controller} controller)."
        )


def _check_pose(character, pose: str) -> None:
    """One error naming --pose unless `pose` is 'default' or one of the character's relax-pose
    presets."""
    from eigengait.character.relax import DEFAULT_POSE

    known = [DEFAULT_POSE, *character.meta.relax_poses]
    if pose not in known:
        raise UserInputError(
            f"unknown pose '{pose}' for {character.name}",
            field="--pose",
            fix=f"use one of: {', '.join(known)}",
        )
