"""Track every clip of the shared motion-capture corpus at five robustness values and print one
Markdown table.

Per clip (walker, cleaned feet, start frame 1, as `eigengait track` does by default) and robustness
0, 0.25, 0.5, 0.75, 1: tracked time of the clip's duration, joint RMS error, COM error (RMS, m),
simulated foot skate (m, mean per stance / worst stance), mean artificial torque (N·m) and the
largest sideways push survived.

Push search (coarse): a 0.1 s push along +y on the torso (as `track --push`) at t = 0.5 s, forces
100, 200, 350, 500, 700 N in turn until one fells the character; each pushed run lasts until 4.5 s
after the push or the clip's end (the whole clip but for the 20 s laugh), and a push is survived
when the character has not fallen by then. When the unpushed run already falls within that window
the column says so instead. Prints the wall time at the end. Run: nice .venv/bin/python
benchmarks/bench_tracking_corpus.py [--controller momentum|qp] [CLIP.bvh ...] (`track
--controller`; qp by default).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from eigengait.control.balance.reference import kinematic_replay
from eigengait.control.balance.tracker import CONTROLLERS, BodyPush, TrackerSettings, track
from eigengait.motion.tracking import measure_simulated_feet, reference_poses

CORPUS = Path(__file__).resolve().parents[2] / "shared/data/mocap"
ROBUSTNESS = [0.0, 0.25, 0.5, 0.75, 1.0]
PUSH_FORCES = [100.0, 200.0, 350.0, 500.0, 700.0]  # N
PUSH_TIME = 0.5  # s
SETTLE = 4.5  # s after the push: the whole clip for every clip of 5 s or less


def largest_push(world, reference, robustness: float, unpushed, settings: TrackerSettings) -> str:
    """The push column: the largest of PUSH_FORCES survived, or why none was tried (`unpushed`: the
    clip's tracking result without a push; the simulation is deterministic, so it also tells a
    shorter run's fate)."""
    window = min(reference.duration, PUSH_TIME + SETTLE)
    if unpushed.fell and unpushed.fall_time_s <= window:
        return f"— (falls at {unpushed.fall_time_s:.2f} s unpushed)"
    survived = "none"
    for force in PUSH_FORCES:
        push = BodyPush(force=(0.0, force, 0.0), time_s=PUSH_TIME, body="torso")
        if track(world, reference, robustness, settings, window, (push,)).fell:
            break
        survived = f"{force:.0f} N"
    return survived


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("clips", nargs="*", type=Path)
    parser.add_argument("--controller", choices=CONTROLLERS, default=TrackerSettings().controller)
    args = parser.parse_args()
    clips = args.clips or sorted(CORPUS.glob("*.bvh"))
    settings = TrackerSettings(controller=args.controller)
    start = time.perf_counter()
    print(
        "| clip | robustness | tracked | joint RMS | COM error | foot skate (sim, mean / worst) | "
        "mean artificial torque | largest push survived |\n|---|---:|---:|---:|---:|---:|---:|---|"
    )
    for clip in clips:
        ref = reference_poses(clip, "walker", None, 1)
        world = ref["world"]
        reference = kinematic_replay(world, ref["qpos"], ref["frame_time"])
        for r in ROBUSTNESS:
            res = track(world, reference, r, settings)
            measure_simulated_feet(world, res)
            push = largest_push(world, reference, r, res, settings)
            print(
                f"| `{clip.name}` | {r:g} | {res.duration_s:.2f} of {reference.duration:.2f} s | "
                f"{res.joint_rms_deg:.1f}° | {res.com_error_m:.3f} m | "
                f"{res.foot_skate_m:.3f} / {res.foot_skate_max_m:.3f} m | "
                f"{res.artificial_torque:.1f} N·m | {push} |",
                flush=True,
            )
    print(f"\nwall time: {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
