"""Simulation health: NaN, runaway velocity or a control MuJoCo would refuse is a blow-up, reported with the
time and the body (`SimulationBlowUp`, exit status 2 on the command line)."""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.errors import SimulationBlowUp
from eigengait.sim.world import World

MAX_SPEED = 500.0  # rad/s or m/s on any dof: beyond this the simulation is considered to have blown up
MAX_CONTROL = 1e9  # N·m: MuJoCo resets the simulation on controls beyond ~1e10, hiding the blow-up


def first_blow_up(
    qvel: np.ndarray,
    motor_torques: np.ndarray,
    motor_dofs: np.ndarray,
    times: np.ndarray | None = None,
    dt: float = 0.0,
) -> tuple[int, int] | None:
    """(step, dof) of the first blow-up in a recording (steps × nv velocities, steps × motors torques), or None.

    A torque that is not finite or beyond `MAX_CONTROL` counts at its step, on its motor's dof. With `times`
    (s: before the first step, then after each) a clock that does not advance by `dt` means MuJoCo reset the
    diverged simulation; the dof is then the fastest one just before the reset."""
    bad_v = ~np.isfinite(qvel) | (np.abs(qvel) > MAX_SPEED)
    bad_u = ~np.isfinite(motor_torques) | (np.abs(motor_torques) > MAX_CONTROL)
    reset = np.zeros(len(qvel), bool)
    if times is not None:
        reset = np.diff(times) < 0.5 * dt
    rows = np.flatnonzero(bad_v.any(axis=1) | bad_u.any(axis=1) | reset)
    if rows.size == 0:
        return None
    k = int(rows[0])
    if bad_u[k].any():
        return k, int(motor_dofs[np.argmax(bad_u[k])])
    if bad_v[k].any():
        return k, int(np.argmax(bad_v[k]))
    return k, int(np.argmax(np.abs(qvel[max(k - 1, 0)])))


def raise_blow_up(world: World, time: float, dof: int, file: str | None = None) -> None:
    """Raise `SimulationBlowUp` naming the time (s) and the body that owns `dof`; `file` is the user's file at
    fault (default: the character)."""
    body = world.model.body(int(world.model.dof_bodyid[dof])).name
    raise SimulationBlowUp(
        f"the simulation blew up at t = {time:.4f} s (body '{body}' reached NaN, a runaway "
        f"speed or an impossible torque)",
        file=str(file or world.character.path),
        field=f"body '{body}'",
        fix="reduce the time step, the torques, the initial speeds or the joint stiffness",
    )


def step(world: World, data: mujoco.MjData, nstep: int = 1, model: mujoco.MjModel | None = None) -> None:
    """Advance `nstep` physics steps in C, then check the state. `model`: the model `data` belongs to, when it is
    an edited copy of the world's."""
    warnings_before = int(data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number)
    mujoco.mj_step(model or world.model, data, nstep)
    found = first_blow_up(data.qvel[None], np.zeros((1, 0)), np.zeros(0, int))
    dof = None if found is None else found[1]
    if int(data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number) > warnings_before and dof is None:
        dof = int(np.argmax(np.abs(data.qacc))) if data.qacc.size else 0
    if dof is not None:
        raise_blow_up(world, float(data.time), dof)
