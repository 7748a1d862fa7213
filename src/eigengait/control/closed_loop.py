"""Play many pulse controllers with balance feedback as one batch, stepping in C between feedback
readings.

The horizon is cut into chunks of `FEEDBACK_DT`; each chunk is one `mujoco.rollout` call over the
candidates still standing. At each chunk boundary the features of every candidate are read from its
last state (NumPy, whole batch), recorded as the reference during the first cycle, and turned into
feedback torques afterwards (see `feedback.py`). Sideways pushes are generalized forces on the
root's y translation; an optional hand on the root (`root_assist.py`, optimization only) adds its
forces, read at each boundary and held like the feedback. A candidate falls when its COM drops
below half the standing height, its root turns upside down, or it blows up (`sim/falls.py`'s
`failed_steps` and `sim/stepping.py`: a non-finite or runaway state, or a torque MuJoCo would
refuse; recorded as `blow_up`); it is not simulated further.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout

from eigengait.control.activations import mode_indices
from eigengait.control.feedback import (
    EVENT_MIRROR_SIGNS,
    MIRROR_SIGNS,
    FeatureReader,
    FeedbackGains,
    StateRole,
    hip_motors_by_foot,
    steps_per_reading,
    hip_torque,
    state_roles,
)
from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.control.phase_clock import MAX_WAIT, PhaseClock
from eigengait.control.root_assist import RootAssist
from eigengait.sim.falls import failed_steps
from eigengait.sim.stepping import blown_up_dof, first_bad_torque

PUSH_SECONDS = 0.1  # s, duration of every push


@dataclass(frozen=True)
class Push:
    time: float  # s from the start of the playback
    force: float  # N along world +y on the root body


@dataclass
class BatchRun:
    """Recorded batch: every array is candidates × steps × …; rows past `ended[i]` are unused."""

    states: np.ndarray  # MuJoCo full physics states after each step
    sensors: np.ndarray  # sensordata after each step
    torques: np.ndarray  # applied motor torques (pulses + feedback, clipped), N·m
    ended: np.ndarray  # steps simulated per candidate
    fell: np.ndarray  # bool per candidate
    steps: np.ndarray  # steps asked for per candidate
    fell_time: np.ndarray  # s, when each fallen candidate fell (nan if it did not)
    blow_up: list = None  # per candidate: (time s, dof) of a blow-up, or None
    cycle_ends: list = None  # per candidate: index of the last step of each completed cycle


def add_pushes(
    control: np.ndarray, pushes: tuple[Push, ...], first_step: int, dt: float, nu: int
) -> None:
    """Write the pushes active during a chunk into its applied generalized forces, in place:
    `control` is candidates × steps × (nu + nv), its first row the physics step `first_step`; a push
    is a force (N) on qvel 1, the root's sideways translation."""
    times = (first_step + np.arange(control.shape[1])) * dt
    for push in pushes:
        on = (times >= push.time) & (times < push.time + PUSH_SECONDS)
        control[:, on, nu + 1] = push.force


def clock_cycle_ends(period: float, timestep: float, cycles: int) -> list[int]:
    """Index of the last physics step of each of `cycles` cycles played on the fixed clock."""
    return [int(round(c * period / timestep)) - 1 for c in range(1, cycles + 1)]


def cycle_errors(
    system: GaitSystem,
    p: GaitParameters,
    states: np.ndarray,
    cycles: int,
    ends: list[int] | None = None,
) -> np.ndarray:
    """Hard cyclic constraint over `cycles` played cycles (states: steps × MuJoCo full physics
    state; `ends`: the last step of each cycle, by default the fixed clock's).

    One block per cycle k: the state at its end against the state at its start ((q₀, q̇₀) for the
    first); for symmetric gaits one more block: the mirrored state half a cycle in against (q₀, q̇₀).
    """
    view, dt = system.world.view, system.world.model.opt.timestep
    q = lambda k: view.qpos(states[k])  # noqa: E731
    v = lambda k: view.qvel(states[k])  # noqa: E731
    ends = clock_cycle_ends(p.period, dt, cycles) if ends is None else ends
    errors, start = [], None
    for k in ends[:cycles]:
        ref = (p.qpos0, p.qvel0) if start is None else (q(start), v(start))
        errors.append(system.state_error(*ref, q(k), v(k)))
        start = k
    if system.mirror is not None:
        k = int(round(0.5 * p.period / dt)) - 1
        errors.append(system.half_cycle_error(p, q(k), v(k)))
    return np.concatenate(errors)


class FeedbackPlan:
    """One candidate's per-state feedback matrices G (n_states × n_motor × 8) and its reference
    recorder, and its ``event`` matrices E (n_states × n_motor × 10, or None)."""

    def __init__(self, system: GaitSystem, p: GaitParameters, motors: dict[str, tuple[int, int]]):
        self.states = system.states(p)
        self.roles = state_roles(self.states)
        self.period = p.period
        self.starts = np.array([s.start for s in self.states])
        n_motor = system.world.nmotor
        gains = p.feedback
        self.G = _per_state(
            system,
            self.states,
            lambda c: _canonical_matrix(
                system, gains, self.states[c], self.roles[c], motors, n_motor
            ),
            MIRROR_SIGNS,
        )
        self.enabled = gains.enabled
        self.event = gains.event
        self.E = (
            _per_state(
                system,
                self.states,
                lambda c: _event_matrix(system, self.states[c], gains.event),
                EVENT_MIRROR_SIGNS,
            )
            if gains.event
            else None
        )
        self.event_held: tuple[int, int] | None = None  # (cycle, state) of the held correction
        self.event_tau: np.ndarray | float = 0.0
        self.ref_phase: list[float] = []  # first-cycle readings: phase (s) and features
        self.ref_value: list[np.ndarray] = []

    def torque(
        self,
        reader: FeatureReader,
        cycle: int,
        phase: float,
        state: np.ndarray,
        sensors: np.ndarray,
    ) -> np.ndarray | float:
        """Feedback torque (n_motor,) at a cycle's `phase` (s) from the current state and sensors:
        the ``event`` correction while a pulse lasts, plus, once the first cycle is recorded as the
        reference, the ``hip`` and ``modal`` mechanisms' response; 0 with no mechanism enabled."""
        k = self.state_index(phase)
        tau = self.event_torque(reader, cycle, k, phase, state, sensors)
        features = reader.read(state, sensors, self.roles[k].support)
        if self.record(cycle, phase, features) or not self.enabled:
            return tau
        return tau + self.response(k, features, phase)

    def event_torque(
        self,
        reader: FeatureReader,
        cycle: int,
        k: int,
        phase: float,
        state: np.ndarray,
        sensors: np.ndarray,
    ) -> np.ndarray | float:
        """The ``event`` pulse correction (n_motor,) of state k, read at its first reading in
        `cycle` and held while its pulse lasts; 0 outside the pulse or without the mechanism."""
        s = self.states[k]
        if self.E is None or phase - s.start >= s.pulse:
            return 0.0
        if self.event_held != (cycle, k):
            f = reader.read_event(state, sensors, self.roles[k].support, self.event.speed)
            self.event_tau = self.E[k] @ f
            self.event_held = (cycle, k)
        return self.event_tau

    def response(self, k: int, features: np.ndarray, phase: float) -> np.ndarray:
        """Torque (…×n_motor) of state k's gains for features (…×8) read at a cycle's `phase` (s),
        once the reference cycle is recorded."""
        return (features - self.reference(phase)) @ self.G[k].T

    def record(self, cycle: int, phase: float, features: np.ndarray) -> bool:
        """Store a first-cycle reading (phase in s); True while the reference is still being
        recorded."""
        if cycle == 0:
            self.ref_phase.append(phase)
            self.ref_value.append(features)
            return True
        return False

    def role_at(self, phase: float) -> StateRole:
        """The roles of the feet in the state at a cycle's `phase` (s)."""
        return self.roles[self.state_index(phase)]

    def state_index(self, phase: float) -> int:
        return int(np.searchsorted(self.starts, phase, side="right") - 1)

    def reference(self, phase: float) -> np.ndarray:
        """Reference features at a cycle phase (s), interpolated between the reference cycle's
        readings."""
        ph = np.asarray(self.ref_phase)
        k = int(np.searchsorted(ph, phase))
        if k == 0:
            return self.ref_value[0]
        if k >= len(ph):
            return self.ref_value[-1]
        w = (phase - ph[k - 1]) / (ph[k] - ph[k - 1])
        return (1 - w) * self.ref_value[k - 1] + w * self.ref_value[k]


def _per_state(system: GaitSystem, states, matrix, signs: np.ndarray) -> np.ndarray:
    """Per state, `matrix(c)` (n_motor × features) of its canonical state c: itself, or for a
    symmetric gait's second foot its first-foot twin half a cycle earlier, whose matrix is then
    mirrored (rows as dofs, feature columns times `signs`)."""
    first, out = states[0].foot, []
    for k, s in enumerate(states):
        mirrored = system.mirror is not None and s.foot != first
        M = matrix(k - len(states) // 2 if mirrored else k)
        out.append(system.mirror.dofs(M.T).T * signs if mirrored else M)
    return np.stack(out)


def _event_matrix(system: GaitSystem, state, event) -> np.ndarray:
    """The ``event`` torque per unit feature (n_motor × 10) of a state: its phase's mode columns
    times their gains (zero when the phase has none)."""
    if state.phase not in event.phases:
        return np.zeros((system.world.nmotor, len(EVENT_MIRROR_SIGNS)))
    modes, K = event.phases[state.phase]
    return system.basis_matrix(state.foot, state.phase)[:, mode_indices(modes)] @ K


def _canonical_matrix(
    system: GaitSystem, gains: FeedbackGains, state, role, motors, n_motor: int
) -> np.ndarray:
    G = np.zeros((n_motor, 8))
    if gains.hip is not None:
        for i in range(8):
            G[:, i] = hip_torque(gains.hip, np.eye(8)[i], role, motors, n_motor)
    if state.phase in gains.modal:
        modes, K = gains.modal[state.phase]
        basis = system.basis_matrix(state.foot, state.phase)[:, mode_indices(modes)]
        G += basis @ K
    return G


class ClosedLoopRunner:
    """Simulates pulse controllers with feedback for several cycles, as one batch on a C thread
    pool."""

    def __init__(self, system: GaitSystem, threads: int = 1):
        self.system = system
        world = system.world
        self.model = world.model
        self.datas = [mujoco.MjData(self.model) for _ in range(max(1, threads))]
        # this runner's own threads
        self.pool = rollout.Rollout(nthread=threads if threads > 1 else 0)
        self.reader = FeatureReader(world)
        self.motors = hip_motors_by_foot(world, system.feet)
        self.standing_com = world.standing_com_height
        self.chunk = steps_per_reading(self.model.opt.timestep)
        self.motor_dofs = np.asarray(world.internal_qvel)
        self.steps_simulated = 0
        self.servo = system.servo
        self.layer = system.balance_layer

    def close(self) -> None:
        """Stop this runner's threads (other runners and MuJoCo's shared pool are not touched)."""
        self.pool.close()

    def run(
        self,
        params: list[GaitParameters],
        cycles: float,
        pushes: tuple[Push, ...] = (),
        assist: RootAssist | None = None,
    ) -> BatchRun:
        model, system, dt = self.model, self.system, self.model.opt.timestep
        nv, nu, n_motor = model.nv, model.nu, system.world.nmotor
        P = len(params)
        ff = [system.controls(p, span=cycles * p.period) for p in params]
        # a touchdown-timed gait plays until it completes `cycles` cycles, its late touchdowns
        # allowed for
        stretch = [1.0 if p.trigger == "clock" else 1.0 + MAX_WAIT for p in params]
        steps = np.array([int(len(u) * k) for u, k in zip(ff, stretch)])
        N = int(steps.max())
        plans = [FeedbackPlan(system, p, self.motors) for p in params]
        clocks = [
            PhaseClock(system.states(p), system.controls(p, cycles=1), dt)
            if p.trigger == "touchdown"
            else None
            for p in params
        ]
        state = np.stack([system.initial_state(p) for p in params])
        sensors_now = np.stack([system.initial_sensors(p) for p in params])
        nstate = state.shape[1]
        states = np.zeros((P, N, nstate))
        sensors = np.zeros((P, N, model.nsensordata))
        torques = np.zeros((P, N, n_motor))
        ended, fell, alive = steps.copy(), np.zeros(P, bool), np.ones(P, bool)
        fell_time = np.full(P, np.nan)
        blow_up: list = [None] * P
        spec = mujoco.mjtState.mjSTATE_CTRL | (
            mujoco.mjtState.mjSTATE_QFRC_APPLIED if pushes or assist else 0
        )
        width = nu + (nv if pushes or assist else 0)
        limit = system.torque_limits

        def end(i: int, step: int) -> None:
            """Candidate i stops after `step` steps, fallen."""
            fell[i], alive[i], ended[i], fell_time[i] = True, False, step, step * dt

        for a in range(0, N, self.chunk):
            b = min(N, a + self.chunk)
            idx = np.flatnonzero(alive)
            if idx.size == 0:
                break
            control = np.zeros((idx.size, b - a, width))
            keep = np.ones(idx.size, bool)
            t = a * dt
            servo = self.servo.torque(state[idx]) if self.servo is not None else None
            for k, i in enumerate(idx):
                upto = min(b, steps[i])
                if upto <= a:
                    continue
                clock, period = clocks[i], params[i].period
                if clock is None:
                    cycle, phase = int(t // period), t % period
                    u = ff[i][a:upto].copy()
                else:
                    cycle, phase = clock.cycle, clock.phase_time
                    u = clock.controls(upto - a)
                tau_fb = plans[i].torque(self.reader, cycle, phase, state[i], sensors_now[i])
                if servo is not None:
                    tau_fb = tau_fb + servo[k]
                if self.layer is not None:
                    tau_fb = tau_fb + self.layer.torque(
                        state[i], sensors_now[i], plans[i].role_at(phase)
                    )
                u[:, :n_motor] = np.clip(u[:, :n_motor] + tau_fb, -limit, limit)
                control[k, : upto - a, :nu] = u
                bad_torque = first_bad_torque(u[:, :n_motor], self.motor_dofs)
                if bad_torque is not None:  # never handed to MuJoCo, which would reset and hide it
                    keep[k] = False
                    end(i, a + bad_torque[0])
                    blow_up[i] = (fell_time[i], bad_torque[1])
            idx, control = idx[keep], control[keep]
            if idx.size == 0:
                break
            add_pushes(control, pushes, a, dt, nu)
            if assist is not None:
                w = nu + assist.first_qvel
                control[:, :, w : w + 4] += assist.forces(state[idx])[:, None, :]
            time_before = system.world.view.time(state[idx])[:, None]
            s, d = self.pool.rollout(model, self.datas, state[idx], control, control_spec=spec)
            self.steps_simulated += idx.size * (b - a)
            states[idx, a:b], sensors[idx, a:b] = s, d
            torques[idx, a:b] = system.world.applied_motor_torques(s, control[:, :, :n_motor])
            state[idx], sensors_now[idx] = s[:, -1], d[:, -1]
            bad, blown, qvel = failed_steps(
                system.world.view, s, d, time_before, self.standing_com, dt
            )
            for k, i in enumerate(idx):
                upto = min(b, steps[i]) - a
                hit = np.flatnonzero(bad[k, :upto])
                if hit.size:
                    end(i, a + hit[0] + 1)
                    diverged = np.flatnonzero(blown[k, :upto])
                    if diverged.size:
                        blow_up[i] = (
                            (a + diverged[0] + 1) * dt,
                            blown_up_dof(qvel[k], diverged[0]),
                        )
                elif steps[i] <= b:
                    alive[i] = False
                elif clocks[i] is not None and clocks[i].cycle >= cycles:
                    alive[i], ended[i], steps[i] = (
                        False,
                        clocks[i].cycle_ends[int(np.ceil(cycles)) - 1] + 1,
                        b,
                    )
                if clocks[i] is not None:
                    clocks[i].observe(self._touching(sensors_now[i]))
        return BatchRun(
            states=states,
            sensors=sensors,
            torques=torques,
            ended=ended,
            fell=fell,
            steps=steps,
            fell_time=fell_time,
            blow_up=blow_up,
            cycle_ends=[
                [e for e in clock_cycle_ends(p.period, dt, int(np.ceil(cycles))) if e < ended[i]]
                if c is None
                else c.cycle_ends
                for i, (p, c) in enumerate(zip(params, clocks))
            ],
        )

    def _touching(self, sensors: np.ndarray) -> dict[str, bool]:
        """Whether each foot touches the ground (`sim/contacts.py`), from its contact spheres'
        centre sensors."""
        return {f: bool(on) for f, on in self.system.world.view.feet_touching(sensors).items()}
