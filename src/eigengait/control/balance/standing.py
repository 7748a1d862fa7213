"""The chapter's reference-free mode: stand in a pose with no motion capture and recover from
pushes.

No second controller: the tracker (`tracker.py`) runs unchanged against a constant reference, the
world's own standing pose (its relax pose with the lowest point on the floor, `World.model.qpos0`)
held still for the whole run. Its replay gives the COM target (the standing COM, world axes), zero
momenta and the support point between the feet, which is the chapter's E19 without a reference
(p_com,d over the support, v_com,d = 0).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from eigengait.control.balance.reference import Reference, kinematic_replay
from eigengait.control.balance.tracker import (
    PUSH_DURATION,
    BodyPush,
    TrackerSettings,
    TrackingResult,
    track,
)
from eigengait.control.playback import pushes_survived
from eigengait.sim.world import World

FRAME_TIME = 1.0 / 60.0  # s between the constant reference's frames (and the recorded frames)
REST_WINDOW = 0.5  # s at the end of a run over which the root's speed is measured
# m/s: below this mean horizontal root speed over REST_WINDOW the character is at rest
REST_SPEED = 0.05


@dataclass
class StandingResult:
    """A standing run: the tracker's result, the pushes given (forces N along world axes, times s),
    the mass (kg) and the mean horizontal speed of the root body over the run's last REST_WINDOW
    seconds (m/s)."""

    tracking: TrackingResult
    pushes: tuple[BodyPush, ...]
    mass_kg: float
    end_speed_mps: float

    @property
    def pushes_survived(self) -> int:
        """Pushes after which the character did not fall before the next push (or the end of the
        run)."""
        return pushes_survived([p.time_s for p in self.pushes], self.tracking.fall_time_s)

    @property
    def at_rest(self) -> bool:
        """Did not fall and stands still at the end: a push the character merely has not fallen from
        yet (still swaying or sliding) does not count as recovered."""
        return not self.tracking.fell and self.end_speed_mps < REST_SPEED

    def summary(self) -> dict:
        """JSON-ready: the tracker's figures (COM error = RMS distance to the standing COM) and the
        pushes."""
        pushes = [
            {
                "force_n": round(float(np.linalg.norm(p.force)), 3),
                "time_s": p.time_s,
                "impulse_n_s_per_kg": round(
                    float(np.linalg.norm(p.force)) * PUSH_DURATION / self.mass_kg, 4
                ),
                "body": p.body,
            }
            for p in self.pushes
        ]
        return {
            **self.tracking.summary(),
            "mass_kg": round(self.mass_kg, 3),
            "pushes": pushes,
            "pushes_given": len(self.pushes),
            "pushes_survived": self.pushes_survived,
            "end_speed_mps": round(self.end_speed_mps, 4),
            "at_rest": self.at_rest,
        }


def standing_reference(world: World, duration_s: float) -> Reference:
    """The world's standing pose held still for duration_s seconds (at least one frame interval)."""
    frames = max(int(np.ceil(duration_s / FRAME_TIME)), 1) + 1
    return kinematic_replay(world, np.repeat(world.model.qpos0[None], frames, axis=0), FRAME_TIME)


def stand(
    world: World,
    robustness: float,
    duration_s: float,
    pushes: Sequence[BodyPush] = (),
    settings: TrackerSettings = TrackerSettings(),
) -> StandingResult:
    """Stand in the world's pose for duration_s seconds under the given pushes, balance at
    `robustness` ∈ [0, 1]."""
    result = track(
        world,
        standing_reference(world, duration_s),
        robustness,
        settings,
        duration_s,
        tuple(pushes),
    )
    return StandingResult(result, tuple(pushes), world.mass(), _end_speed(world, result))


def _end_speed(world: World, result: TrackingResult) -> float:
    """Mean horizontal speed (m/s) of the root body's origin over the last REST_WINDOW seconds
    recorded (the whole run when shorter; 0 for a run of a single frame)."""
    frames = min(int(round(REST_WINDOW / result.frame_time)), len(result.qpos) - 1)
    if frames < 1:
        return 0.0
    adr = int(world.model.jnt_qposadr[world.model.body_jntadr[world.root_body]])
    steps = np.diff(result.qpos[-1 - frames :, adr : adr + 2], axis=0)
    return float(np.linalg.norm(steps, axis=1).sum() / (frames * result.frame_time))


__all__ = ["StandingResult", "stand", "standing_reference"]
