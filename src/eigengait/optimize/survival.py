"""Harden a gait: optimize how long it survives, with no reset, under sampled sideways pushes.

After Wang, Fleet & Hertzmann (2010, "Optimizing walking controllers for uncertain inputs and
environments"): the objective is the expected outcome over random disturbances, not the cyclic
constraint. Each candidate is played `copies` times from (q₀, q̇₀): once undisturbed and otherwise
pushed sideways once, at a random time between the second cycle and three cycles before the horizon,
with a random sign and an impulse drawn from `push_impulse` (N·s per kg of body mass, over 0.1 s).
Every candidate of a generation meets the same pushes (common random numbers), so their ranking
compares controllers, not luck. The cost of one candidate is

    mean over copies of (1 − cycles survived / H)  +  w_v · max(0, v* − v) / v*
                                                 +  EFFORT_WEIGHT · max(0, E / E* − 1)
                                                 +  SLIP_WEIGHT · max(0, s / s* − 1)
                                                 +  TILT_WEIGHT · max(0, θ / θ* − 1)
                                                 +  PAIR_WEIGHT · P

with v the undisturbed copy's mean forward COM speed from the end of its first cycle (a push
speeds or slows a play, and the launch from the initial state is not the gait), v* = `speed_share`
× the starting gait's speed, E the mean squared motor torque (the thesis's E_energia) and E* =
`effort_share` × the starting gait's (that term only when `effort_share` is set): a gait cannot buy
survival by standing still or by flailing. s is the copies' mean stance-foot slip
(`stance_slip_max_m` of the gait metrics, the feet sampled at 60 frames/s) and s* = `max_slip`
(that term only when `max_slip` is set): a gait cannot keep its feet by sliding them either. θ is
the undisturbed copy's largest root pitch or roll and θ* = `max_tilt_deg` (only
when set). P (only with `paired_feet`) charges a footfall pattern the gait does not keep, read on
the undisturbed copy from its third cycle on: per pair of feet that should land together, how far
(in cycles) their mean touchdown phases lie apart beyond `PAIR_TOLERANCE`, and with two pairs, how
far the pairs lie from half a cycle apart beyond it; a foot that never lands again costs
`PAIR_MISSING`. `target_speed` (m/s), when given, replaces `speed_share` × the starting speed as
v*; w_v = `speed_weight` (`SPEED_WEIGHT` unless set: raise it for a gait that buys survival by
slowing down). The horizon H starts at `horizon` cycles and grows by `HORIZON_STEP` (up to
`max_horizon`) whenever the generation's median candidate survives it: the optimizer always sees
the fall it has to prevent. With `assist` (a level, `control/root_assist.py`) every play starts with
a hand on the root that catches the body past the targets' tilt and below 0.8 of its height;
whenever the median candidate survives the horizon the hand weakens by `ASSIST_DECAY` (to nothing
below `ASSIST_FLOOR`), and only without it does the horizon grow: a gait that falls on its own has
survivors to rank from the first generation. The best candidate is the one that needed the weakest
hand, and the final choice is validated with none.

Searched (normalized, 0 = the starting gait): the period (±20 %), the air ratio (±0.1), both pulse
durations (±30 %), every non-zero activation ψ (± half its size, at least ±5 N·m), the eight
`hip` feedback gains (± 0.3 m g h per normalized unit, added when the gait had none). With
`event_modes` (phase -> 1-based modes) the search is the activations and the ``event`` feedback's
gains on those modes instead (± 0.6 m g h per normalized unit, added to the gait's own; its target
speed `target_speed`), the timing and the hip gains kept as they are. Given the
sketch's timing, the period, air ratio and pulse durations also stay within the bounds `optimize`
keeps them in (`optimize/parameters.py`), so that hardening a gait again and again cannot walk its
timing away from the sketch. The initial state and the trigger are kept.

A run folder holds `survival.json` (settings and every generation's candidates and costs: the
checkpoint, replayed on resume through CMA-ES from the same seed), `log.csv` and
`best_controller.json`.
"""

from __future__ import annotations

import json
import time
from dataclasses import asdict, dataclass, fields, replace
from pathlib import Path

import cma
import numpy as np

from eigengait.control.closed_loop import PUSH_SECONDS, ClosedLoopRunner, Push
from eigengait.control.controller import save_controller, to_file
from eigengait.control.feedback import EVENT_FEATURES, EventGains, FeedbackGains
from eigengait.control.gait_targets import MAX_SLIP_M, MAX_TILT_DEG
from eigengait.control.gait_metrics import (
    circular_mean_turn,
    phase_distance,
    rollout_footfalls,
    rollout_stance_slips,
)
from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.control.lookahead import LookaheadSettings
from eigengait.control.root_assist import RootAssist
from eigengait.control.sketch import Sketch, Timing
from eigengait.errors import UserInputError
from eigengait.optimize.parameters import timing_bounds
from eigengait.outputs import write_atomically
from eigengait.sim.root import root_layout
from eigengait.sim.world import GRAVITY

SPEED_WEIGHT = 0.5
EFFORT_WEIGHT = 0.5
SLIP_WEIGHT = 0.5
TILT_WEIGHT = 0.5
PAIR_WEIGHT = 2.0
# normalized gain units, in m g h (N·m per normalized feature): hip feedback, event feedback (the
# event gains start from zero; the shipped dog's reach 1.7 m g h, docs/locomotion.md)
HIP_GAIN_SCALE = 0.3
EVENT_GAIN_SCALE = 0.6
PAIR_TOLERANCE = 0.1  # cycles
PAIR_MISSING = 3.0  # the pattern term of a gait with a foot that stops landing
EVENT_FIRST_SHARE = 1 / 6  # of a staged event search's minutes, before slip and pairs count
EVENT_POPSIZE = 16  # candidates per generation of a staged event search
HORIZON_STEP = 4  # cycles added when the median candidate survives the horizon
ASSIST_DECAY = 0.8  # the hand's level is multiplied by this when the median candidate survives
ASSIST_FLOOR = 0.1  # a weaker hand is taken away
CHECKPOINT = "survival.json"
VALIDATION_GENERATION = -1  # the pushes of the final choice: a stream no generation uses


@dataclass(frozen=True)
class StartingFigures:
    """What the starting gait does, played 20 cycles undisturbed: the references of the speed and
    effort terms."""

    speed: float  # m/s, mean forward COM speed
    effort: float  # (N·m)², mean over steps of Σ_j τ_j²

    @classmethod
    def of(cls, played) -> "StartingFigures":
        """From a `control.playback.PlaybackResult` of the starting gait."""
        return cls(speed=played.mean_speed_mps, effort=played.mean_squared_torque)


@dataclass(frozen=True)
class SurvivalSettings:
    minutes: float  # wall-clock budget
    generations: int | None = None  # optional cap on the generations (resumed ones included)
    seed: int = 1
    popsize: int = 12
    copies: int = 3  # plays per candidate: one undisturbed, the others pushed once
    push_impulse: tuple[float, float] = (0.2, 0.6)  # N·s/kg, range of the sampled pushes
    horizon: int = 8  # cycles, at the start
    max_horizon: int = 24
    speed_share: float = 0.9  # the gait must keep this share of its starting speed
    # and use at most this share of its starting mean squared torque (None: no effort term)
    effort_share: float | None = 1.2
    # m: stance-foot slip above this is penalized (None: not measured)
    max_slip: float | None = MAX_SLIP_M
    sigma0: float = 0.3
    threads: int = 1
    max_tilt_deg: float | None = None  # root pitch or roll beyond this is penalized
    target_speed: float | None = None  # m/s: v* of the speed term (None: speed_share × start)
    speed_weight: float = SPEED_WEIGHT  # w_v: the speed term's weight against survival
    assist: float | None = None  # starting level of the hand on the root (None: no hand)
    paired_feet: tuple[tuple[str, str], ...] = ()  # feet that should land together
    event_modes: dict[str, tuple[int, ...]] | None = None  # phase -> modes of searched event gains
    # name -> (low, high) of the period (s), air ratio and pulse durations (s) from the sketch's
    # timing (`optimize.parameters.timing_bounds`; None: not bounded); `harden` sets it
    sketch_timing_bounds: dict[str, tuple[float, float]] | None = None

    @property
    def reads_starting_figures(self) -> bool:
        """Whether the speed or effort term is relative to the starting gait's `StartingFigures`."""
        return self.target_speed is None or self.effort_share is not None


class SurvivalSpace:
    """Normalized offsets z from a starting gait, and back (`decode`); the decoded timing is
    clipped to `bounds` (name -> (low, high), `timing_bounds` of the sketch's timing) when given.
    With `event_modes` (phase -> 1-based modes) z is the activations and the ``event`` gains on
    those modes, read against `target_speed` (m/s); the timing and the hip gains are then kept
    and have no coordinates. Otherwise z is the timing (4), the activations and the hip gains (8).
    """

    def __init__(
        self,
        system: GaitSystem,
        start: GaitParameters,
        bounds: dict[str, tuple[float, float]] | None = None,
        event_modes: dict[str, tuple[int, ...]] | None = None,
        target_speed: float | None = None,
    ):
        self.start, self.bounds = start, bounds
        self.slots = [
            (key, int(i)) for key, psi in start.activations.items() for i in np.flatnonzero(psi)
        ]
        self.psi_scale = np.array(
            [max(0.5 * abs(start.activations[k][i]), 5.0) for k, i in self.slots]
        )
        world = system.world
        self.gain_scale = HIP_GAIN_SCALE * world.mass() * GRAVITY * world.standing_com_height
        self.event_scale = EVENT_GAIN_SCALE * world.mass() * GRAVITY * world.standing_com_height
        self.hip0 = start.feedback.hip if start.feedback.hip is not None else np.zeros(8)
        self.event_modes = {ph: list(m) for ph, m in (event_modes or {}).items() if m}
        self.event0 = _starting_event_gains(start.feedback.event, self.event_modes)
        own = start.feedback.event
        self.event_speed = target_speed if target_speed is not None else (own.speed if own else 0)
        searched = not self.event_modes
        self.sizes = {
            "timing": 4 if searched else 0,
            "activations": len(self.slots),
            "hip": 8 if searched else 0,
            "event": sum(k.size for k in self.event0.values()),
        }
        self.size = sum(self.sizes.values())

    def decode(self, z: np.ndarray) -> GaitParameters:
        parts, at = {}, 0
        for name, n in self.sizes.items():
            parts[name] = np.asarray(z[at : at + n], dtype=float)
            at += n
        s = self.start
        activations = {k: v.copy() for k, v in s.activations.items()}
        for (key, i), scale, dz in zip(self.slots, self.psi_scale, parts["activations"]):
            activations[key][i] += scale * dz
        timing, hip, event = {}, self.hip0, s.feedback.event
        if self.sizes["timing"]:
            t = parts["timing"]
            timing = {
                "period": s.period * (1 + 0.2 * np.tanh(t[0])),
                "air_ratio": float(np.clip(s.air_ratio + 0.1 * np.tanh(t[1]), 0.02, 0.98)),
                "pulse_air": s.pulse_air * (1 + 0.3 * np.tanh(t[2])),
                "pulse_ground": s.pulse_ground * (1 + 0.3 * np.tanh(t[3])),
            }
            if self.bounds is not None:
                timing = {key: float(np.clip(v, *self.bounds[key])) for key, v in timing.items()}
            hip = self.hip0 + self.gain_scale * parts["hip"]
        if self.event_modes:
            phases, at = {}, 0
            for phase, K0 in self.event0.items():
                dK = parts["event"][at : at + K0.size].reshape(K0.shape)
                phases[phase] = (self.event_modes[phase], K0 + self.event_scale * dK)
                at += K0.size
            event = EventGains(speed=self.event_speed, phases=phases)
        return replace(
            s,
            **timing,
            activations=activations,
            feedback=FeedbackGains(hip=hip, modal=s.feedback.modal, event=event),
        )


def _starting_event_gains(
    own: EventGains | None, modes: dict[str, list[int]]
) -> dict[str, np.ndarray]:
    """phase -> (modes × 10) starting event gains: the gait's own on the modes it has, else 0."""
    start = {}
    for phase, numbers in modes.items():
        K = np.zeros((len(numbers), len(EVENT_FEATURES)))
        if own is not None and phase in own.phases:
            rows = dict(zip(own.phases[phase][0], own.phases[phase][1]))
            for r, m in enumerate(numbers):
                if m in rows:
                    K[r] = rows[m]
        start[phase] = K
    return start


def event_settings(sketch: Sketch) -> dict:
    """`SurvivalSettings` fields of an event search (`harden --event`): the sketch's priority and
    allowed modes per phase, its mean speed as the feedback's and the speed term's target, and no
    effort term (the starting gait's torque is no reference for one that is to reach another
    speed)."""
    modes = {
        phase: tuple(dict.fromkeys([*part.priority, *(part.allowed or [])]))
        for phase, part in (("air", sketch.air), ("ground", sketch.ground))
    }
    return {"event_modes": modes, "target_speed": sketch.targets.mean_speed, "effort_share": None}


def generation_pushes(
    settings: SurvivalSettings, generation: int, period: float, horizon: int, mass: float
):
    """The pushes of one generation: None for the undisturbed copy, then one `Push` per other
    copy."""
    rng = np.random.default_rng([settings.seed, generation % 2**32])
    pushes = [None]
    for _ in range(settings.copies - 1):
        impulse = rng.uniform(*settings.push_impulse) * rng.choice([-1.0, 1.0])
        at = rng.uniform(1.0, max(1.0, horizon - 3.0)) * period
        pushes.append(Push(time=float(at), force=float(impulse * mass / PUSH_SECONDS)))
    return pushes


class SurvivalScorer:
    """Plays a generation's candidates under its pushes and scores them (lower is better)."""

    def __init__(
        self,
        system: GaitSystem,
        start: GaitParameters,
        settings: SurvivalSettings,
        figures: StartingFigures | None,
    ):
        if figures is None and settings.reads_starting_figures:
            raise ValueError("these settings need the starting gait's StartingFigures")
        self.system, self.settings = system, settings
        self.runner = ClosedLoopRunner(system, settings.threads)
        self.dt = self.runner.model.opt.timestep
        self.mass = system.world.mass()
        target = settings.target_speed
        self.target_speed = max(
            settings.speed_share * figures.speed if target is None else target, 0.05
        )
        share = settings.effort_share
        self.target_effort = None if share is None else max(share * figures.effort, 1e-9)
        self.period = start.period
        model = system.world.model
        self.tilt = root_layout(model, int(model.jnt_bodyid[0]))

    def close(self) -> None:
        self.runner.close()

    def score(
        self, params: list[GaitParameters], generation: int, horizon: int, assist: float = 0.0
    ) -> tuple[np.ndarray, np.ndarray]:
        """(cost, mean cycles survived) per candidate, every play under a hand on the root at
        level `assist` (0: none)."""
        hand = RootAssist(self.system.world, assist) if assist > 0 else None
        dt = self.dt
        # each candidate's sensor row at (q₀, q̇₀), before its rollouts' first step
        firsts = [self.system.initial_sensors(p) for p in params]
        cycles = np.zeros((len(params), self.settings.copies))
        effort, slip = np.zeros_like(cycles), np.zeros_like(cycles)
        # the undisturbed copy's speed and its tilt and footfall terms
        speed, shape = np.zeros(len(params)), np.zeros(len(params))
        for c, push in enumerate(
            generation_pushes(self.settings, generation, self.period, horizon, self.mass)
        ):
            run = self.runner.run(params, horizon, () if push is None else (push,), hand)
            for i, p in enumerate(params):
                end = max(int(run.ended[i]), 1)
                cycles[i, c] = min(
                    len(run.cycle_ends[i]) + (end * dt % p.period) / p.period, horizon
                )
                effort[i, c] = np.mean(np.sum(run.torques[i, :end] ** 2, axis=1))
                if self.settings.max_slip is not None:
                    slip[i, c] = self._slip(firsts[i], run.sensors[i, : int(run.ended[i])])
                if push is None:
                    speed[i] = self._speed(p, run.sensors[i, :end])
                    shape[i] = self._shape(p, firsts[i], run.states[i, :end], run.sensors[i, :end])
        lag = np.clip(self.target_speed - speed, 0, None) / self.target_speed
        excess = (
            0.0
            if self.target_effort is None
            else np.clip(effort.mean(axis=1) / self.target_effort - 1, 0, None)
        )
        cost = (
            (1 - cycles.mean(axis=1) / horizon)
            + self.settings.speed_weight * lag
            + EFFORT_WEIGHT * excess
        )
        if self.settings.max_slip is not None:
            cost += SLIP_WEIGHT * np.clip(slip.mean(axis=1) / self.settings.max_slip - 1, 0, None)
        return cost + shape, cycles.mean(axis=1)

    def _speed(self, p: GaitParameters, sensors: np.ndarray) -> float:
        """Mean forward COM speed (m/s) of a rollout from the end of its first cycle (the launch
        from the initial state left out); 0 if it ends within that cycle."""
        first = int(round(p.period / self.dt))
        if len(sensors) <= first + 1:
            return 0.0
        com_x = self.system.world.view.com(sensors[[first, -1]])[:, 0]
        return float(com_x[1] - com_x[0]) / ((len(sensors) - 1 - first) * self.dt)

    def _shape(
        self, p: GaitParameters, first: np.ndarray, states: np.ndarray, sensors: np.ndarray
    ) -> float:
        """TILT_WEIGHT and PAIR_WEIGHT terms of one undisturbed rollout (0 when not asked); `first`
        its sensor row before its first step."""
        cost, settings, world = 0.0, self.settings, self.system.world
        if settings.max_tilt_deg is not None:
            pitch, roll = self.tilt.tilt_deg(world.view.qpos(states))
            tilt = float(np.max(np.abs(np.r_[pitch, roll])))
            cost += TILT_WEIGHT * max(0.0, tilt / settings.max_tilt_deg - 1)
        if settings.paired_feet:
            footfall = rollout_footfalls(
                world.view, first, sensors, self.dt, p.period, 2 * p.period
            )
            cost += PAIR_WEIGHT * footfall_pattern_cost(footfall, settings.paired_feet)
        return cost

    def _slip(self, first: np.ndarray, sensors: np.ndarray) -> float:
        """`stance_slip_max_m` (m; 0 without a stance) of a rollout's sensor rows, as playback
        measures it; `first` the sensor row before its first step."""
        per_foot = rollout_stance_slips(self.system.world.view, first, sensors, self.dt).values()
        slips = [float(v.mean()) for v in per_foot if v.size]
        return max(slips, default=0.0)


def footfall_pattern_cost(
    footfall: dict[str, float | None], pairs: tuple[tuple[str, str], ...]
) -> float:
    """How far (cycles) a footfall (foot -> touchdown phase) is from `pairs` landing together,
    beyond PAIR_TOLERANCE per pair, plus, for two pairs, how far the pairs are from half a cycle
    apart beyond it; PAIR_MISSING when a paired foot has no touchdown."""
    if any(footfall.get(foot) is None for pair in pairs for foot in pair):
        return PAIR_MISSING
    cost, centres = 0.0, []
    for a, b in pairs:
        cost += max(0.0, phase_distance(footfall[a], footfall[b]) - PAIR_TOLERANCE)
        centres.append(circular_mean_turn([footfall[a], footfall[b]]) % 1.0)
    if len(pairs) == 2:
        apart = phase_distance(*centres)
        cost += max(0.0, abs(0.5 - apart) - PAIR_TOLERANCE)
    return cost


def harden(
    system: GaitSystem,
    start: GaitParameters,
    figures: StartingFigures | None,
    folder: Path,
    settings: SurvivalSettings,
    resume: bool = False,
    name: str = "",
    progress=print,
    lookahead: LookaheadSettings | None = None,
    sketch: dict | None = None,
    timing: Timing | None = None,
) -> GaitParameters:
    """Run (or resume) the survival optimization in `folder`; returns the best controller, also
    saved there with the starting controller's `lookahead` settings and `sketch` modes. `figures`:
    the starting gait's, needed unless the settings fix the target speed and drop the effort term.
    `timing`: the sketch's, whose bounds the searched timing keeps."""
    folder.mkdir(parents=True, exist_ok=True)
    checkpoint = folder / CHECKPOINT
    bounds = timing_bounds(timing) if timing is not None else None
    settings = replace(settings, sketch_timing_bounds=bounds)
    history = _load_history(checkpoint, settings) if resume else []
    space = SurvivalSpace(system, start, bounds, settings.event_modes, settings.target_speed)
    scorer = SurvivalScorer(system, start, settings, figures)
    es = cma.CMAEvolutionStrategy(
        np.zeros(space.size),
        settings.sigma0,
        {"popsize": settings.popsize, "seed": settings.seed, "verbose": -9},
    )
    horizon, assist, best = settings.horizon, settings.assist or 0.0, None
    for record in history:  # replay: the same seed asks the same candidates
        es.ask()
        es.tell([np.array(z) for z in record["candidates"]], record["costs"])
        horizon, best = record["next_horizon"], record["best"]
        assist = record.get("next_assist", 0.0)
    spent = history[-1]["elapsed"] if history else 0.0
    t0 = time.perf_counter() - spent
    try:
        while time.perf_counter() - t0 < settings.minutes * 60 and len(history) < (
            settings.generations or 1 << 30
        ):
            zs = es.ask()
            decoded = [space.decode(z) for z in zs]
            costs, survived = scorer.score(decoded, es.countiter, horizon, assist)
            es.tell(zs, costs.tolist())
            k = int(np.argmin(costs))
            if best is None or _better(assist, horizon, costs[k], best):
                best = {
                    "cost": float(costs[k]),
                    "horizon": horizon,
                    "assist": assist,
                    "z": [float(v) for v in zs[k]],
                }
            next_horizon, next_assist = horizon, assist
            if np.median(survived) >= horizon - 0.5:
                if assist > 0:
                    weaker = assist * ASSIST_DECAY
                    next_assist = weaker if weaker >= ASSIST_FLOOR else 0.0
                else:
                    next_horizon = min(horizon + HORIZON_STEP, settings.max_horizon)
            history.append(
                {
                    "candidates": [[float(v) for v in z] for z in zs],
                    "costs": [float(c) for c in costs],
                    "next_horizon": next_horizon,
                    "next_assist": next_assist,
                    "best": best,
                    "elapsed": time.perf_counter() - t0,
                }
            )
            _save(checkpoint, settings, history)
            _log(folder / "log.csv", history)
            hand = f", hand {assist:.2f}" if assist else ""
            progress(
                f"generation {len(history)}: horizon {horizon} cycles{hand}, best survives "
                f"{survived[k]:.1f} (median {np.median(survived):.1f}), cost {costs[k]:.3f}, "
                f"{time.perf_counter() - t0:.0f} s"
            )
            horizon, assist = next_horizon, next_assist
        result = _validated(scorer, space, es, best, horizon) if best else start
    finally:
        scorer.close()
    save_controller(
        to_file(system, result, name, lookahead=lookahead, sketch=sketch),
        folder / "best_controller.json",
    )
    return result


def harden_event_in_stages(
    system: GaitSystem,
    start: GaitParameters,
    sketch: Sketch,
    folder: Path,
    minutes: float,
    seed: int = 1,
    threads: int = 1,
    name: str = "",
    sketch_modes: dict | None = None,
    progress=print,
) -> GaitParameters:
    """Search a gait's event feedback (`event_settings` of its `sketch`) in two stages, each a
    `harden` run in `folder`/stage1, stage2 (resumed if interrupted): for `EVENT_FIRST_SHARE` of
    `minutes` survival, speed and tilt (`MAX_TILT_DEG`) alone (a gait must move before its feet can
    be placed), then, from its result, also the stance slip (`MAX_SLIP_M`) and the sketch's paired
    feet. Returns the second stage's result, also saved as folder/stage2/best_controller.json
    (without lookahead)."""
    common = {
        "seed": seed,
        "popsize": EVENT_POPSIZE,
        "threads": threads,
        "max_tilt_deg": MAX_TILT_DEG,
        **event_settings(sketch),
    }
    stages = (
        SurvivalSettings(minutes=EVENT_FIRST_SHARE * minutes, max_slip=None, **common),
        SurvivalSettings(
            minutes=(1 - EVENT_FIRST_SHARE) * minutes,
            max_slip=MAX_SLIP_M,
            paired_feet=tuple(tuple(pair) for pair in sketch.targets.paired_feet),
            **common,
        ),
    )
    for number, settings in enumerate(stages, 1):
        stage = folder / f"stage{number}"
        start = harden(
            system,
            start,
            None,  # the event settings fix the target speed and have no effort term
            stage,
            settings,
            (stage / CHECKPOINT).exists(),
            name,
            progress,
            sketch=sketch_modes,
            timing=sketch.timing,
        )
    return start


def _better(assist: float, horizon: int, cost: float, best: dict) -> bool:
    """Whether a candidate of `cost`, scored at `horizon` under a hand at level `assist`, beats the
    `best` so far: a weaker hand first, then a longer horizon, then a lower cost."""
    key = (assist, -horizon, cost)
    return key < (best.get("assist", 0.0), -best["horizon"], best["cost"])


def _validated(
    scorer: SurvivalScorer, space: SurvivalSpace, es, best: dict, horizon: int
) -> GaitParameters:
    """The better of the best candidate seen and the search's mean, on pushes no generation has
    met."""
    choices = [np.array(best["z"]), np.asarray(es.mean)]
    costs, _ = scorer.score([space.decode(z) for z in choices], VALIDATION_GENERATION, horizon)
    return space.decode(choices[int(np.argmin(costs))])


def _save(path: Path, settings: SurvivalSettings, history: list[dict]) -> None:
    write_atomically(path, json.dumps({"settings": asdict(settings), "generations": history}))


def _load_history(path: Path, settings: SurvivalSettings) -> list[dict]:
    if not path.is_file():
        raise UserInputError(
            "no survival run to resume here", file=path, fix="start the run without resume=True"
        )
    try:
        data = json.loads(path.read_text())
        saved = data["settings"]
        history = data["generations"]
    except (ValueError, KeyError, TypeError):
        raise UserInputError(
            "cannot read the checkpoint", file=path, fix="start over without resume=True"
        ) from None
    mine = {
        k: v for k, v in asdict(settings).items() if k not in ("minutes", "generations", "threads")
    }
    # a setting added since the run was saved reads as its default
    defaults = {f.name: f.default for f in fields(SurvivalSettings) if f.name in mine}
    theirs = {**defaults, **{k: _tuples(v) for k, v in saved.items() if k in mine}}
    if theirs != mine:
        changed = ", ".join(k for k in mine if theirs.get(k) != mine[k])
        raise UserInputError(
            f"the run was started with other settings ({changed})",
            file=path,
            fix="resume with the same options",
        )
    return history


def _log(path: Path, history: list[dict]) -> None:
    rows = ["generation,horizon,best_cost,generation_best_cost,seconds"]
    for g, h in enumerate(history, 1):
        rows.append(
            f"{g},{h['best']['horizon']},{h['best']['cost']:.6f},{min(h['costs']):.6f},{h['elapsed']:.1f}"
        )
    write_atomically(path, "\n".join(rows) + "\n")


def _tuples(value):
    """JSON lists (also inside dicts) back to the tuples the settings hold."""
    if isinstance(value, dict):
        return {k: _tuples(v) for k, v in value.items()}
    return tuple(_tuples(v) for v in value) if isinstance(value, list) else value
