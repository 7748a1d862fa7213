"""Touchdown-triggered timing: the clock waits for a late touchdown and jumps ahead on an early
one."""

import numpy as np

from eigengait.control.phase_clock import MAX_WAIT, PhaseClock
from eigengait.control.pulse import schedule

DT = 0.001


def clock(air_ratio=0.4, period=0.2):
    states = schedule(["a", "b"], period, air_ratio, 0.01, 0.01)
    n = int(round(period / DT))
    table = np.arange(n, dtype=float)[:, None]  # row k's control is k: the table index played
    return PhaseClock(states, table, DT), states


def test_no_touchdown_holds_each_air_state_for_its_longest_wait():
    c, states = clock()
    played = c.controls(400)[:, 0]
    waits = sum(int(MAX_WAIT * s.duration / DT) for s in states if s.phase == "air")
    assert c.cycle_ends[0] == 200 + waits - 1
    air_end = int(round(states[0].duration / DT)) - 1  # last row of the first air state
    held = np.flatnonzero(played[: c.cycle_ends[0] + 1] == air_end)
    assert len(held) == 1 + int(MAX_WAIT * states[0].duration / DT)


def test_touchdown_after_lift_off_starts_the_ground_state():
    c, states = clock()
    c.controls(5)
    c.observe({"a": True, "b": True})  # still on the ground: no lift-off seen, nothing happens
    assert c.state == 0
    c.observe({"a": False, "b": True})  # lifted
    c.controls(5)
    c.observe({"a": True, "b": True})  # touched down early, 10 ms into a 40 ms air state
    assert c.state == 1 and c.step == int(round(states[1].start / DT))
    c.observe({"a": True, "b": True})  # ground states ignore contacts
    assert c.state == 1


def test_touchdowns_on_schedule_replay_the_clock():
    c, _ = clock()
    played = []
    for _ in range(200):
        played.append(c.controls(1)[0, 0])
        s = c.states[c.state]
        # lands as its air state ends, when the clock starts to wait
        landed = s.phase == "air" and c.waited > 0
        c.observe({f: f != s.foot or landed for f in ("a", "b")})
    assert played == list(range(200)) and c.cycle_ends == [199]
