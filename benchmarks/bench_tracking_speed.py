"""How fast the balance controllers track a clip, against the bare engine in the same process.

Per controller (`qp`, `momentum`), CMU 02_01 (2.85 s, walker, cleaned feet, robustness 0.5, as
`eigengait track` runs it): the wall time of `track` and its physics steps per second. The baseline,
one figure for both, is `mujoco.mj_step` on a tracker's private model copy (soles on), from the
clip's first pose with the motors off, for as many steps (the character falls; the engine's cost
barely depends on the pose). Ratios: controller steps/s over raw steps/s, and simulated seconds per
wall second (real-time factor). Best of ROUNDS rounds each, since a shared machine's load varies.

Run: nice .venv/bin/python benchmarks/bench_tracking_speed.py
"""

from __future__ import annotations

import time
from pathlib import Path

import mujoco

from eigengait.control.balance.reference import kinematic_replay
from eigengait.control.balance.tracker import CONTROLLERS, Tracker, TrackerSettings
from eigengait.motion.tracking import reference_poses

CLIP = Path(__file__).resolve().parents[2] / "shared/data/mocap/cmu_02_01_walk.bvh"
ROBUSTNESS = 0.5
ROUNDS = 3


def raw_steps_per_second(tracker: Tracker, steps: int) -> float:
    """mj_step rate on the tracker's model copy from the reference's first pose, motors off."""
    model, data = tracker.model, mujoco.MjData(tracker.model)
    data.qpos[:] = tracker.reference.qpos[0]
    start = time.perf_counter()
    for _ in range(steps):
        mujoco.mj_step(model, data)
    return steps / (time.perf_counter() - start)


def main() -> None:
    ref = reference_poses(CLIP, "walker", None, 1)
    world = ref["world"]
    reference = kinematic_replay(world, ref["qpos"], ref["frame_time"])
    steps = int(round(reference.duration / world.model.opt.timestep))
    print(
        f"CMU 02_01, {reference.duration:.2f} s, walker, robustness {ROBUSTNESS}, "
        f"{steps} physics steps of {1000 * world.model.opt.timestep:g} ms; best of {ROUNDS}\n"
    )
    walls = {name: float("inf") for name in CONTROLLERS}
    raw = 0.0
    for _ in range(ROUNDS):
        for name in CONTROLLERS:
            tracker = Tracker(world, reference, ROBUSTNESS, TrackerSettings(controller=name))
            start = time.perf_counter()
            tracker.run()
            walls[name] = min(walls[name], time.perf_counter() - start)
        raw = max(raw, raw_steps_per_second(tracker, steps))
    print(f"raw mj_step: {raw:.0f} steps/s\n")
    print(
        "| controller | wall time | steps/s | ratio to raw mj_step | real-time factor |\n"
        "|---|---:|---:|---:|---:|"
    )
    for name, wall in walls.items():
        rate = steps / wall
        print(
            f"| {name} | {wall:.2f} s | {rate:.0f} | {rate / raw:.3f} | "
            f"{reference.duration / wall:.2f} |"
        )


if __name__ == "__main__":
    main()
