"""Evaluate a CMA-ES population as one batch: stepping in C (`mujoco.rollout`, threads), objectives from the
recorded states and sensors, and early termination of candidates that fall.

Every candidate is simulated for one whole cycle T, so soft constraints and falls cover all that playback
repeats; the cyclic constraint is read at T/2 (mirrored) for symmetric bipeds, as in the thesis, else at T.

The horizon is split into chunks; after each chunk, fallen candidates (COM below half its initial height or the
root upside down) are dropped and the survivors continue from their last state. A fallen candidate's soft
penalty grows with the share of the horizon it did not survive, so falls still rank.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import mujoco
import numpy as np
from mujoco import rollout

from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.control.sketch import Targets
from eigengait.optimize import terms
from eigengait.optimize.parameters import ParameterSpace

FALL_PENALTY = 100.0   # soft-constraint units for a fall at t = 0, scaled by the unsurvived share of the horizon


@dataclass
class Outcome:
    """The result of one candidate. `cost` = w_p·E_vel·E_energia + w_r·Σ soft; `cycle` = φ (hard constraint)."""
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
    """Simulates candidates of a parameter space over the cyclic-constraint horizon."""

    def __init__(self, system: GaitSystem, space: ParameterSpace, targets: Targets, threads: int | None = None,
                 chunks: int = 4, sample_dt: float = 0.01):
        self.system, self.space, self.targets = system, space, targets
        self.model = system.world.model
        self.threads = threads or default_threads()
        self.datas = [mujoco.MjData(self.model) for _ in range(self.threads)]
        self.chunks, self.dt = chunks, self.model.opt.timestep
        self.sample_every = max(1, int(round(sample_dt / self.dt)))
        self.nq, self.nv = self.model.nq, self.model.nv
        world = system.world
        self.standing_com = world.new_data().subtree_com[world.root_body][2]
        self.toe_radius = {f: float(self.model.geom_size[world.foot_spheres[f][0], 0]) for f in system.feet}
        self.toe_sensor = {f: world.foot_sensor[world.character.feet[f].toe] for f in system.feet}
        self.steps_simulated = 0

    def close(self) -> None:
        rollout.shutdown_persistent_pool()

    def horizon_steps(self, p: GaitParameters) -> int:
        """A whole cycle is simulated: what playback repeats must hold up for all of it."""
        return max(1, int(round(p.period / self.dt)))

    def cycle_step(self, p: GaitParameters) -> int:
        """The step whose state the cyclic constraint compares: T/2 (mirrored) for symmetric gaits, else T."""
        return max(1, int(round(self.system.horizon_fraction * p.period / self.dt)))

    def simulate(self, params: list[GaitParameters]):
        """Batched rollout with early termination: (states P×N×nstate, sensors P×N×ns, steps P, fell P)."""
        P = len(params)
        steps = np.array([self.horizon_steps(p) for p in params])
        N = int(steps.max())
        controls = np.zeros((P, N, self.model.nu))
        for i, p in enumerate(params):
            u = self.system.controls(p, span=steps[i] * self.dt)
            controls[i, :len(u)] = u[:N]
        state = np.stack([self.system.initial_state(p) for p in params])
        states = np.zeros((P, N, state.shape[1]))
        sensors = np.zeros((P, N, self.model.nsensordata))
        ended = steps.copy()
        fell = np.zeros(P, bool)
        alive = np.ones(P, bool)
        bounds = np.linspace(0, N, self.chunks + 1).astype(int)
        for a, b in zip(bounds[:-1], bounds[1:]):
            idx = np.flatnonzero(alive)
            if idx.size == 0 or b <= a:
                continue
            s, d = rollout.rollout(self.model, self.datas, state[idx], controls[idx, a:b], persistent_pool=True)
            states[idx, a:b], sensors[idx, a:b] = s, d
            self.steps_simulated += idx.size * (b - a)
            state[idx] = s[:, -1]
            for k, i in enumerate(idx):
                upto = min(b, steps[i]) - a
                com_z = d[k, :upto, 2]
                up_z = self.system.world.root.up_z(s[k, :upto, 1:1 + self.nq])
                bad = np.flatnonzero((com_z < 0.5 * self.standing_com) | (up_z < 0) |
                                     ~np.isfinite(s[k, :upto, 1:1 + self.nq + self.nv]).all(axis=1))
                if bad.size:
                    fell[i], ended[i], alive[i] = True, a + bad[0] + 1, False
                elif steps[i] <= b:
                    alive[i] = False
        return states, sensors, ended, fell, controls, steps

    def evaluate(self, X: np.ndarray) -> list[Outcome]:
        params = [self.space.decode(x) for x in np.atleast_2d(X)]
        states, sensors, ended, fell, controls, steps = self.simulate(params)
        return [self._outcome(p, states[i, :ended[i]], sensors[i, :ended[i]], controls[i, :ended[i]],
                              fell[i], ended[i] / steps[i]) for i, p in enumerate(params)]

    # ------------------------------------------------------------------ objective of one candidate
    def _outcome(self, p: GaitParameters, states, sensors, controls, fell: bool, survived: float) -> Outcome:
        tg, nq, nv = self.targets, self.nq, self.nv
        n_motor = self.system.world.nmotor
        samples = slice(self.sample_every - 1, None, self.sample_every)
        com, comvel = sensors[:, 0:3], sensors[:, 3:6]
        duration = len(states) * self.dt
        mean_vel = (com[-1] - self.system.initial_com(p)) / duration
        energy = terms.energy_objective(controls[:, :n_motor]) if len(controls) else 0.0
        qvel = states[samples, 1 + nq:1 + nq + nv]
        soft = {
            "min_speed": terms.min_speed_term(comvel[samples, 0], tg.min_speed),
            "mean_speed": terms.mean_speed_term(mean_vel, tg.mean_speed, tg.lateral_speed, tg.vertical_speed),
            "joint_speed": terms.joint_speed_term(qvel[:, self.system.world.internal_qvel], tg.joint_speed),
            "energy_max": terms.energy_limit_term(energy, tg.energy),
            "priority": terms.priority_term(self._priority_split(p)),
            "upright": terms.upright_term(self.system.world.root.up_z(states[samples, 1:1 + nq])),
        }
        soft["stance_contact"], soft["stance_rise"] = self._stance_terms(p, sensors)
        if fell:
            soft["fall"] = FALL_PENALTY * (2.0 - survived)
            cycle = np.full(2 * nv - 1, 10.0)
        else:
            k = min(self.cycle_step(p), len(states)) - 1
            cycle = self.system.cycle_error(p, states[k, 1:1 + nq], states[k, 1 + nq:1 + nq + nv])
        cost = (terms.OBJECTIVE_WEIGHT * terms.speed_objective(mean_vel[0]) * energy
                + terms.SOFT_WEIGHT * sum(soft.values()))
        return Outcome(cost=float(cost), cycle=cycle, fell=bool(fell), mean_velocity=mean_vel, energy=energy,
                       soft=soft)

    def _priority_split(self, p: GaitParameters) -> list[tuple[np.ndarray, np.ndarray]]:
        out = []
        for (foot, phase), psi in p.activations.items():
            prio = np.zeros(len(psi), bool)
            prio[[m - 1 for m in self.space.sketch.phase(phase).priority]] = True
            out.append((psi[prio], psi[~prio]))
        return out

    def _stance_terms(self, p: GaitParameters, sensors) -> tuple[float, float]:
        contact = rise = 0.0
        n = len(sensors)
        for s in self.system.states(p):
            if s.phase != "ground":
                continue
            a = int(s.start / self.dt)
            if a >= n:
                continue
            z = sensors[a:min(n, int((s.start + s.duration) / self.dt)), self.toe_sensor[s.foot] + 2]
            clearance = z - self.toe_radius[s.foot]
            window = max(1, int(s.pulse / 2 / self.dt))
            contact += terms.stance_contact_term(clearance[:window])
            rise += terms.stance_rise_term(z)
        return contact, rise
