"""Picture strips of the shipped gaits for the README: one cycle of each, played with gravity, side view.

Usage: python scripts/gait_strips.py  ->  docs/images/gait_<name>.png
"""

from __future__ import annotations

from pathlib import Path

import imageio.v2 as imageio
import numpy as np

from eigengait.control.controller import load_controller, system_for, to_parameters
from eigengait.control.library import gait_names, resolve
from eigengait.control.playback import play
from eigengait.render.video import CameraView, iter_frames

FRAMES = 8
OUT = Path(__file__).resolve().parents[1] / "docs" / "images"


def strip(name: str) -> Path:
    controller = load_controller(resolve("gait", name))
    system = system_for(controller)
    result = play(system, to_parameters(controller, system), cycles=2)
    per_cycle = len(result.qpos) // 2
    picks = result.qpos[per_cycle + np.linspace(0, per_cycle - 1, FRAMES).astype(int)]   # the second cycle
    view = CameraView(azimuth_deg=100.0, elevation_deg=-24.0)
    frames = list(iter_frames(system.world, picks, 240, 260, view))
    path = OUT / f"gait_{name}.png"
    imageio.imwrite(path, np.concatenate(frames, axis=1))
    return path


if __name__ == "__main__":
    for gait in gait_names():
        print(strip(gait))
