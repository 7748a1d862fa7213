"""Touchdown-triggered timing of the pulse state machine (the SIMBICON and Raibert-hopper
convention).

With the thesis's fixed clock a cycle of period T plays its states at fixed times, whatever the body
does. With touchdown timing the clock follows the feet: when the foot of an air state is seen to
leave the ground and then touch it again, the state machine jumps to that foot's ground state at
once (an early touchdown cuts the air state short); when the air state's scheduled end comes before
the touchdown, the clock waits at that instant for at most `MAX_WAIT` of the air state's duration
(a late touchdown stretches it). Ground states always last their scheduled duration. The controls of
each phase are the same one-cycle pulse table as with the clock, so a gait whose touchdowns come on
schedule plays exactly as before.

Contacts (`sim/contacts.py`) are read every feedback interval (`FEEDBACK_DT`), so a touchdown is
seen at most 10 ms late.
"""

from __future__ import annotations

import numpy as np

from eigengait.control.pulse import State

MAX_WAIT = 0.5  # a late touchdown may stretch an air state by at most this share of its duration


class PhaseClock:
    """The phase of one candidate's pulse state machine, in physics steps; `table` holds one cycle
    of controls."""

    def __init__(self, states: list[State], table: np.ndarray, timestep: float):
        self.states, self.table, self.timestep = states, table, timestep
        self.cycle_steps = len(table)
        starts = np.array([int(round(s.start / timestep)) for s in states] + [self.cycle_steps])
        self.start_step = starts[:-1]
        self.end_step = starts[1:]
        self.state_of = np.repeat(np.arange(len(states)), np.diff(starts))
        self.max_wait = [
            int(MAX_WAIT * s.duration / timestep) if s.phase == "air" else 0 for s in states
        ]
        self.step = 0  # position in the cycle table
        self.cycle = 0  # completed cycles
        self.elapsed = 0  # physics steps played
        self.cycle_ends: list[int] = []  # index of the last step of each completed cycle
        self.airborne = False  # the current air state's foot has been seen off the ground
        self.waited = 0  # steps the current air state has been held at its end

    @property
    def state(self) -> int:
        return int(self.state_of[self.step])

    @property
    def phase_time(self) -> float:
        """Time (s) into the cycle as the state machine sees it."""
        return self.step * self.timestep

    def controls(self, n: int) -> np.ndarray:
        """The next `n` steps of controls, advancing the clock (held at a late air state's end)."""
        rows = np.empty(n, int)
        for j in range(n):
            rows[j] = self.step
            self._tick()
        return self.table[rows]

    def _tick(self) -> None:
        self.elapsed += 1
        k = self.state
        at_end = self.step + 1 == self.end_step[k]
        if at_end and self.states[k].phase == "air" and self.waited < self.max_wait[k]:
            self.waited += 1
            return
        self.step += 1
        if self.step == self.cycle_steps:
            self.step, self.cycle = 0, self.cycle + 1
            self.cycle_ends.append(self.elapsed - 1)
        if self.step == self.start_step[self.state]:
            self.airborne, self.waited = False, 0

    def observe(self, touching: dict[str, bool]) -> None:
        """Feet on the ground now: a touchdown of the air state's foot starts its ground state."""
        k = self.state
        s = self.states[k]
        if s.phase != "air":
            return
        if not touching[s.foot]:
            self.airborne = True
        elif self.airborne:
            self.step = int(self.start_step[k + 1])
            self.airborne, self.waited = False, 0
