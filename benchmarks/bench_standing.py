"""Standing with no clip (`eigengait balance walker`): the largest sideways push survived per
robustness.

A push is a force along +y on the root body (pelvis) for 0.1 s at t = 0.5 s; it is survived when,
3 s after it, the character has not fallen (the tracker's test: COM below half its standing height,
or a body other than a foot on the floor) and is at rest (`StandingResult.at_rest`: root slower than
0.05 m/s over the last 0.5 s; without this a character still sliding and swaying on its feet would
count). Search per robustness: doubling from 100 N until a push is not survived, then bisection to
10 N (assumes that a survived force survives every smaller one). Also: the mean artificial torque
while standing still for 2 s.
The target of the tracking issue: 0.5 N·s/kg (5 N/kg for 0.1 s) at robustness 0.5.
Run: nice .venv/bin/python benchmarks/bench_standing.py [ROBUSTNESS ...]
"""

from __future__ import annotations

import sys
import time

from eigengait.character import load_character
from eigengait.control.balance.standing import stand
from eigengait.control.balance.tracker import PUSH_DURATION, BodyPush
from eigengait.sim.world import build_world

ROBUSTNESS = [0.0, 0.25, 0.5, 0.75, 1.0]
PUSH_TIME = 0.5  # s
SETTLE = 3.0  # s after the push
RESOLUTION = 10.0  # N
LARGEST_TRIED = 12_800.0  # N


def survives(world, robustness: float, force: float) -> bool:
    push = BodyPush(
        force=(0.0, force, 0.0), time_s=PUSH_TIME, body=world.model.body(world.root_body).name
    )
    return stand(world, robustness, PUSH_TIME + SETTLE, (push,)).at_rest


def largest_push(world, robustness: float) -> float:
    """Largest force survived (N) to within RESOLUTION; 0 N counts as survived."""
    low, high = 0.0, 100.0
    while survives(world, robustness, high):
        low, high = high, 2.0 * high
        if high > LARGEST_TRIED:
            return low
    while high - low > RESOLUTION:
        middle = 0.5 * (low + high)
        low, high = (middle, high) if survives(world, robustness, middle) else (low, middle)
    return low


def main() -> None:
    world = build_world(load_character("walker"))
    mass = world.mass()
    start = time.perf_counter()
    print(
        f"walker, {mass:.1f} kg, default pose; push at t = {PUSH_TIME} s for {PUSH_DURATION} s on "
        "the pelvis\n\n"
        "| robustness | largest push survived | impulse per kg | mean artificial torque standing "
        "still |\n"
        "|---:|---:|---:|---:|"
    )
    for r in [float(a) for a in sys.argv[1:]] or ROBUSTNESS:
        still = stand(world, r, 2.0).tracking.artificial_torque
        force = largest_push(world, r)
        print(
            f"| {r:g} | {force:.0f} N | {force * PUSH_DURATION / mass:.2f} N·s/kg | "
            f"{still:.1f} N·m |",
            flush=True,
        )
    print(f"\nwall time: {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
