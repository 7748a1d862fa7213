"""Balance-controller experiments on the CMU walking clip (cmu_02_01_walk.bvh, whole length).

1. Trade-off: tracking error, fall time and mean artificial torque for robustness values 0 … 1
   (plot: docs/images/balance_tradeoff.png).
2. Push recovery: a 0.1 s sideways push on the torso at t = 0.5 s; the largest force survived per robustness.
3. The ankleless humanoid with the same controller, for comparison.
4. Modal gaits (src/eigengait/data/gaits/*.json) played without the snap: open loop (`play(..., snap=False)`)
   vs with balance feedback (`play_with_feedback`), cycles survived out of 20.
Character: the walker (the humanoid with ankles). Prints Markdown tables. Run: .venv/bin/python benchmarks/bench_balance.py
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from eigengait.character import load_character  # noqa: E402
from eigengait.control.balance.gait_feedback import play_with_feedback  # noqa: E402
from eigengait.control.balance.reference import kinematic_replay  # noqa: E402
from eigengait.control.controller import load_controller, system_for, to_parameters  # noqa: E402
from eigengait.control.playback import play  # noqa: E402
from eigengait.control.balance.tracker import Push, track  # noqa: E402
from eigengait.motion.bvh import read_bvh  # noqa: E402
from eigengait.motion.retarget import builtin_mapping, retarget  # noqa: E402
from eigengait.sim.world import build_world  # noqa: E402

CLIP = Path("/work/shared/data/mocap/cmu_02_01_walk.bvh")
ROBUSTNESS = [0.0, 0.25, 0.5, 0.75, 0.9, 1.0]
PUSHES = [0, 100, 200, 300, 400, 600]
GAITS = sorted((Path(__file__).resolve().parents[1] / "src/eigengait/data/gaits").glob("*.json"))
CYCLES = 20
PLOT = Path(__file__).resolve().parents[1] / "docs/images/balance_tradeoff.png"


def load(character: str):
    world = build_world(load_character(character))
    clip = read_bvh(CLIP)
    poses = retarget(clip, world, builtin_mapping(character, clip))
    return world, kinematic_replay(world, poses.qpos, poses.frame_time)


def gaits() -> None:
    print("\n| gait | open loop, no snap (cycles) | feedback R=0 (cycles) | feedback R=0.5 (cycles) | "
          "COM error R=0 (m) | balance torque RMS R=0 (N·m) |\n|---|---:|---:|---:|---:|---:|")
    for path in GAITS:
        controller = load_controller(path)
        system = system_for(controller)
        params = to_parameters(controller, system, path)
        open_loop = play(system, params, cycles=CYCLES, snap=False)
        fb0 = play_with_feedback(system, params, cycles=CYCLES, robustness=0.0)
        fb5 = play_with_feedback(system, params, cycles=CYCLES, robustness=0.5)
        print(f"| {path.stem} | {open_loop.cycles_completed} | {fb0.cycles_completed} | {fb5.cycles_completed} | "
              f"{fb0.com_error_m:.3f} | {fb0.balance_torque_rms:.0f} |", flush=True)


def main() -> None:
    world, reference = load("walker")
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

    _, plain = load("humanoid")
    print("\n| humanoid (no ankle), robustness | tracked (s) | fell | joint RMS (deg) | COM error (m) | "
          "artificial torque mean (N·m) |\n|---:|---:|---|---:|---:|---:|")
    humanoid_world = build_world(load_character("humanoid"))
    for r in (0.0, 0.5, 1.0):
        res = track(humanoid_world, plain, r)
        print(f"| {r} | {res.duration_s:.2f} | {res.fell} | {res.joint_rms_deg:.1f} | {res.com_error_m:.3f} | "
              f"{res.artificial_torque:.1f} |", flush=True)

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
    fig.suptitle("CMU 02_01 walk on the built-in walker")
    fig.tight_layout()
    PLOT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(PLOT, dpi=120)
    print(f"\nplot: {PLOT}")
    gaits()


if __name__ == "__main__":
    main()
