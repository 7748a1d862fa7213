"""Balance-controller experiments on the CMU walking clip (cmu_02_01_walk.bvh, whole length).

1. Trade-off: tracking error, fall time and mean artificial torque for robustness values 0 … 1
   (plot: docs/images/balance_tradeoff.png).
2. Push recovery: a 0.1 s sideways push on the torso at t = 0.5 s; the largest force survived per robustness.
Prints Markdown tables. Run: .venv/bin/python benchmarks/bench_balance.py
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from eigengait.character import load_character  # noqa: E402
from eigengait.control.balance.reference import kinematic_replay  # noqa: E402
from eigengait.control.balance.tracker import Push, track  # noqa: E402
from eigengait.motion.bvh import read_bvh  # noqa: E402
from eigengait.motion.retarget import builtin_mapping, retarget  # noqa: E402
from eigengait.sim.world import build_world  # noqa: E402

CLIP = Path("/work/shared/data/mocap/cmu_02_01_walk.bvh")
ROBUSTNESS = [0.0, 0.25, 0.5, 0.75, 0.9, 1.0]
PUSHES = [0, 50, 100, 200, 300, 400]
PLOT = Path(__file__).resolve().parents[1] / "docs/images/balance_tradeoff.png"


def main() -> None:
    world = build_world(load_character("humanoid"))
    clip = read_bvh(CLIP)
    poses = retarget(clip, world, builtin_mapping("humanoid", clip))
    reference = kinematic_replay(world, poses.qpos, poses.frame_time)
    print(f"clip {CLIP.name}: {reference.duration:.2f} s\n")
    print("| robustness | tracked (s) | fell | joint RMS (deg) | COM error (m) | artificial torque mean (N·m) | "
          "wall time (s) |\n|---:|---:|---|---:|---:|---:|---:|")
    rows = []
    for r in ROBUSTNESS:
        start = time.perf_counter()
        res = track(world, reference, r)
        wall = time.perf_counter() - start
        rows.append(res)
        print(f"| {r} | {res.duration_s:.2f} | {res.fell} | {res.joint_rms_deg:.1f} | {res.com_error_m:.3f} | "
              f"{res.artificial_torque:.1f} | {wall:.2f} |", flush=True)

    print("\n| robustness | largest push survived (N, 0.1 s at t = 0.5 s) |\n|---:|---:|")
    for r in ROBUSTNESS:
        survived = None
        for force in PUSHES:
            res = track(world, reference, r, push=Push((0.0, float(force), 0.0), 0.5) if force else None)
            if res.fell:
                break
            survived = force
        print(f"| {r} | {'fell without push' if survived is None else survived} |", flush=True)

    fig, ax = plt.subplots(1, 2, figsize=(9, 3.6))
    art = [res.artificial_torque for res in rows]
    ax[0].plot(ROBUSTNESS, [res.duration_s for res in rows], "o-", label="time tracked before falling (s)")
    ax[0].axhline(reference.duration, color="gray", ls=":", label="clip length")
    ax[0].set_xlabel("robustness")
    ax[0].legend(fontsize=8)
    ax[1].plot(art, [res.joint_rms_deg for res in rows], "o-")
    for r, a, res in zip(ROBUSTNESS, art, rows):
        ax[1].annotate(f"R={r}", (a, res.joint_rms_deg), fontsize=8)
    ax[1].set_xlabel("mean artificial torque (N·m)")
    ax[1].set_ylabel("joint RMS error (deg)")
    fig.suptitle("CMU 02_01 walk on the built-in humanoid")
    fig.tight_layout()
    PLOT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(PLOT, dpi=120)
    print(f"\nplot: {PLOT}")


if __name__ == "__main__":
    main()
