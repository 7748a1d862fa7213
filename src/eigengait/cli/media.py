"""Video and BVH outputs shared by the commands that simulate motion (sketch, play, track, demo).

Status lines go to standard error when a command prints JSON, so its standard output stays one JSON
document.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np
import typer
from rich.console import Console

from eigengait.errors import UserInputError

CAMERAS = ("follow", "fixed")
FPS_OPTION = typer.Option(
    30.0,
    "--fps",
    help="Frames per second of the video and the BVH (exact: the simulation is resampled by time).",
)
SPEED_OPTION = typer.Option(
    1.0, "--speed", help="Video playback speed: 1 = real time, 0.5 = slow motion."
)
CAMERA_OPTION = typer.Option(
    "follow",
    "--camera",
    help=(
        "Video camera: follow (moves with the character) or fixed (frames the whole motion, so "
        "travel shows)."
    ),
)
BVH_UNITS_OPTION = typer.Option(
    "m",
    "--bvh-units",
    help=(
        "BVH length unit: m (default; life-size in Blender at import scale 1) or cm "
        "(MotionBuilder-style tools)."
    ),
)


@dataclass(frozen=True)
class MediaOptions:
    """What to write and how: paths (None: skip), frame rate (1/s), playback speed, camera, BVH
    unit."""

    video: Optional[Path] = None
    bvh: Optional[Path] = None
    fps: float = 30.0
    speed: float = 1.0
    camera: str = "follow"
    bvh_units: str = "m"

    def check(self) -> "MediaOptions":
        """Refuse bad values before any simulation runs."""
        from eigengait.motion.bvh_export import UNIT_SCALE
        from eigengait.motion.resample import frame_times
        from eigengait.render.video import video_path

        frame_times(0.0, self.fps, self.speed)
        if self.camera not in CAMERAS:
            raise UserInputError(
                f"unknown camera '{self.camera}'", field="--camera", fix="use follow or fixed"
            )
        if self.bvh_units not in UNIT_SCALE:
            raise UserInputError(
                f"unknown BVH unit '{self.bvh_units}'", field="--bvh-units", fix="use m or cm"
            )
        if self.video is not None:
            video_path(self.video)
        if self.bvh is not None and self.bvh.suffix.lower() != ".bvh":
            raise UserInputError(
                f"cannot write '{self.bvh.suffix or 'no extension'}' as BVH",
                file=self.bvh,
                field="--bvh",
                fix="name the file .bvh",
            )
        return self


def status_console(as_json: bool) -> Console:
    """Where human-readable status lines go: standard error for --json commands, standard output
    otherwise."""
    return Console(stderr=as_json, soft_wrap=True)


def write_media(
    world, qpos: np.ndarray, source_fps: float, options: MediaOptions, console: Console
) -> None:
    """Write the video and/or BVH of a qpos trajectory (T × nq) recorded at `source_fps`."""
    if options.video:
        from eigengait.render.video import CameraView, render_video

        view = CameraView(follow=options.camera == "follow")
        frames = render_video(
            world,
            qpos,
            source_fps,
            options.video,
            view=view,
            progress=True,
            fps=options.fps,
            speed=options.speed,
        )
        console.print(
            f"video: {options.video} ({frames} frames at {options.fps:g} frames/s, speed "
            f"{options.speed:g}×)"
        )
    if options.bvh:
        from eigengait.motion.bvh_export import write_trajectory_bvh

        clip = write_trajectory_bvh(
            world, qpos, source_fps, options.bvh, fps=options.fps, units=options.bvh_units
        )
        console.print(
            f"BVH: {options.bvh} ({clip.n_frames} frames at {options.fps:g} frames/s, "
            f"{len(clip.joints)} joints, lengths in {options.bvh_units})"
        )
