"""Picture strips and footfall diagrams of the shipped gaits for the README and the gallery: each gait played as
shipped (with its lookahead, if it has one) for two cycles (or N); the strip shows the last cycle from a
fixed side camera (so travel shows), each tile stamped with its time, its phase in the cycle and the
feet on the ground; below it, the contact diagram of both cycles, with the strip's frames marked.

Usage: python scripts/gait_strips.py [--output FOLDER] [--cycle N] [GAIT ...] ->
FOLDER/gait_<name>.png (default docs/images; N: the cycle shown, default 2)
"""  # noqa: E501

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from eigengait.control.binding import gait_system  # noqa: E402
from eigengait.control.controller import load_controller, to_parameters  # noqa: E402
from eigengait.control.library import gait_names, resolve  # noqa: E402
from eigengait.control.playback import play  # noqa: E402
from eigengait.motion.resample import resample  # noqa: E402
from eigengait.render.contacts import contact_diagram, foot_contacts  # noqa: E402
from eigengait.render.video import CameraView, iter_frames  # noqa: E402

FRAMES = 8
TILE = (240, 260)  # width, height in pixels
VIEW = CameraView(azimuth_deg=100.0, elevation_deg=-27.0, fill=0.85, follow=False)
OUT = Path(__file__).resolve().parents[1] / "docs" / "images"


def strip(name: str, folder: Path, cycle: int = 2) -> Path:
    """Draw gait `name`'s strip of its cycle `cycle` (1-based) and the contacts of that cycle and
    the one before it into `folder`."""
    controller = load_controller(resolve("gait", name))
    system = gait_system(controller)
    result = play(
        system, to_parameters(controller, system), cycles=cycle, lookahead=controller.planner()
    )
    world, period = system.world, controller.period
    times = np.arange(len(result.qpos)) / result.fps
    picks = (cycle - 1 + np.arange(FRAMES) / FRAMES) * period
    shown = times >= (cycle - 2) * period - 1e-9  # the contacts of the last two cycles
    poses = resample(world.model, result.qpos, times, picks)
    tiles = list(iter_frames(world, poses, *TILE, VIEW, times=picks))

    width, title, chart = FRAMES * TILE[0], 34, 250  # pixels
    height = title + TILE[1] + chart
    fig = plt.figure(figsize=(width / 100, height / 100), dpi=100)
    fell = (
        f" — FELL at t = {times[-1]:.2f} s (tiles after it repeat the last pose)"
        if result.fell
        else ""
    )
    shown_cycle = "its second cycle" if cycle == 2 else f"cycle {cycle}"
    fig.text(
        0.005,
        1 - 17 / height,
        f"{name}: {shown_cycle} ({period:.3f} s) from a fixed side camera, and the feet on the "
        f"ground over {'two cycles' if cycle > 1 else 'it'}{fell}",
        fontsize=13,
        weight="bold",
        va="center",
        color="#c0392b" if fell else "black",
    )
    top = fig.add_axes((0, (chart) / height, 1, TILE[1] / height))
    top.imshow(np.concatenate(tiles, axis=1), interpolation="nearest")
    top.set_axis_off()
    for k in range(FRAMES):
        top.text(
            (k + 0.5) * TILE[0],
            TILE[1] - 8,
            f"phase {k / FRAMES:.3g}",
            ha="center",
            va="bottom",
            fontsize=11,
            bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8},
        )
        if k:
            top.axvline(k * TILE[0] - 0.5, color="white", lw=2)
    diagram = fig.add_axes((0.07, 45 / height, 0.91, (chart - 120) / height))
    contact_diagram(
        diagram,
        times[shown],
        foot_contacts(world, result.qpos[shown]),
        list(world.foot_spheres),
        period,
        picks,
    )
    path = folder / f"gait_{name}.png"
    fig.savefig(path)
    plt.close(fig)
    return path


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("gaits", nargs="*", help="shipped gait names (default: all)")
    parser.add_argument(
        "--output", type=Path, default=OUT, help="folder for the images (default: docs/images)"
    )
    parser.add_argument(
        "--cycle",
        type=int,
        default=2,
        help="the cycle shown (1-based; default 2: a later one for a gait that settles slowly)",
    )
    args = parser.parse_args()
    args.output.mkdir(parents=True, exist_ok=True)
    for gait in args.gaits or gait_names():
        print(strip(gait, args.output, args.cycle))
