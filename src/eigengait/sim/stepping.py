"""Simulation health: NaN, runaway velocity or a control MuJoCo would refuse is a blow-up, reported
with the time and the body (`SimulationBlowUp`, exit status 2 on the command line)."""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.errors import SimulationBlowUp
from eigengait.sim.world import World

# rad/s or m/s on any dof: beyond this the simulation is considered to have blown up
MAX_SPEED = 500.0
MAX_CONTROL = 1e9  # N·m: MuJoCo resets the simulation on controls beyond ~1e10, hiding the blow-up


def blown_up_steps(
    qvel: np.ndarray, times: np.ndarray | None = None, dt: float = 0.0
) -> np.ndarray:
    """Which steps blew up (bool, qvel's shape without its last axis): a velocity that is not finite
    or beyond `MAX_SPEED`, or, given `times` (s: before the first step, then after each, on the last
    axis), a clock that does not advance by `dt`, which is how MuJoCo's silent reset of a diverged
    simulation shows."""
    bad = (~np.isfinite(qvel) | (np.abs(qvel) > MAX_SPEED)).any(axis=-1)
    if times is not None:
        bad |= np.diff(times, axis=-1) < 0.5 * dt
    return bad


def blown_up_dof(qvel: np.ndarray, step: int) -> int:
    """The dof to blame at a blown-up `step` of a recording (steps × nv): its first non-finite or
    runaway velocity, else (a reset) the fastest dof one step earlier."""
    bad = ~np.isfinite(qvel[step]) | (np.abs(qvel[step]) > MAX_SPEED)
    return int(np.argmax(bad)) if bad.any() else int(np.argmax(np.abs(qvel[max(step - 1, 0)])))


def first_bad_torque(torques: np.ndarray, motor_dofs: np.ndarray) -> tuple[int, int] | None:
    """(step, dof) of the first torque (steps × motors, N·m) that is not finite or beyond
    `MAX_CONTROL`, or None; `motor_dofs[i]` is motor i's dof."""
    bad = ~np.isfinite(torques) | (np.abs(torques) > MAX_CONTROL)
    rows = np.flatnonzero(bad.any(axis=1))
    return None if rows.size == 0 else (int(rows[0]), int(motor_dofs[np.argmax(bad[rows[0]])]))


def raise_blow_up(world: World, time: float, dof: int, file: str | None = None) -> None:
    """Raise `SimulationBlowUp` naming the time (s) and the body that owns `dof`; `file` is the
    user's file at fault (default: the character)."""
    body = world.model.body(int(world.model.dof_bodyid[dof])).name
    raise SimulationBlowUp(
        f"the simulation blew up at t = {time:.4f} s (body '{body}' reached NaN, a runaway "
        f"speed or an impossible torque)",
        file=str(file or world.character.path),
        field=f"body '{body}'",
        fix="reduce the time step, the torques, the initial speeds or the joint stiffness",
    )


_BAD_STATE_WARNINGS = (
    mujoco.mjtWarning.mjWARN_BADQACC,
    mujoco.mjtWarning.mjWARN_BADQVEL,
    mujoco.mjtWarning.mjWARN_BADQPOS,
    mujoco.mjtWarning.mjWARN_BADCTRL,
)  # MuJoCo warns and resets the state (a bad position, velocity, acceleration) or drops the control


def _warning_counts(data: mujoco.MjData) -> list[int]:
    return [int(data.warning[w].number) for w in _BAD_STATE_WARNINGS]


def _warned_dof(model: mujoco.MjModel, data: mujoco.MjData, before: list[int]) -> int | None:
    """The dof to blame for a bad state MuJoCo warned of during the last steps, given the warning
    counts `before` them (None: no new warning): a bad control's actuator's joint, else the
    fastest-accelerating dof."""
    grown = [w for w, n in zip(_BAD_STATE_WARNINGS, before) if int(data.warning[w].number) > n]
    if not grown:
        return None
    if grown == [mujoco.mjtWarning.mjWARN_BADCTRL]:
        actuator = int(data.warning[mujoco.mjtWarning.mjWARN_BADCTRL].lastinfo)
        if (
            0 <= actuator < model.nu
            and model.actuator_trntype[actuator] == mujoco.mjtTrn.mjTRN_JOINT
        ):
            return int(model.jnt_dofadr[model.actuator_trnid[actuator, 0]])
    return int(np.argmax(np.abs(data.qacc))) if data.qacc.size else 0


def step(
    world: World, data: mujoco.MjData, nstep: int = 1, model: mujoco.MjModel | None = None
) -> None:
    """Advance `nstep` physics steps in C, then check the state. `model`: the model `data` belongs
    to, when it is an edited copy of the world's. A NaN or huge acceleration, velocity, position or
    control, which MuJoCo only warns of (resetting the state or dropping the control), is a blow-up
    too, reported at the time these steps started from when the reset restarted the clock."""
    model = model or world.model
    before, start = _warning_counts(data), float(data.time)
    mujoco.mj_step(model, data, nstep)
    dof = blown_up_dof(data.qvel[None], 0) if blown_up_steps(data.qvel) else None
    if dof is None:
        dof = _warned_dof(model, data, before)
    if dof is not None:
        raise_blow_up(world, max(float(data.time), start), dof)
