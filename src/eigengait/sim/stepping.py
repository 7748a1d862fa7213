"""Stepping with a blow-up check: NaN or runaway velocity raises an error naming the time and the body."""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.errors import SimulationBlowUp
from eigengait.sim.world import World

MAX_SPEED = 500.0  # rad/s or m/s on any dof: beyond this the simulation is considered to have blown up


def blown_up_dof(qvel: np.ndarray) -> int | None:
    """Index of the first non-finite or runaway velocity, or None."""
    bad = ~np.isfinite(qvel) | (np.abs(qvel) > MAX_SPEED)
    return int(np.argmax(bad)) if bad.any() else None


def raise_blow_up(world: World, time: float, dof: int) -> None:
    body = world.model.body(int(world.model.dof_bodyid[dof])).name
    raise SimulationBlowUp(f"the simulation blew up at t = {time:.4f} s (body '{body}' reached NaN or runaway speed)",
                           file=str(world.character.path), field=f"body '{body}'",
                           fix="reduce the time step, the torques or the joint stiffness")


def step(world: World, data: mujoco.MjData, nstep: int = 1) -> None:
    """Advance `nstep` physics steps in C, then check the state."""
    warnings_before = int(data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number)
    mujoco.mj_step(world.model, data, nstep)
    dof = blown_up_dof(data.qvel)
    if int(data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number) > warnings_before and dof is None:
        dof = int(np.argmax(np.abs(data.qacc))) if data.qacc.size else 0
    if dof is not None:
        raise_blow_up(world, float(data.time), dof)
