"""Balance feedback inside the pulse controller: features, output directions, and what it does to
drift."""

from pathlib import Path

import cma
import mujoco
import numpy as np
import pytest

from eigengait.control.closed_loop import ClosedLoopRunner, cycle_errors
from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_parameters
from eigengait.control.feedback import (
    HIP_GAINS,
    FeedbackGains,
    StateRole,
    hip_motors,
    hip_torque,
    leg_root_joint,
    root_tilt,
    state_roles,
)
from eigengait.control.library import resolve
from eigengait.control.pulse import schedule


def quat(axis, angle):
    q = np.zeros(4)
    mujoco.mju_axisAngle2Quat(q, np.asarray(axis, float), angle)
    return q


def test_root_tilt_reads_pitch_roll_and_world_rates():
    pitch, roll, _, _ = root_tilt(quat([0, 1, 0], 0.3), np.zeros(3))
    # nose down is positive
    assert pitch == pytest.approx(0.3) and roll == pytest.approx(0.0, abs=1e-12)
    pitch, roll, _, _ = root_tilt(quat([1, 0, 0], -0.2), np.zeros(3))
    assert roll == pytest.approx(-0.2) and pitch == pytest.approx(0.0, abs=1e-12)
    # yawed by 90°, a spin about the body's x axis is a spin about world y: a pitch rate
    _, _, pitch_rate, roll_rate = root_tilt(quat([0, 0, 1], np.pi / 2), np.array([0.7, 0.0, 0.0]))
    assert pitch_rate == pytest.approx(0.7) and roll_rate == pytest.approx(0.0, abs=1e-12)


def shipped(name):
    controller = load_controller(resolve("gait", name))
    system = gait_system(controller)
    return system, to_parameters(controller, system)


@pytest.fixture(scope="module")
def gait():
    return shipped("humanoid-basic-run")


def test_the_hips_are_the_thighs_and_their_pitch_axis_is_world_y(gait):
    system, _ = gait
    world = system.world
    assert (
        leg_root_joint(world, "left") == "left_thigh"
        and leg_root_joint(world, "right") == "right_thigh"
    )
    pitch, roll = hip_motors(world, "left")
    dof_pitch, dof_roll = world.internal_qvel[pitch], world.internal_qvel[roll]
    j = world.model.joint("left_thigh").id
    assert dof_pitch - world.model.jnt_dofadr[j] == 1 and dof_roll - world.model.jnt_dofadr[j] == 0


def test_state_roles_and_hip_torque_follow_simbicon():
    roles = state_roles(schedule(["left", "right"], 0.6, 0.4, 0.1, 0.1))
    # flight before left lands
    assert roles[0] == StateRole(support="right", swing="left", stance=None)
    assert roles[1] == StateRole(support="left", swing="right", stance="left")
    motors = {"left": (0, 1), "right": (2, 3)}
    gains = np.arange(1.0, 9.0)
    dev = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8])
    tau = hip_torque(gains, dev, roles[1], motors, 4)
    assert tau[2] == pytest.approx(1 * 0.1 + 2 * 0.3)  # swing hip pitch ← dx, vx
    assert tau[3] == pytest.approx(3 * 0.2 + 4 * 0.4)  # swing hip roll ← dy, vy
    assert tau[0] == pytest.approx(5 * 0.5 + 6 * 0.7)  # stance hip pitch ← pitch, pitch rate
    assert tau[1] == pytest.approx(7 * 0.6 + 8 * 0.8)  # stance hip roll ← roll, roll rate


def test_first_cycle_is_open_loop_and_zero_gains_change_nothing(gait):
    system, p = gait
    runner = ClosedLoopRunner(system)
    open_loop = runner.run([p], 2)
    p.feedback = FeedbackGains(hip=np.full(len(HIP_GAINS), 50.0))
    closed = runner.run([p], 2)
    p.feedback = FeedbackGains()
    n = int(round(p.period / system.world.model.opt.timestep))
    # the reference cycle
    np.testing.assert_array_equal(open_loop.torques[0, :n], closed.torques[0, :n])
    # feedback acts after it
    assert np.abs(open_loop.torques[0, n:] - closed.torques[0, n:]).max() > 1.0


def drift(runner, system, p, cycles=3):
    """Cycle-to-cycle drift: the largest cycle-end error of cycles 2.. (10 if it falls)."""
    run = runner.run([p], cycles)
    if run.fell[0]:
        return 10.0
    blocks = cycle_errors(system, p, run.states[0], cycles)
    width = 2 * system.world.model.nv - 1
    return float(np.abs(blocks[width : cycles * width]).max())


@pytest.fixture(scope="module")
def hopper():
    """An open-loop hop (no feedback gains) that drifts from cycle to cycle and falls in its
    fifth."""
    controller = load_controller(Path(__file__).parent / "data" / "kangaroo_open_loop.json")
    system = gait_system(controller)
    return system, to_parameters(controller, system)


def test_optimized_hip_feedback_reduces_cycle_to_cycle_drift(hopper):
    """A short CMA-ES run over the eight hip gains alone, on an open-loop hop that drifts: drift
    must drop."""
    system, p = hopper
    runner = ClosedLoopRunner(system)
    baseline = drift(runner, system, p)
    scale = 200.0

    def objective(x):
        p.feedback = FeedbackGains(hip=scale * np.asarray(x))
        return drift(runner, system, p)

    es = cma.CMAEvolutionStrategy(
        np.zeros(len(HIP_GAINS)), 0.3, {"seed": 3, "popsize": 8, "maxiter": 6, "verbose": -9}
    )
    es.optimize(objective)
    best = es.result.fbest
    p.feedback = FeedbackGains()
    assert best < 0.8 * baseline, (best, baseline)


def test_every_cycle_played_in_full_is_counted(gait):
    """A cycle of 0.3396 s is 679.26 steps of 0.5 ms, played as 679: it ends on the last step and
    still counts. (One cycle, which the open-loop run survives on any build; whether it survives a
    fourth is chaotic.)"""
    system, p = gait
    assert p.period / system.world.model.opt.timestep % 1 == pytest.approx(0.26, abs=0.01)
    run = ClosedLoopRunner(system).run([p], 1)
    assert not run.fell[0]
    assert len(run.cycle_ends[0]) == 1 and run.cycle_ends[0][-1] == run.ended[0] - 1
