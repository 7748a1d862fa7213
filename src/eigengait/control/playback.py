"""Play a pulse controller on the ground with gravity: physics only, its balance feedback included.

The gait runs on its own for the asked number of cycles (`control/closed_loop.py`), optionally
pushed sideways. `snap=True` reproduces the thesis's "simple and effective, but physically
incorrect" reset instead: each cycle is played open loop from (q₀, q̇₀), keeping only the root's
forward position. Frames are sampled at exactly `fps` (the nearest physics step to each frame time).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from eigengait.control.closed_loop import (
    PUSH_SECONDS,
    BatchRun,
    ClosedLoopRunner,
    Push,
    cycle_errors,
)
from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.control.gait_metrics import PLAYBACK_FPS, GaitRecording, gait_metrics
from eigengait.control.gait_signatures import gait_signatures
from eigengait.control.lookahead import LookaheadRunner, LookaheadSettings
from eigengait.errors import UserInputError
from eigengait.sim.recording import frame_rows
from eigengait.sim.stepping import raise_blow_up
from eigengait.sim.world import GRAVITY

MAX_PUSH_N = 1e5  # N: beyond this a 0.1 s push launches any creature


@dataclass
class PlaybackResult:
    qpos: np.ndarray  # (frames × nq) at `fps`
    fps: float
    cycles_completed: int
    fell: bool
    mean_speed_mps: float  # forward COM speed over the played time
    active_energy: float  # J: positive mechanical work of the active torques, Σ max(τ·q̇, 0) dt
    mean_squared_torque: float  # (N·m)²: the thesis's E_energia, mean over steps of Σ_j τ_j²
    cost_of_transport: float  # active_energy / (m g distance), dimensionless
    cycle_violation: float  # max |φ_i| over the played cycles (each cycle's end against its start)
    snapped: bool = False
    lookahead: bool = False
    # gait_metrics() and gait_signatures() of the played motion
    quality: dict = field(default_factory=dict)
    # steps × n_internal applied active N·m
    torques: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    pushes: tuple[Push, ...] = ()
    pushes_survived: int | None = None

    def summary(self) -> dict:
        out = {
            "cycles_completed": self.cycles_completed,
            "fell": self.fell,
            "mean_speed_mps": round(float(self.mean_speed_mps), 4),
            "active_energy": round(self.active_energy, 3),
            "mean_squared_torque": round(float(self.mean_squared_torque), 3),
            "cost_of_transport": round(self.cost_of_transport, 4)
            if np.isfinite(self.cost_of_transport)
            else None,
            "cycle_violation": round(self.cycle_violation, 5)
            if np.isfinite(self.cycle_violation)
            else None,
            "snap": self.snapped,
            "lookahead": self.lookahead,
            **self.quality,
        }
        if self.pushes:
            out["pushes_survived"] = self.pushes_survived
        return out


def parse_pushes(text: str) -> tuple[Push, ...]:
    """`FORCE@TIME[,FORCE@TIME…]` (N, s) -> pushes; one clear error for anything else."""
    pushes = []
    for item in text.split(","):
        try:
            force, time = (float(v) for v in item.split("@"))
        except ValueError:
            raise UserInputError(
                f"cannot read push '{item.strip()}'",
                field="push",
                fix="write FORCE@TIME in N and s, e.g. 350@1.3,-350@2.5",
            ) from None
        if not (np.isfinite(force) and np.isfinite(time)) or time < 0 or abs(force) > MAX_PUSH_N:
            raise UserInputError(
                f"push '{item.strip()}' is out of range",
                field="push",
                fix=f"use a finite time ≥ 0 s and a force within ±{MAX_PUSH_N:.0f} N",
            )
        pushes.append(Push(time=time, force=force))
    return tuple(pushes)


def play(
    system: GaitSystem,
    p: GaitParameters,
    cycles: int = 4,
    snap: bool = False,
    fps: float = PLAYBACK_FPS,
    pushes: tuple[Push, ...] = (),
    source: str | None = None,
    lookahead: LookaheadSettings | None = None,
    progress=None,
) -> PlaybackResult:
    """Play `cycles` cycles, with `lookahead` decisions at each state start if given
    (`progress(cycle, cycles)` after each cycle); a blow-up raises `SimulationBlowUp` naming the
    time, the body and `source` (the controller file)."""
    if snap:
        run, completed = _play_snapped(ClosedLoopRunner(system), p, cycles)
    else:
        run = _run(system, p, cycles, pushes, lookahead, progress)
        completed = min(len(run.cycle_ends[0]), cycles)
    if run.blow_up[0] is not None:
        raise_blow_up(system.world, *run.blow_up[0], file=source)
    return _result(
        system, p, run, completed, snap, fps, pushes, planned=lookahead is not None and not snap
    )


def _run(system, p, cycles, pushes, lookahead: LookaheadSettings | None, progress=None) -> BatchRun:
    """One playback with no reset: with lookahead decisions, or the pulses and their feedback as
    they are."""
    if lookahead is None:
        return ClosedLoopRunner(system).run([p], cycles, pushes)
    runner = LookaheadRunner(system, lookahead)
    try:
        return runner.run(p, cycles, pushes, progress)
    finally:
        runner.close()


def _play_snapped(runner: ClosedLoopRunner, p: GaitParameters, cycles: int) -> tuple[BatchRun, int]:
    """Cycle by cycle from (q₀, q̇₀), open loop, keeping the root's forward position: the thesis's
    reset."""
    parts, completed, blow_up = [], 0, None
    view = runner.system.world.view
    forward = view.root.forward_qpos
    start = p
    for _ in range(cycles):
        run = runner.run([start], 1)
        parts.append(run)
        if run.fell[0]:
            blow_up = run.blow_up[0]
            break
        completed += 1
        qpos0 = p.qpos0.copy()
        if forward is not None:
            qpos0[forward] = view.qpos(run.states[0, -1])[forward]
        start = GaitParameters(**{**p.__dict__, "qpos0": qpos0})
    cat = lambda name: np.concatenate([getattr(r, name)[0, : r.ended[0]] for r in parts])[None]  # noqa: E731
    ended = sum(int(r.ended[0]) for r in parts)
    return BatchRun(
        states=cat("states"),
        sensors=cat("sensors"),
        torques=cat("torques"),
        ended=np.array([ended]),
        fell=np.array([parts[-1].fell[0]]),
        steps=np.array([ended]),
        fell_time=np.array([np.nan]),
        blow_up=[blow_up],
    ), completed


def _result(
    system: GaitSystem,
    p: GaitParameters,
    run: BatchRun,
    completed: int,
    snap: bool,
    fps: float,
    pushes: tuple[Push, ...],
    planned: bool = False,
) -> PlaybackResult:
    world, model, view = system.world, system.world.model, system.world.view
    dt = model.opt.timestep
    end = int(run.ended[0])
    states, sensors, torques = run.states[0, :end], run.sensors[0, :end], run.torques[0, :end]
    qvel = view.qvel(states)
    work = float(
        np.sum(np.clip(np.sum(torques * qvel[:, world.internal_qvel], axis=1), 0, None)) * dt
    )
    duration = end * dt
    distance = float(view.com(sensors[-1])[0] - system.initial_com(p)[0])
    states = np.vstack([system.initial_state(p), states])
    sensors = np.vstack([system.initial_sensors(p), sensors])
    frames = frame_rows(end, dt, fps)
    recording = GaitRecording(
        fps=fps,
        period=p.period,
        qpos=view.qpos(states)[frames],
        com=view.com(sensors)[frames],
        foot_points={f: view.foot_points(sensors[frames], f) for f in world.character.feet},
        foot_radius=dict(view.foot_radius),
    )
    quality = (
        {**gait_metrics(model, recording), **gait_signatures(model, recording)}
        if len(frames) > 1
        else {}
    )
    violation = (
        _violation(system, p, run, completed) if not snap else _snapped_violation(system, p, run)
    )
    mass = world.mass()
    return PlaybackResult(
        qpos=recording.qpos,
        fps=fps,
        cycles_completed=completed,
        fell=bool(run.fell[0]),
        mean_speed_mps=distance / duration if duration else 0.0,
        active_energy=work,
        mean_squared_torque=float(np.mean(np.sum(torques**2, axis=1))) if end else 0.0,
        cost_of_transport=work / (mass * GRAVITY * distance) if distance > 1e-6 else float("inf"),
        cycle_violation=violation,
        snapped=snap,
        lookahead=planned,
        quality=quality,
        pushes=tuple(pushes),
        pushes_survived=_pushes_survived(pushes, run) if pushes else None,
        torques=torques,
    )


def _violation(system: GaitSystem, p: GaitParameters, run: BatchRun, completed: int) -> float:
    if completed < 1:
        return float("nan")
    return float(np.abs(cycle_errors(system, p, run.states[0], completed, run.cycle_ends[0])).max())


def _snapped_violation(system: GaitSystem, p: GaitParameters, run: BatchRun) -> float:
    """With the reset every cycle starts at (q₀, q̇₀): the first cycle's error is every cycle's."""
    if run.ended[0] < int(round(p.period / system.world.model.opt.timestep)):
        return float("nan")
    return float(np.abs(cycle_errors(system, p, run.states[0], 1)).max())


def _pushes_survived(pushes: tuple[Push, ...], run: BatchRun) -> int:
    """A push is survived when the gait does not fall before the next push (or the end of the
    playback)."""
    return pushes_survived(
        [p.time for p in pushes], float(run.fell_time[0]) if run.fell[0] else None
    )


def pushes_survived(times_s: list[float], fall_time_s: float | None) -> int:
    """How many pushes (start times in s, each lasting PUSH_SECONDS) were survived, given when the
    character fell (None: it did not): a push is survived when the fall, if any, comes after the
    next push (or after the end of the run for the last one)."""
    if fall_time_s is None:
        return len(times_s)
    times = sorted(times_s)
    return sum(
        1
        for k, t in enumerate(times)
        if (times[k + 1] if k + 1 < len(times) else np.inf) <= fall_time_s
        and t + PUSH_SECONDS <= fall_time_s
    )


def push_robustness(
    system: GaitSystem,
    p: GaitParameters,
    impulse_per_kg: float = 0.5,
    cycle: int = 3,
    phases: int = 5,
    cycles_after: int = 10,
    lookahead: LookaheadSettings | None = None,
) -> list[bool]:
    """Survival of one sideways push of `impulse_per_kg` N·s/kg (over 0.1 s) given at each of
    `phases` evenly spaced phases of cycle `cycle` (1-based), the gait then playing `cycles_after`
    more cycles."""
    force = impulse_per_kg * system.world.mass() / PUSH_SECONDS
    start = (cycle - 1) * p.period
    survived = []
    for k in range(phases):
        push = Push(time=start + k * p.period / phases, force=force)
        run = _run(system, p, cycle + cycles_after, (push,), lookahead)
        if run.blow_up[0] is not None:
            raise_blow_up(system.world, *run.blow_up[0])
        survived.append(not bool(run.fell[0]))
    return survived
