"""Play a pulse controller on the ground with gravity, cycle by cycle.

By default the state is snapped back to (q₀, q̇₀) at each cycle end, all but the root's forward position (the
thesis's "simple and effective, but physically incorrect" choice); `snap=False` lets the gait run on its own and
reports how many cycles it survives. Each cycle is stepped in C with `mujoco.rollout`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np
from mujoco import rollout

from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.sim.world import GRAVITY


@dataclass
class PlaybackResult:
    qpos: np.ndarray                 # (frames × nq) at `fps`
    fps: float
    cycles_completed: int
    fell: bool
    mean_speed_mps: float            # forward COM speed over the played time
    active_energy: float             # J: positive mechanical work of the active torques, Σ max(τ·q̇, 0) dt
    mean_squared_torque: float       # (N·m)²: the thesis's E_energia, mean over steps of Σ_j τ_j²
    cost_of_transport: float         # active_energy / (m g distance), dimensionless
    cycle_violation: float           # max |φ_i| of the cyclic constraint after the first (half) cycle
    snapped: bool = True
    events: list[str] = field(default_factory=list)

    def summary(self) -> dict:
        return {"cycles_completed": self.cycles_completed, "fell": self.fell,
                "mean_speed_mps": round(float(self.mean_speed_mps), 4), "active_energy": round(self.active_energy, 3),
                "mean_squared_torque": round(float(self.mean_squared_torque), 3),
                "cost_of_transport": round(self.cost_of_transport, 4),
                "cycle_violation": round(self.cycle_violation, 5), "snap": self.snapped}


def play(system: GaitSystem, p: GaitParameters, cycles: int = 4, snap: bool = True, fps: float = 60.0) -> PlaybackResult:
    model, world = system.world.model, system.world
    data = mujoco.MjData(model)
    dt = model.opt.timestep
    u = system.controls(p, cycles=1)
    n = len(u)
    stride = max(1, int(round(1 / (fps * dt))))
    nq, nv = model.nq, model.nv
    standing = world.new_data().subtree_com[world.root_body][2]
    state = system.initial_state(p)
    frames, work, sq, steps = [], 0.0, 0.0, 0
    fell, completed = False, 0
    half = int(round(system.horizon_fraction * n))
    violation = np.nan
    com_start = system.initial_com(p)
    motor = slice(0, world.nmotor)
    for cycle in range(cycles):
        states, sensors = rollout.rollout(model, [data], state[None], u[None])
        states, sensors = states[0], sensors[0]
        qvel = states[:, 1 + nq:1 + nq + nv]
        quat = states[:, 4:8]
        up_z = 1 - 2 * (quat[:, 1] ** 2 + quat[:, 2] ** 2)
        bad = np.flatnonzero((sensors[:, 2] < 0.5 * standing) | (up_z < 0) | ~np.isfinite(states).all(axis=1))
        end = bad[0] + 1 if bad.size else n
        tau = u[:end, motor]
        work += float(np.sum(np.clip(np.sum(tau * qvel[:end][:, world.internal_qvel], axis=1), 0, None)) * dt)
        sq += float(np.sum(tau ** 2))
        steps += end
        frames.append(states[stride - 1:end:stride, 1:1 + nq])
        com_end = sensors[end - 1, 0:3]
        if cycle == 0:
            violation = float(np.abs(system.cycle_error(p, states[half - 1, 1:1 + nq],
                                                         states[half - 1, 1 + nq:1 + nq + nv])).max())
        if bad.size:
            fell = True
            break
        completed += 1
        state = states[-1].copy()
        if snap:
            x = 1 + world.root.forward_qpos       # state = (time, qpos, qvel, ...)
            snapped = system.initial_state(p)
            snapped[0], snapped[x] = state[0], state[x]
            state = snapped
    qpos = np.concatenate(frames) if frames else np.zeros((0, nq))
    duration = steps * dt
    distance = float(com_end[0] - com_start[0])
    mass = world.mass()
    return PlaybackResult(qpos=qpos, fps=1 / (stride * dt), cycles_completed=completed, fell=fell,
                          mean_speed_mps=distance / duration if duration else 0.0, active_energy=work,
                          mean_squared_torque=sq / max(steps, 1),
                          cost_of_transport=work / (mass * GRAVITY * distance) if distance > 1e-6 else float("inf"),
                          cycle_violation=violation, snapped=snap)
