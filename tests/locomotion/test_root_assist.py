"""The hand on the root that hardening can start a falling gait under: its forces against values
worked by hand, and what it does to a gait that falls on its own."""

import mujoco
import numpy as np
import pytest

from eigengait.control.binding import gait_system
from eigengait.control.closed_loop import ClosedLoopRunner
from eigengait.control.controller import load_controller, to_parameters
from eigengait.control.library import resolve
from eigengait.control.root_assist import (
    DAMPING_SHARE,
    FREE_HEIGHT_SHARE,
    LIFT_SPAN,
    RootAssist,
)
from eigengait.errors import UserInputError
from eigengait.sim.world import GRAVITY


@pytest.fixture(scope="module")
def run_gait():
    path = resolve("gait", "humanoid-basic-run")
    c = load_controller(path).model_copy(update={"lookahead": None})
    system = gait_system(c, source=path)
    return system, to_parameters(c, system, path)


def _state(world, qpos, qvel):
    data = mujoco.MjData(world.model)
    data.qpos[:], data.qvel[:] = qpos, qvel
    mujoco.mj_forward(world.model, data)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state = np.zeros(mujoco.mj_stateSize(world.model, spec))
    mujoco.mj_getState(world.model, data, state, spec)
    return state[None]


def test_the_hand_leaves_an_upright_body_alone_and_turns_back_one_leaning_past_30_degrees(run_gait):
    system, _ = run_gait
    world = system.world
    hand = RootAssist(world, 1.5)
    zero = world.model.qpos0.copy()
    np.testing.assert_allclose(hand.forces(_state(world, zero, np.zeros(world.model.nv))), 0)
    # pitched 40° nose down (about world +y), turning at 1 rad/s about world x and 2 about z
    leaning = zero.copy()
    half = np.radians(40) / 2
    leaning[3:7] = [np.cos(half), 0, np.sin(half), 0]
    qvel = np.zeros(world.model.nv)
    # the free joint's angular velocity is in the root's frame: world (1, 0, 2) turned back
    c, s = np.cos(2 * half), np.sin(2 * half)
    qvel[3:6] = np.array([[c, 0, -s], [0, 1, 0], [s, 0, c]]) @ [1.0, 0.0, 2.0]
    f = hand.forces(_state(world, leaning, qvel))[0]
    h, m = world.standing_com_height, world.mass()
    k = 1.5 * m * GRAVITY * h
    damping = k * DAMPING_SHARE * np.sqrt(h / GRAVITY)
    # back about −y by the 10° past the bound, the roll rate damped, the heading rate left alone
    world_moment = np.array([-damping * 1.0, -k * np.radians(10), 0.0])
    rot = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])  # root frame -> world
    assert f[0] == 0  # the root stands at its own height
    np.testing.assert_allclose(f[1:], rot.T @ world_moment, rtol=1e-6, atol=1e-6)


def test_the_hand_lifts_a_sinking_root_by_its_weight_over_the_span(run_gait):
    system, _ = run_gait
    world = system.world
    hand = RootAssist(world, 1.0)
    sunk = world.model.qpos0.copy()
    low = FREE_HEIGHT_SHARE * sunk[2]
    sunk[2] = low - LIFT_SPAN * low  # the span below the free band: the whole weight
    qvel = np.zeros(world.model.nv)
    f = hand.forces(_state(world, sunk, qvel))[0]
    assert f[0] == pytest.approx(world.mass() * GRAVITY, rel=1e-9)
    qvel[2] = -1.0  # sinking at 1 m/s: damped
    settle = DAMPING_SHARE * np.sqrt(world.standing_com_height / GRAVITY)
    assert hand.forces(_state(world, sunk, qvel))[0, 0] == pytest.approx(
        world.mass() * GRAVITY * (1 + settle / (LIFT_SPAN * low)), rel=1e-9
    )


def test_the_hand_holds_up_a_run_that_falls_on_its_own(run_gait):
    system, p = run_gait
    runner = ClosedLoopRunner(system)
    alone = runner.run([p], 8)
    held = runner.run([p], 8, assist=RootAssist(system.world, 2.0))
    runner.close()
    assert alone.fell[0] and len(alone.cycle_ends[0]) < 8
    assert not held.fell[0] and len(held.cycle_ends[0]) == 8


def test_a_planar_root_is_refused_with_the_fix():
    path = resolve("gait", "planar-walker-walk")
    c = load_controller(path)
    system = gait_system(c, source=path)
    with pytest.raises(UserInputError, match="planar") as raised:
        RootAssist(system.world, 1.0)
    assert "--assist" in raised.value.fix
