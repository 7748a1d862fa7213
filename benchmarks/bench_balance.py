"""Balance-controller experiments on the CMU walking clip (cmu_02_01_walk.bvh, whole length).

1. Trade-off: tracking error, fall time and mean artificial torque for robustness values 0 … 1
   (plot: docs/images/balance_tradeoff.png).
2. Push recovery: a 0.1 s sideways push on the torso at t = 0.5 s; the largest force survived per
   robustness.
3. The ankleless humanoid with the same controller, for comparison.
Character: the walker (the humanoid with ankles). Prints Markdown tables.
Run: .venv/bin/python benchmarks/bench_balance.py
(`... bench_balance.py tradeoff` runs part 1 and redraws the plot only).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from eigengait.character import load_character  # noqa: E402
from eigengait.control.balance.reference import kinematic_replay  # noqa: E402
from eigengait.control.balance.tracker import BodyPush, track  # noqa: E402
from eigengait.motion.bvh import read_bvh  # noqa: E402
from eigengait.motion.retarget import builtin_mapping, retarget  # noqa: E402
from eigengait.sim.world import build_world  # noqa: E402

CLIP = Path("/work/shared/data/mocap/cmu_02_01_walk.bvh")
ROBUSTNESS = [0.0, 0.25, 0.5, 0.75, 0.9, 1.0]
PUSHES = [0, 100, 200, 300, 400, 600]
PLOT = Path(__file__).resolve().parents[1] / "docs/images/balance_tradeoff.png"


def load(character: str):
    world = build_world(load_character(character))
    clip = read_bvh(CLIP)
    poses = retarget(clip, world, builtin_mapping(character, clip))
    return world, kinematic_replay(world, poses.qpos, poses.frame_time)


def tradeoff(world, reference) -> None:
    """Part 1: tracking error and artificial torque per robustness, as a table and
    docs/images/balance_tradeoff.png."""
    print(
        "| robustness | tracked (s) | fell | joint RMS (deg) | COM error (m) | "
        "artificial torque mean (N·m) | wall time (s) |\n|---:|---:|---|---:|---:|---:|---:|"
    )
    rows = []
    for r in ROBUSTNESS:
        start = time.perf_counter()
        res = track(world, reference, r)
        wall = time.perf_counter() - start
        rows.append(res)
        print(
            f"| {r} | {res.duration_s:.2f} | {res.fell} | {res.joint_rms_deg:.1f} | "
            f"{res.com_error_m:.3f} | {res.artificial_torque:.1f} | {wall:.2f} |",
            flush=True,
        )
    plot_tradeoff(rows, reference.duration)


def plot_tradeoff(rows, clip_s: float) -> None:
    """Three panels against robustness: joint RMS error, COM error, mean artificial torque; falls
    marked."""
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.6))
    panels = (
        ("joint RMS error (deg)", [res.joint_rms_deg for res in rows], "{:.1f}"),
        ("COM error (m)", [res.com_error_m for res in rows], "{:.3f}"),
        ("mean artificial torque (N·m)", [res.artificial_torque for res in rows], "{:.0f}"),
    )
    for ax, (label, values, fmt) in zip(axes, panels):
        ax.plot(ROBUSTNESS, values, "o-", color="#2a6fb0")
        for k, (r, v, res) in enumerate(zip(ROBUSTNESS, values, rows)):
            # label the left of a close pair
            crowded = k + 1 < len(ROBUSTNESS) and ROBUSTNESS[k + 1] - r < 0.2
            ax.annotate(
                fmt.format(v),
                (r, v),
                textcoords="offset points",
                xytext=(-4, 6) if crowded else (4, 6),
                ha="right" if crowded else "left",
                fontsize=8,
            )
            if res.fell:
                ax.plot(r, v, "x", color="#c0392b", ms=9)
        ax.set_ylim(0, max(values) * 1.22)
        ax.set_xlim(-0.08, 1.15)
        ax.set_xlabel("robustness R (0 = no artificial torque)")
        ax.set_ylabel(label)
        ax.set_xticks(ROBUSTNESS, [f"{r:g}" for r in ROBUSTNESS], fontsize=8)
        ax.grid(alpha=0.3)
    fell = [f"{r:g}" for r, res in zip(ROBUSTNESS, rows) if res.fell]
    note = (
        f"fell at R = {', '.join(fell)} (×)"
        if fell
        else f"every setting tracks the whole {clip_s:.2f} s clip"
    )
    fig.suptitle(f"CMU 02_01 walk on the built-in walker: {note}", fontsize=11)
    fig.tight_layout()
    PLOT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(PLOT, dpi=120)
    print(f"\nplot: {PLOT}")


def main() -> None:
    world, reference = load("walker")
    print(f"clip {CLIP.name}: {reference.duration:.2f} s\n")
    tradeoff(world, reference)
    if sys.argv[1:] == ["tradeoff"]:
        return

    print("\n| robustness | largest push survived (N, 0.1 s at t = 0.5 s) |\n|---:|---:|")
    for r in ROBUSTNESS:
        survived = None
        for force in PUSHES:
            res = track(
                world,
                reference,
                r,
                pushes=(BodyPush((0.0, float(force), 0.0), 0.5),) if force else (),
            )
            if res.fell:
                break
            survived = force
        print(f"| {r} | {'fell without push' if survived is None else survived} |", flush=True)

    _, plain = load("humanoid")
    print(
        "\n| humanoid (no ankle), robustness | tracked (s) | fell | joint RMS (deg) | "
        "COM error (m) | artificial torque mean (N·m) |\n|---:|---:|---|---:|---:|---:|"
    )
    humanoid_world = build_world(load_character("humanoid"))
    for r in (0.0, 0.5, 1.0):
        res = track(humanoid_world, plain, r)
        print(
            f"| {r} | {res.duration_s:.2f} | {res.fell} | {res.joint_rms_deg:.1f} | "
            f"{res.com_error_m:.3f} | {res.artificial_torque:.1f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
