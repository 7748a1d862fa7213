"""`eigengait track`: retarget a BVH clip onto a character and track it in physics with the balance
controller."""

from __future__ import annotations

from pathlib import Path

import typer

from eigengait.cli.balance_options import (
    CONTROLLER_OPTION,
    FOOT_FRICTION_OPTION,
    FOOT_HEIGHT_OPTION,
    FOOT_RADIUS_OPTION,
    ROBUSTNESS_OPTION,
    balance_settings,
)
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
from eigengait.motion.flat_feet import FLAT_TILT_WARN_DEG
from eigengait.outputs import refuse_existing

PUSH_HELP = (
    "Push the torso sideways: FORCE@TIME[,...] in N and s (e.g. 150@1.0), each held for 0.1 s "
    "along +y."
)


def register(app: typer.Typer) -> None:
    """Add the `track` command to the CLI."""

    @app.command("track")
    def track_command(
        clip: Path = typer.Argument(..., help="BVH motion-capture clip."),
        character: str = typer.Option(
            "walker",
            "--character",
            help="Built-in character name or MJCF path (default: the walker, the "
            "humanoid with ankles; 'humanoid' has none and tracks worse).",
        ),
        robustness: float = ROBUSTNESS_OPTION,
        foot_radius: float = FOOT_RADIUS_OPTION,
        foot_height: float = FOOT_HEIGHT_OPTION,
        foot_friction: float = FOOT_FRICTION_OPTION,
        push: str = typer.Option(None, "--push", help=PUSH_HELP),
        mapping: Path = typer.Option(
            None, "--mapping", help="YAML mapping BVH joints → MJCF joints."
        ),
        start_frame: int = typer.Option(
            1, "--start-frame", help="First clip frame used (CMU frame 0 is a T-pose)."
        ),
        tolerance: float = typer.Option(
            0.0,
            "--tolerance",
            help="Switch balance off while the compensated fraction is below this.",
        ),
        controller: str = CONTROLLER_OPTION,
        recoveries: int = typer.Option(
            None,
            "--recoveries",
            help="Falls searched past: at a fall the simulation is rewound 0.3-2 s and replayed "
            "with sampled balance targets until one stays up (default 4; 0: the controller "
            "alone).",
        ),
        kinematic: bool = typer.Option(
            False,
            "--kinematic",
            help="No physics: play the retargeted reference and report its foot skate, "
            "floor penetration, ground clearance and its feet's tilt where the clip's feet stand "
            "flat (--video/--bvh show it).",
        ),
        levelling: str = typer.Option(
            "still",
            "--levelling",
            help="The frames each foot is levelled on: 'still' (where the character's foot stands "
            "still) or 'flat' (where the clip's own ankle and toe are both down; better for walks "
            "that --kinematic warns of, worse for most runs).",
        ),
        clean_feet: bool = typer.Option(
            True,
            "--clean-feet/--raw-feet",
            help=(
                "Put the reference's stance feet on the floor and remove their skate by leg IK "
                "(default), or keep the retargeted feet."
            ),
        ),
        video: Path = typer.Option(
            None, "--video", help="Write the simulated motion to this .mp4 or .gif."
        ),
        bvh: Path = typer.Option(
            None,
            "--bvh",
            help=(
                "Write the simulated motion as BVH (root motion included; lengths in --bvh-units)."
            ),
        ),
        fps: float = FPS_OPTION,
        speed: float = SPEED_OPTION,
        camera: str = CAMERA_OPTION,
        bvh_units: str = BVH_UNITS_OPTION,
        force: bool = typer.Option(False, "--force", help="Overwrite existing outputs."),
        as_json: bool = typer.Option(False, "--json", help="Print the result as JSON."),
    ) -> None:
        """Track a motion-capture clip in physics with the balance controller."""
        from eigengait.motion.tracking import kinematic_summary, reference_poses, run_track

        foot = balance_settings(robustness, foot_radius, foot_height, foot_friction)
        media = MediaOptions(
            video=video, bvh=bvh, fps=fps, speed=speed, camera=camera, bvh_units=bvh_units
        ).check()
        refuse_existing([video, bvh], force)
        units = {"bvh_units": bvh_units} if bvh else {}
        if kinematic:
            ref = reference_poses(clip, character, mapping, start_frame, clean_feet, levelling)
            write_media(
                ref["world"], ref["qpos"], 1.0 / ref["frame_time"], media, status_console(as_json)
            )
            _print_kinematic({**kinematic_summary(ref, clean_feet), **units}, as_json)
            return
        world, reference, result = run_track(
            clip,
            character,
            robustness,
            push,
            mapping,
            start_frame,
            tolerance,
            clean_feet,
            foot,
            controller,
            recoveries,
            levelling,
        )
        write_media(world, result.qpos, 1.0 / result.frame_time, media, status_console(as_json))
        if as_json:
            summary = {**result.summary(), "controller": controller, "levelling": levelling}
            typer.echo(json_text.dumps({**summary, **units}))
            return
        state = f"fell at {result.fall_time_s:.2f} s" if result.fell else "did not fall"
        typer.echo(
            f"tracked {result.duration_s:.2f} s of {reference.duration:.2f} s ({state}); "
            f"joint RMS error {result.joint_rms_deg:.1f}°, COM error {result.com_error_m:.3f} m, "
            f"mean artificial torque {result.artificial_torque:.1f} N·m, foot skate "
            f"{result.foot_skate_m:.3f} m per stance, {result.foot_skate_max_m:.3f} m at worst "
            f"(robustness {robustness}, {controller} controller)."
        )
        if result.recovery_simulations:
            typer.echo(
                f"recovery: {result.recoveries} fall(s) searched past, "
                f"{result.recovery_simulations} simulations of sampled balance targets "
                "(--recoveries 0: the controller alone)."
            )


def _print_kinematic(report: dict, as_json: bool) -> None:
    if as_json:
        typer.echo(json_text.dumps(report))
        return
    source = report["source"]
    axes = (
        (
            f"{source['unit']} ({source['metres_per_unit']:g} m), up {source['up_axis']}, facing "
            f"{source['forward_axis']}"
        )
        if source
        else "axes from the mapping file or the CMU convention"
    )
    clearance = report["ground_clearance_m"]
    typer.echo(
        f"reference {report['duration_s']:.2f} s, {axes}; foot skate {report['foot_skate_m']:.3f} "
        f"m per stance ({report['stances']} stances; {report['raw']['foot_skate_m']:.3f} m before "
        f"cleanup), floor penetration {report['floor_penetration_m']:.3f} m, ground clearance "
        f"{'n/a' if clearance is None else f'{clearance:.3f} m'}."
    )
    for foot, tilt in report["flat_foot_tilt_deg"].items():
        if tilt > FLAT_TILT_WARN_DEG:
            typer.echo(
                f"warning: the {foot} foot stands {tilt:.0f}° off level where the clip's foot is "
                "flat, so the reference stands on its heel or toe there; --levelling flat levels "
                "it on those frames (docs/balance.md, 'Levelling on the clip's own flat feet')."
            )
    for glitch in report["capture_glitches"]:
        typer.echo(
            f"capture glitch repaired: {glitch['joint']} turned faster than a human joint can, "
            f"{glitch['start_s']:.3f}-{glitch['end_s']:.3f} s of the clip (interpolated)."
        )
