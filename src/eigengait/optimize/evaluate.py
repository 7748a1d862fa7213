"""Evaluate a CMA-ES population as one batch of closed-loop rollouts over several cycles, with no
reset.

Every candidate is simulated for `cycles` consecutive cycles (`control/closed_loop.py`: stepping in
C, feedback for the whole batch in NumPy between chunks; fallen candidates are dropped early). The
hard cyclic constraint φ holds at every cycle end: the state at the end of cycle k against the state
at its start (root x excluded), and for symmetric gaits also the mirrored state at T/2 of the first
cycle against (q₀, q̇₀), the thesis's choice. A fallen candidate's soft penalty grows with the share
of the horizon it did not survive, so falls still rank; a candidate that blows up gets the worst
fall's penalty and finite values only.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import mujoco
import numpy as np

from eigengait.control.activations import mode_indices
from eigengait.control.closed_loop import BatchRun, ClosedLoopRunner, cycle_errors
from eigengait.control.feedback import leg_root_joint
from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.control.gait_metrics import rollout_stance_slips
from eigengait.control.sketch import Targets
from eigengait.errors import UserInputError
from eigengait.optimize import terms
from eigengait.optimize.parameters import ParameterSpace

# soft-constraint units for a fall at t = 0, scaled by the unsurvived share of the horizon
FALL_PENALTY = 100.0
FALLEN_CYCLE_ERROR = 10.0


@dataclass
class Outcome:
    """The result of one candidate. `cost` = w_p·E_vel·E_energia + w_r·Σ soft; `cycle` = φ (hard
    constraint)."""

    cost: float
    cycle: np.ndarray
    fell: bool
    mean_velocity: np.ndarray
    energy: float
    soft: dict[str, float] = field(default_factory=dict)

    @property
    def violation(self) -> float:
        return float(np.abs(self.cycle).max())


def default_threads() -> int:
    return max(1, len(os.sched_getaffinity(0)))


class BatchEvaluator:
    """Simulates candidates of a parameter space for `cycles` cycles and scores them."""

    def __init__(
        self,
        system: GaitSystem,
        space: ParameterSpace,
        targets: Targets,
        threads: int | None = None,
        cycles: int = 5,
        sample_dt: float = 0.01,
    ):
        self.system, self.space, self.targets, self.cycles = system, space, targets, cycles
        self.model = system.world.model
        self.threads = threads or default_threads()
        self.runner = ClosedLoopRunner(system, self.threads)
        self.dt = self.model.opt.timestep
        self.sample_every = max(1, int(round(sample_dt / self.dt)))
        self.nv = self.model.nv
        world = system.world
        self.view = world.view
        self.hip_joint = {
            f: self.model.joint(leg_root_joint(world, f)).id for f in dict.fromkeys(system.feet)
        }
        self.kinematics = mujoco.MjData(self.model)
        for pair in targets.paired_feet:
            for foot in pair:
                if foot not in world.character.feet:
                    raise UserInputError(
                        f"paired foot '{foot}' is not a foot of '{world.character.name}'",
                        file=system.source,
                        field="targets.paired_feet",
                        fix=f"pair feet among: {', '.join(world.character.feet)}",
                    )

    @property
    def steps_simulated(self) -> int:
        return self.runner.steps_simulated

    @steps_simulated.setter
    def steps_simulated(self, value: int) -> None:
        self.runner.steps_simulated = value

    def close(self) -> None:
        self.runner.close()

    def simulate(self, params: list[GaitParameters]) -> BatchRun:
        return self.runner.run(params, self.cycles)

    def evaluate(self, X: np.ndarray) -> list[Outcome]:
        params = [self.space.decode(x) for x in np.atleast_2d(X)]
        run = self.simulate(params)
        return [self._outcome(p, run, i) for i, p in enumerate(params)]

    # ------------------------------------------------------------------ objective of one candidate
    def _outcome(self, p: GaitParameters, run: BatchRun, i: int) -> Outcome:
        if run.blow_up[i] is not None:
            return Outcome(
                cost=2 * terms.SOFT_WEIGHT * FALL_PENALTY,
                fell=True,
                mean_velocity=np.zeros(3),
                cycle=np.full(self.constraint_size, FALLEN_CYCLE_ERROR),
                energy=0.0,
                soft={"fall": 2 * FALL_PENALTY},
            )
        tg, view = self.targets, self.view
        end = int(run.ended[i])
        states, sensors, torques = run.states[i, :end], run.sensors[i, :end], run.torques[i, :end]
        samples = slice(self.sample_every - 1, None, self.sample_every)
        comvel = view.com_velocity(sensors)
        mean_vel = (view.com(sensors[-1]) - self.system.initial_com(p)) / (end * self.dt)
        energy = terms.energy_objective(torques) if end else 0.0
        qvel = view.qvel(states[samples])
        soft = {
            "min_speed": terms.min_speed_term(comvel[samples, 0], tg.min_speed),
            "mean_speed": terms.mean_speed_term(
                mean_vel, tg.mean_speed, tg.lateral_speed, tg.vertical_speed
            ),
            "joint_speed": terms.joint_speed_term(
                qvel[:, self.system.world.internal_qvel], tg.joint_speed
            ),
            "energy_max": terms.energy_limit_term(energy, tg.energy),
            "priority": terms.priority_term(self._priority_split(p)),
            "upright": terms.upright_term(view.up_z(states[samples])),
            **self._stance_terms(p, states, sensors),
        }
        if tg.stance_slip is not None:
            slips = rollout_stance_slips(
                view, self.system.initial_sensors(p), sensors, self.dt
            ).values()
            soft["stance_slip"] = terms.stance_slip_term(
                np.concatenate(list(slips)), tg.stance_slip
            )
        if tg.paired_feet:
            soft["paired_feet"] = self._paired_term(p, sensors[samples])
        if run.fell[i]:
            soft["fall"] = FALL_PENALTY * (2.0 - end / run.steps[i])
        # fallen, or touchdowns too late to finish
        if run.fell[i] or len(run.cycle_ends[i]) < self.cycles:
            cycle = np.full(self.constraint_size, FALLEN_CYCLE_ERROR)
        else:
            cycle = cycle_errors(self.system, p, run.states[i], self.cycles, run.cycle_ends[i])
        cost = terms.OBJECTIVE_WEIGHT * terms.speed_objective(
            mean_vel[0]
        ) * energy + terms.SOFT_WEIGHT * sum(soft.values())
        return Outcome(
            cost=float(cost),
            cycle=cycle,
            fell=bool(run.fell[i]),
            mean_velocity=mean_vel,
            energy=energy,
            soft=soft,
        )

    def _paired_term(self, p: GaitParameters, sampled_sensors: np.ndarray) -> float:
        """`targets.paired_feet`'s term over the played cycles (the last one may be partial), from
        sensors sampled every `sample_every` steps."""
        touching = self.view.feet_touching(sampled_sensors)
        per_cycle = p.period / (self.sample_every * self.dt)
        cycles = max(1, int(round(len(sampled_sensors) / per_cycle)))
        total = 0.0
        for a, b in self.targets.paired_feet:
            apart = touching[a] != touching[b]
            shares = [part.mean() for part in np.array_split(apart, cycles) if part.size]
            total += terms.paired_contact_term(np.array(shares), self.targets.pair_tolerance)
        return total

    @property
    def constraint_size(self) -> int:
        blocks = self.cycles + (1 if self.system.mirror is not None else 0)
        return blocks * (2 * self.nv - 1)

    def _priority_split(self, p: GaitParameters) -> list[tuple[np.ndarray, np.ndarray]]:
        out = []
        for (foot, phase), psi in p.activations.items():
            prio = np.zeros(len(psi), bool)
            prio[mode_indices(self.space.sketch.phase(phase).priority)] = True
            out.append((psi[prio], psi[~prio]))
        return out

    # ---------------------------------------------------------------- stance terms (Eqs. 4.17–4.20)
    def _hips(self, states: np.ndarray) -> dict[str, np.ndarray]:
        """World hip-anchor positions (n × 3) per leg, from forward kinematics of the recorded
        states."""
        model, data = self.model, self.kinematics
        out = {f: np.empty((len(states), 3)) for f in self.hip_joint}
        for k, row in enumerate(states):
            data.qpos[:] = self.view.qpos(row)
            mujoco.mj_kinematics(model, data)
            for f, j in self.hip_joint.items():
                out[f][k] = data.xanchor[j]
        return out

    def _stance_terms(
        self, p: GaitParameters, states: np.ndarray, sensors: np.ndarray
    ) -> dict[str, float]:
        out = {"stance_contact": 0.0, "stance_rise": 0.0, "anti_stumble": 0.0}
        n, dt, view = len(sensors), self.dt, self.view
        schedule = self.system.states(p)
        distinct = list(dict.fromkeys(self.system.feet))
        for c in range(self.cycles):
            offset = c * p.period
            for k, s in enumerate(schedule):
                if s.phase != "ground":
                    continue
                a, b = (
                    int((offset + s.start) / dt),
                    min(n, int((offset + s.start + s.duration) / dt)),
                )
                if a >= n:
                    continue
                clearance = view.toe(sensors[a:b], s.foot)[:, 2] - view.foot_radius[s.foot]
                out["stance_contact"] += terms.stance_contact_term(
                    clearance[: max(1, int(s.pulse / 2 / dt))]
                )
                air = schedule[k - 1]
                w0 = int((offset + air.start) / dt)
                after = schedule[(k + 1) % len(schedule)]
                w1 = min(n, int((offset + s.start + s.duration + after.duration) / dt))
                if view.has_heel(s.foot) and w1 > w0:
                    window = sensors[w0:w1]
                    toe_z, heel_z = view.toe(window, s.foot)[:, 2], view.heel(window, s.foot)[:, 2]
                    rise = terms.push_off_rise(view.com_velocity(window)[:, 2], toe_z, heel_z, dt)
                    out["stance_rise"] += terms.stance_rise_term(rise)
                if len(distinct) == 2:
                    other = distinct[1] if s.foot == distinct[0] else distinct[0]
                    rows = np.arange(a, b, self.sample_every)
                    touching = rows[clearance[rows - a] < 0.01]
                    if touching.size:
                        hips = self._hips(states[touching])
                        out["anti_stumble"] += terms.anti_stumble_term(
                            self._toe_to_hip(sensors[touching], hips, s.foot),
                            self._toe_to_hip(sensors[touching], hips, other),
                        )
        return out

    def _toe_to_hip(
        self, sensors: np.ndarray, hips: dict[str, np.ndarray], foot: str
    ) -> np.ndarray:
        toe = self.view.toe(sensors, foot)
        return np.linalg.norm(toe - hips[foot], axis=1)
