"""Lookahead: predictive sampling in the mode basis, one decision at each state start.

At the start of every pulse state the controller draws `samples` plans. A plan adds a constant
torque Δτ = Φ Δψ to each of the states in the next `horizon_cycles` cycles, with Δψ in the mode
basis Φ of that state (its phase and stance foot, as the pulses themselves): the gait is still a
sequence of modal pulses, only their amplitudes move. Every plan is simulated from the current state
(`mujoco.rollout`, all plans in one call, at `plan_substeps` times the physics timestep) and scored
by `TaskCost`; the best plan's first state is played with the full physics, and the rest of it seeds
the next decision (warm start, as in MuJoCo MPC's predictive sampling; Howell et al. 2022). Plan 0
is always the warm start and plan 1 the unmodified gait, so a decision is never worse, by the model,
than playing the pulses as they are. `refinements` more rounds then draw plans around the best one
at half the spread each; when every plan still falls, the spread is doubled (twice at most) and
plans are drawn again.

Pushes act on the played motion only: the planner does not foresee them and answers them at the next
state start. The state machine runs on the clock (a touchdown-triggered gait is refused by the
controller file). With `feedback` on, the controller's own balance feedback (`feedback.py`: read
every 10 ms against the first played cycle) is added to the played motion and, once that reference
cycle is recorded, to every plan, simulated in 10 ms chunks as the optimizer does; off (the default:
measured in docs/locomotion.md), plans and played motion are the pulses alone. A gait with a
swing-foot servo (`swing_servo.py`) has it in the played motion and in every plan, read every 10 ms
the same way.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout

from eigengait.body_tree import ancestors
from eigengait.control.activations import mode_indices
from eigengait.control.closed_loop import BatchRun, FeedbackPlan, Push, add_pushes, clock_cycle_ends
from eigengait.control.feedback import FeatureReader, hip_motors_by_foot, steps_per_reading
from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.control.pulse import State
from eigengait.sim.contacts import spheres_touching
from eigengait.sim.falls import failed_steps, fallen
from eigengait.sim.stepping import blown_up_dof
from eigengait.sim.world import GRAVITY, World

# Cost weights; every term is dimensionless (lengths over the standing COM height h, speeds over
# √(g h)).
UPRIGHT_WEIGHT = 4.0  # × (1 − z of the root's up axis)
HEADING_WEIGHT = 4.0  # × (root yaw − its starting yaw)², rad²
HEIGHT_WEIGHT = 10.0  # × ((COM z − the first cycle's mean COM z) / h)²
SPEED_WEIGHT = 3.0  # × ((COM forward speed − target) / √(g h))², unless a gait sets its own
SIDE_SPEED_WEIGHT = 0.5  # × (COM sideways speed / √(g h))²
SIDE_WEIGHT = 0.2  # × (COM sideways offset from the start / h)²
# × Σ over the foot spheres touching the floor at two consecutive cost samples of (their horizontal
# speed / √(g h))² (`sliding_cost`), unless a gait sets its own: off by default, because the plans
# then buy clean feet with speed and uprightness (docs/locomotion.md, "Sliding feet in the plans'
# cost")
SLIP_WEIGHT = 0.0
# × a plan's size (`plan_size`: about 1 for a plan drawn at the spread), so that among plans that
# score alike the gentlest wins: off by default (docs/locomotion.md, "The plans' size")
EFFORT_WEIGHT = 0.0
FALL_COST = 1000.0  # a plan that falls costs this × (1 + share of the horizon left when it fell)
COST_EVERY = 0.01  # s between the samples of a plan's trajectory that the cost averages
MAX_ESCALATIONS = 2  # times the spread doubles when every plan falls
# plans per decision: with 32 the shipped monster run fell with 2 of 5 planner seeds and rolled its
# torso to ±50° with a third; with 96 it plays 20 cycles upright with every seed measured, at about
# three times the cost (docs/locomotion.md, "Plans per decision")
SAMPLES = 96
# plans give a joint off the feet's chains its subtree's mass share over this, at most 1
# (`plan_weights`): over planner seeds the run's and the monster's largest frame jumps fell from
# 25-27° and 26-28° to 15-17° and 15°, every play upright for 20 cycles (docs/locomotion.md,
# "Light limbs")
LIGHT_LIMB_SHARE = 0.5


@dataclass(frozen=True)
class LookaheadSettings:
    """How each state-start decision is searched. `speed`: target forward COM speed (m/s)."""

    speed: float
    samples: int = SAMPLES  # plans per decision
    horizon_cycles: float = 2.0  # how far each plan reaches (cycles)
    # std of each Δψ, as a share of the gait's mean |ψ| over its non-zero activations
    spread: float = 0.5
    # further rounds of plans around the best so far, each at half the previous spread
    refinements: int = 1
    # the lowest modes of each state's basis that the plans move (None: all)
    modes: int | None = None
    # or: per phase, the mode numbers they move (the sketch's)
    chosen: dict[str, tuple[int, ...]] | None = None
    plan_substeps: int = 2  # planning timestep = plan_substeps × the physics timestep
    seed: int = 0
    feedback: bool = False  # plans and played motion add the controller's balance feedback
    # light limbs (joints off every foot's chain: arms, heads, tails) get the plans' torque scaled
    # by their subtree's share of the body's mass over this share, at most 1 (`plan_weights`);
    # 0: plans move every joint in full
    min_mass_share: float = LIGHT_LIMB_SHARE
    # weight of the speed term in the plans' cost (`TaskCost`): higher holds the target speed
    # harder against staying upright and at height
    speed_weight: float = SPEED_WEIGHT
    # weight of the plans' sliding-feet term (`sliding_cost`): higher keeps touching feet still
    slip_weight: float = SLIP_WEIGHT
    # weight of the plans' size (`plan_size`): higher picks smaller offsets among alike plans
    effort_weight: float = EFFORT_WEIGHT
    # a plan whose root tilts further than this from upright (degrees) falls at that instant (None:
    # no bound): a plan that breaks the torso bound is chosen only when every plan does, after the
    # spread has been widened as for falls (a cost short of a fall, measured, kept the bound less
    # well: docs/locomotion.md)
    max_tilt_deg: float | None = None


class TaskCost:
    """Scores simulated plans: stay upright, keep the heading, height and speed, do not drift
    sideways or fall (and, with a `slip_weight`, do not slide the feet that touch the floor; with a
    `max_tilt_deg`, do not tilt the root past it)."""

    def __init__(
        self,
        system: GaitSystem,
        speed: float,
        height: float,
        start_qpos: np.ndarray,
        start_com: np.ndarray,
        speed_weight: float = SPEED_WEIGHT,
        slip_weight: float = SLIP_WEIGHT,
        max_tilt_deg: float | None = None,
    ):
        world = system.world
        self.root, self.view = world.root, world.view
        self.h = world.standing_com_height  # m, the standing COM height
        self.v_unit = np.sqrt(GRAVITY * self.h)
        self.speed, self.height, self.speed_weight = speed, height, speed_weight
        self.slip_weight = slip_weight
        # the root's up axis z below this is past the tilt bound (None: no bound)
        self.min_up_z = None if max_tilt_deg is None else float(np.cos(np.radians(max_tilt_deg)))
        self.heading = float(self.root.heading(start_qpos))
        self.side = float(start_com[1])

    def __call__(self, states: np.ndarray, sensors: np.ndarray, every: int) -> np.ndarray:
        """Cost per plan of rollout states and sensors (plans × steps × …), sampled every `every`
        steps."""
        bad = fallen(self.view, states, sensors, self.h)
        if self.min_up_z is not None:
            bad |= self.view.up_z(states) < self.min_up_z
        s, d = states[:, every - 1 :: every], sensors[:, every - 1 :: every]
        qpos = self.view.qpos(s)
        com, vel = self.view.com(d), self.view.com_velocity(d)
        yaw = np.angle(np.exp(1j * (self.root.heading(qpos) - self.heading)))
        with np.errstate(invalid="ignore", over="ignore"):
            terms = (
                UPRIGHT_WEIGHT * (1 - self.root.up_z(qpos))
                + HEADING_WEIGHT * yaw**2
                + HEIGHT_WEIGHT * ((com[..., 2] - self.height) / self.h) ** 2
                + self.speed_weight * ((vel[..., 0] - self.speed) / self.v_unit) ** 2
                + SIDE_SPEED_WEIGHT * (vel[..., 1] / self.v_unit) ** 2
                + SIDE_WEIGHT * ((com[..., 1] - self.side) / self.h) ** 2
            )
            cost = terms.mean(axis=1)
            if self.slip_weight:
                cost = cost + self.slip_weight * self._sliding(s, d)
        fell = bad.any(axis=1)
        left = 1 - bad.argmax(axis=1) / bad.shape[1]
        return np.where(fell | ~np.isfinite(cost), FALL_COST * (1 + left), cost)

    def _sliding(self, states: np.ndarray, sensors: np.ndarray) -> np.ndarray:
        """`sliding_cost` of every foot, summed, on the cost's samples (plans × samples × …)."""
        sample_dt = np.diff(self.view.time(states), axis=1)[..., None]
        return sum(
            sliding_cost(self.view.foot_points(sensors, foot), radius, sample_dt, self.v_unit)
            for foot, radius in self.view.foot_radius.items()
        )


def sliding_cost(
    points: np.ndarray, radius: float, sample_dt: np.ndarray | float, v_unit: float
) -> np.ndarray:
    """Per plan: the mean over pairs of consecutive samples of Σ (v / v_unit)², over the contact
    spheres touching the floor (`sim.contacts.spheres_touching`) at both samples, v the horizontal
    speed (m/s) of the sphere's centre between them. points: plans × samples × spheres × 3 (m);
    sample_dt: s between samples (plans × samples − 1 × 1, or one number)."""
    touching = spheres_touching(points[..., 2], radius)
    both = touching[:, 1:] & touching[:, :-1]
    speed = np.linalg.norm(np.diff(points[..., :2], axis=1), axis=-1) / sample_dt
    return ((speed / v_unit) ** 2 * both).sum(axis=-1).mean(axis=1)


def plan_size(
    plans: np.ndarray, directions: list[np.ndarray], state: int, sigma: float
) -> np.ndarray:
    """Per plan (plans × knots × motors, N·m): the mean over its knots of |Δτ|² / (σ² k), k the
    number of directions the knot's state draws in (`directions`, from `state` on, cyclically) and
    σ the spread (N·m); about 1 for a plan drawn at the spread from unit directions."""
    counts = np.array(
        [directions[(state + j) % len(directions)].shape[1] for j in range(plans.shape[1])]
    )
    return ((plans**2).sum(axis=-1) / (sigma**2 * counts)).mean(axis=1)


def plan_directions(system: GaitSystem, state: State, settings: LookaheadSettings) -> np.ndarray:
    """Torque columns (n_internal × k) a plan's Δψ moves in `state`: the lowest `settings.modes` of
    its basis, or the `settings.chosen` modes of its phase (a symmetric gait's second foot: the
    first foot's, mirrored); each joint's rows scaled by its `plan_weights`."""
    if settings.chosen is None:
        columns = system.basis_matrix(state.foot, state.phase)[:, : settings.modes]
    else:
        foot = state.foot if state.foot in system.active_feet else system.active_feet[0]
        basis = system.basis_matrix(foot, state.phase)
        chosen = mode_indices(m for m in settings.chosen[state.phase] if m <= basis.shape[1])
        columns = basis[:, chosen]
        if foot != state.foot:
            columns = system.mirror.dofs(columns.T).T
    return columns * plan_weights(system.world, settings.min_mass_share)[:, None]


def plan_weights(world: World, min_mass_share: float) -> np.ndarray:
    """Per internal dof (motor order), the share of a plan's torque it receives: 1 on the chain from
    the root to any foot's toe, elsewhere the share of the body's mass its body's subtree holds over
    `min_mass_share`, at most 1 (all 1 when `min_mass_share` is 0). A forearm then gets a few per
    cent of what a leg gets: the plans' whole-body mode shapes would otherwise fling the light
    limbs, whose torque limits are large for their inertia, at every decision."""
    if min_mass_share <= 0:
        return np.ones(world.nmotor)
    model = world.model
    subtree = np.asarray(model.body_subtreemass)
    on_legs = {
        b
        for foot in world.character.feet.values()
        for b in ancestors(model, model.site(foot.toe).bodyid[0])
    }
    share = subtree / subtree[world.root_body]
    bodies = model.dof_bodyid[np.asarray(world.internal_qvel)]
    return np.array([1.0 if b in on_legs else min(1.0, share[b] / min_mass_share) for b in bodies])


class LookaheadRunner:
    """Plays one gait with lookahead decisions for a number of cycles, optionally pushed
    sideways."""

    def __init__(self, system: GaitSystem, settings: LookaheadSettings, threads: int = 2):
        self.system, self.settings = system, settings
        self.model = system.world.model
        self.plan_model = copy.copy(self.model)
        self.plan_model.opt.timestep = self.model.opt.timestep * settings.plan_substeps
        self.datas = [mujoco.MjData(self.model) for _ in range(max(1, threads))]
        self.plan_datas = [mujoco.MjData(self.plan_model) for _ in range(max(1, threads))]
        self.pool = rollout.Rollout(nthread=threads if threads > 1 else 0)
        self.rng = np.random.default_rng(settings.seed)
        self.reader = FeatureReader(system.world)
        self.motors = hip_motors_by_foot(system.world, system.feet)
        self.chunk = steps_per_reading(self.model.opt.timestep)
        self.rollouts = 0  # plans simulated so far
        self.servo = system.servo

    def close(self) -> None:
        self.pool.close()

    def run(
        self,
        p: GaitParameters,
        cycles: float,
        pushes: tuple[Push, ...] = (),
        progress: Callable[[int, int], None] | None = None,
    ) -> BatchRun:
        """Play `cycles` cycles from (q₀, q̇₀); `progress(cycle, cycles)` is called after each
        completed cycle."""
        system, model, settings = self.system, self.model, self.settings
        dt, nv, nu, n_motor = model.opt.timestep, model.nv, model.nu, system.world.nmotor
        view = system.world.view
        states_of_cycle = system.states(p)
        cycle_controls = system.controls(p, cycles=1)
        n_cycle = len(cycle_controls)
        starts = [int(round(s.start / dt)) for s in states_of_cycle] + [n_cycle]
        total = int(round(cycles * p.period / dt))
        directions = [plan_directions(system, s, settings) for s in states_of_cycle]
        scale = _mean_activation(p)
        knots = int(np.ceil(settings.horizon_cycles * len(states_of_cycle))) + 1
        plan = np.zeros((knots, n_motor))
        x, x_sensors = system.initial_state(p), system.initial_sensors(p)
        cost = self._task_cost(p, x, cycle_controls)
        feedback = (
            FeedbackPlan(system, p, self.motors)
            if p.feedback.enabled and settings.feedback
            else None
        )
        chunk = self.chunk if feedback is not None or self.servo is not None else n_cycle
        limit = system.torque_limits
        spec = mujoco.mjtState.mjSTATE_CTRL | (
            mujoco.mjtState.mjSTATE_QFRC_APPLIED if pushes else 0
        )
        width = nu + (nv if pushes else 0)
        out_states = np.zeros((1, total, x.size))
        out_sensors = np.zeros((1, total, model.nsensordata))
        out_torques = np.zeros((1, total, n_motor))
        n, k, fell, fell_time, blow_up = 0, 0, False, np.nan, None
        while n < total and not fell:
            state = k % len(states_of_cycle)
            lengths = [
                starts[(state + j) % len(states_of_cycle) + 1]
                - starts[(state + j) % len(states_of_cycle)]
                for j in range(knots)
            ]
            horizon = min(sum(lengths), int(round(settings.horizon_cycles * n_cycle)))
            nominal = cycle_controls[(n + np.arange(horizon)) % n_cycle]
            start = (n * dt, x_sensors, feedback)
            plan, controls = self._decide(
                x, plan, nominal, lengths, horizon, state, directions, scale, cost, start
            )
            segment = min(lengths[0], total - n)
            for a in range(0, segment, chunk):
                b = min(segment, a + chunk)
                u = controls[a:b].copy()
                tau = self.servo.torque(x) if self.servo is not None else 0.0
                if feedback is not None:
                    t = (n + a) * dt
                    tau = tau + feedback.torque(
                        self.reader, int(t // p.period), t % p.period, x, x_sensors
                    )
                u[:, :n_motor] = np.clip(u[:, :n_motor] + tau, -limit, limit)
                control = np.zeros((1, b - a, width))
                control[0, :, :nu] = u
                add_pushes(control, pushes, n + a, dt, nu)
                s, d = self.pool.rollout(model, self.datas, x[None], control, control_spec=spec)
                out_states[0, n + a : n + b], out_sensors[0, n + a : n + b] = s[0], d[0]
                out_torques[0, n + a : n + b] = system.world.applied_motor_torques(
                    s[0], control[0, :, :n_motor]
                )
                bad, blown, qvel = failed_steps(view, s, d, view.time(x)[None, None], cost.h, dt)
                bad, blown, qvel = bad[0], blown[0], qvel[0]
                if bad.any():
                    first = int(np.argmax(bad))
                    fell, fell_time = True, (n + a + first + 1) * dt
                    if blown[first]:
                        blow_up = (fell_time, blown_up_dof(qvel, first))
                    n += a + first + 1
                    break
                x, x_sensors = s[0, -1].copy(), d[0, -1].copy()
            if fell:
                break
            n += segment
            k += 1
            if progress is not None and state == len(states_of_cycle) - 1:
                progress(k // len(states_of_cycle), int(np.ceil(cycles)))
        return BatchRun(
            states=out_states,
            sensors=out_sensors,
            torques=out_torques,
            ended=np.array([n]),
            fell=np.array([fell]),
            steps=np.array([total]),
            fell_time=np.array([fell_time]),
            blow_up=[blow_up],
            cycle_ends=[[e for e in clock_cycle_ends(p.period, dt, int(np.ceil(cycles))) if e < n]],
        )

    def _task_cost(self, p: GaitParameters, x: np.ndarray, cycle_controls: np.ndarray) -> TaskCost:
        """The cost with the first cycle's mean COM height (played as the pulses are) as its height
        target."""
        system = self.system
        _, d = self.pool.rollout(self.model, self.datas, x[None], cycle_controls[None])
        height = float(np.mean(system.world.view.com(d[0])[:, 2]))
        settings = self.settings
        return TaskCost(
            system,
            settings.speed,
            height,
            p.qpos0,
            system.initial_com(p),
            settings.speed_weight,
            settings.slip_weight,
            settings.max_tilt_deg,
        )

    def _decide(self, x, plan, nominal, lengths, horizon, state, directions, scale, cost, start):
        """Best plan (knots × motors) and its controls (horizon × nu) from state `x`; the plan comes
        back shifted by one state, ready to warm-start the next decision. `start`: (time s, sensors,
        feedback plan or None)."""
        settings, n_motor = self.settings, self.system.world.nmotor
        K, knots, sub = settings.samples, len(lengths), settings.plan_substeps
        bounds = np.concatenate([[0], np.cumsum(lengths)])
        limit, sigma = self.system.torque_limits, settings.spread * scale
        best, best_cost, center = None, np.inf, plan
        rounds = [0.5**r for r in range(settings.refinements + 1)]
        rounds += [2.0**e for e in range(1, MAX_ESCALATIONS + 1)]
        for r, factor in enumerate(rounds):
            noise = np.zeros((K, knots, n_motor))
            for j in range(knots):
                basis = directions[(state + j) % len(directions)]
                noise[:, j] = self.rng.normal(0.0, sigma * factor, (K, basis.shape[1])) @ basis.T
            candidates = center[None] + noise
            candidates[0], candidates[1] = center, 0.0
            controls = np.repeat(nominal[None], K, axis=0)
            for j in range(knots):
                lo, hi = bounds[j], min(bounds[j + 1], horizon)
                if lo < hi:
                    controls[:, lo:hi, :n_motor] += candidates[:, j, None]
            controls[..., :n_motor] = np.clip(controls[..., :n_motor], -limit, limit)
            s, d = self._simulate_plans(
                x, np.ascontiguousarray(controls[:, sub - 1 :: sub]), *start
            )
            self.rollouts += K
            scores = cost(s, d, max(1, int(round(COST_EVERY / self.plan_model.opt.timestep))))
            if settings.effort_weight:
                size = plan_size(candidates, directions, state, sigma)
                scores = np.where(
                    scores < FALL_COST, scores + settings.effort_weight * size, scores
                )
            i = int(np.argmin(scores))
            if scores[i] < best_cost:
                best, best_cost, best_controls = candidates[i], scores[i], controls[i]
            center = best
            if r >= settings.refinements and best_cost < FALL_COST:
                break
        shifted = np.vstack([best[1:], np.zeros((1, n_motor))])
        return shifted, best_controls

    def _simulate_plans(self, x, controls, time, sensors, feedback):
        """Rollout states and sensors of plans (controls: plans × plan steps × nu) from state `x` at
        `time` (s). Once the feedback's reference cycle is recorded, the plans add the controller's
        feedback as the played motion will, and the swing-foot servo if the gait has one, read every
        `FEEDBACK_DT` of plan time; with neither, one rollout call."""
        K, steps = controls.shape[:2]
        now = np.repeat(x[None], K, axis=0)
        if feedback is not None and time < feedback.period:
            feedback = None  # its reference cycle is still being recorded
        if feedback is None and self.servo is None:
            return self.pool.rollout(self.plan_model, self.plan_datas, now, controls)
        n_motor, limit = self.system.world.nmotor, self.system.torque_limits
        dt = self.plan_model.opt.timestep
        chunk = steps_per_reading(dt)
        states, out = np.empty((K, steps, x.size)), np.empty((K, steps, sensors.size))
        now_sensors = np.repeat(sensors[None], K, axis=0)
        for a in range(0, steps, chunk):
            b = min(steps, a + chunk)
            tau = self.servo.torque(now) if self.servo is not None else np.zeros((K, n_motor))
            if feedback is not None:
                phase = (time + a * dt) % feedback.period
                k = feedback.state_index(phase)
                with np.errstate(invalid="ignore", over="ignore"):
                    features = self.reader.read(now, now_sensors, feedback.roles[k].support)
                    tau += feedback.response(k, features, phase)
            tau = np.nan_to_num(tau, nan=0.0, posinf=0.0, neginf=0.0)
            u = controls[:, a:b].copy()
            u[..., :n_motor] = np.clip(u[..., :n_motor] + tau[:, None], -limit, limit)
            s, d = self.pool.rollout(self.plan_model, self.plan_datas, now, u)
            states[:, a:b], out[:, a:b] = s, d
            now, now_sensors = np.ascontiguousarray(s[:, -1]), d[:, -1]
        return states, out


def _mean_activation(p: GaitParameters) -> float:
    """Mean |ψ| (N·m) over the gait's non-zero activations (1 N·m if it has none)."""
    values = np.concatenate([np.abs(v) for v in p.activations.values()])
    values = values[values > 1e-9]
    return float(values.mean()) if values.size else 1.0
