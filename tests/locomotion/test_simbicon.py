"""SIMBICON's balance layer: where it moves the swing thigh and the torso (read from MuJoCo's own
accelerations, in any heading), that every simulation of a gait adds it, and the files that switch
it on."""

import json

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.control.binding import gait_system
from eigengait.control.closed_loop import ClosedLoopRunner, FeedbackPlan
from eigengait.control.controller import load_controller, to_file, to_parameters
from eigengait.control.feedback import StateRole
from eigengait.control.library import resolve
from eigengait.control.simbicon import SimbiconLayer, SimbiconSettings
from eigengait.control.sketch import load_sketch
from eigengait.errors import UserInputError
from eigengait.optimize.evaluate import Outcome
from eigengait.optimize.mom import MomState
from eigengait.optimize.problem import Problem
from eigengait.optimize.run import write_best
from eigengait.sim.world import build_world

RUNNING = StateRole(support="left", swing="right", stance=None)  # in the air, right leg forward
STANDING = StateRole(support="left", swing=None, stance="left")


@pytest.fixture(scope="module")
def humanoid():
    return build_world(load_character("humanoid"))


def _yawed(world, yaw: float, pitch: float = 0.0) -> np.ndarray:
    """The standing pose, 0.5 m up, turned by `yaw` about z and then pitched nose down by
    `pitch` (rad) about its own y axis."""
    qpos = world.model.qpos0.copy()
    qpos[world.root.height_qpos] += 0.5
    turn, tilt = np.zeros(4), np.zeros(4)
    mujoco.mju_axisAngle2Quat(turn, [0, 0, 1], yaw)
    mujoco.mju_axisAngle2Quat(tilt, [0, 1, 0], pitch)
    a = world.root.quat_qpos
    mujoco.mju_mulQuat(qpos[a : a + 4], turn, tilt)
    return qpos


def _state_and_sensors(world, qpos, qvel):
    data = mujoco.MjData(world.model)
    data.qpos[:], data.qvel[:] = qpos, qvel
    mujoco.mj_forward(world.model, data)
    state = np.zeros(mujoco.mj_stateSize(world.model, mujoco.mjtState.mjSTATE_FULLPHYSICS))
    mujoco.mj_getState(world.model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    return state, data.sensordata.copy()


def _accelerations(world, qpos, qvel, tau):
    """MuJoCo's accelerations with the motors giving `tau`, without gravity (the pose is 0.5 m up,
    so nothing touches)."""
    model = world.model
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = qpos, qvel
    data.qfrc_applied[world.internal_qvel] = tau
    gravity = model.opt.gravity.copy()
    model.opt.gravity[:] = 0
    try:
        mujoco.mj_forward(model, data)
    finally:
        model.opt.gravity[:] = gravity
    assert data.ncon == 0
    return data


def _heading(yaw):
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def _knee_acceleration(world, data, foot):
    """World acceleration (3,) of the knee relative to the hip, from qacc through both points'
    Jacobians (velocities are zero, so no bias term)."""
    model = world.model
    thigh = model.body(f"{foot}_thigh").id
    shin = model.body(f"{foot}_shin").id
    jac = []
    for body in (shin, thigh):
        jp = np.zeros((3, model.nv))
        mujoco.mj_jacBody(model, data, jp, None, body)
        jac.append(jp)
    return (jac[0] - jac[1]) @ data.qacc


@pytest.mark.parametrize("yaw", [0.0, 1.2, -2.5])
def test_the_swing_thigh_swings_forward_when_the_body_runs_faster_than_its_target(humanoid, yaw):
    """φ = φ₀ + c_d d_x + c_v (v_x − v*): 2 m/s over the target places the foot ahead (the knee
    accelerates forward in the heading frame), 2 m/s under it behind, whatever the heading."""
    world = humanoid
    qpos = _yawed(world, yaw)
    forward = _heading(yaw)[:, 0]
    for excess, sign in ((2.0, 1.0), (-2.0, -1.0)):
        layer = SimbiconLayer(world, ["left", "right"], SimbiconSettings(speed=2.0 - excess))
        qvel = np.zeros(world.model.nv)
        qvel[:2] = 2.0 * forward[:2]  # the free root's linear velocity, world frame
        state, sensors = _state_and_sensors(world, qpos, qvel)
        tau = layer.torque(state, sensors, RUNNING)
        assert np.abs(tau).max() > 1.0
        moved = [k for k, d in enumerate(world.internal_qvel) if world.model.dof_bodyid[d] != 0]
        assert set(np.flatnonzero(tau)) <= set(moved)
        data = _accelerations(world, qpos, np.zeros(world.model.nv), tau)
        knee = _knee_acceleration(world, data, "right")
        assert sign * (knee @ forward) > 0.5 * np.linalg.norm(knee)


@pytest.mark.parametrize("yaw", [0.0, 2.0])
def test_the_stance_hip_rights_a_torso_pitched_forward(humanoid, yaw):
    """A root pitched 0.3 rad nose down, standing on the left foot: the stance hip's torque turns
    the root back up (its angular acceleration about the heading's y axis is negative) and the
    swing hip is left alone."""
    world = humanoid
    qpos = _yawed(world, yaw, pitch=0.3)
    layer = SimbiconLayer(world, ["left", "right"], SimbiconSettings())
    state, sensors = _state_and_sensors(world, qpos, np.zeros(world.model.nv))
    tau = layer.torque(state, sensors, STANDING)
    model = world.model
    right = {
        k
        for k, d in enumerate(world.internal_qvel)
        if model.dof_bodyid[d] == model.body("right_thigh").id
    }
    assert all(tau[k] == 0 for k in right)
    data = _accelerations(world, qpos, np.zeros(model.nv), tau)
    root_angular = np.zeros((3, model.nv))
    mujoco.mj_jacBody(model, data, None, root_angular, world.root_body)
    spin = _heading(yaw).T @ (root_angular @ data.qacc)
    assert spin[1] < -0.5 * np.abs(spin).max()


def test_every_simulation_of_a_gait_with_the_layer_adds_its_torque():
    """The closed-loop runner's first 10 ms: the torque with the layer minus the torque without
    it is the layer's torque at the initial state."""
    controller = load_controller(resolve("gait", "humanoid-basic-run"))
    plain = gait_system(controller)
    params = to_parameters(controller, plain)
    with_layer = gait_system(
        controller.model_copy(update={"lookahead": None, "simbicon": SimbiconSettings(speed=1.5)})
    )
    runners = [ClosedLoopRunner(s) for s in (plain, with_layer)]
    runs = [runner.run([params], 0.01) for runner in runners]
    plan = FeedbackPlan(with_layer, params, runners[1].motors)
    expected = with_layer.balance_layer.torque(
        with_layer.initial_state(params), with_layer.initial_sensors(params), plan.role_at(0.0)
    )
    added = runs[1].torques[0, 0] - runs[0].torques[0, 0]
    limit = with_layer.torque_limit
    free = np.abs(runs[1].torques[0, 0]) < limit - 1e-6  # not clipped
    assert np.abs(expected).max() > 1.0
    np.testing.assert_allclose(added[free], expected[free], atol=1e-6)


def test_files_switch_the_layer_on_and_refuse_it_beside_plans(tmp_path):
    path = resolve("gait", "humanoid-basic-run")
    data = json.loads(path.read_text())
    data["simbicon"] = {"swing": 0.3, "speed": 1.5}
    beside_plans = tmp_path / "plans.json"
    beside_plans.write_text(json.dumps(data))
    with pytest.raises(UserInputError) as error:
        load_controller(beside_plans)
    assert "simbicon" in str(error.value) and str(beside_plans) in str(error.value)
    data.pop("lookahead")
    good = tmp_path / "layer.json"
    good.write_text(json.dumps(data))
    system = gait_system(load_controller(good))
    assert system.balance_layer is not None and system.simbicon.swing == 0.3
    data["simbicon"] = {"swing": -1}
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data))
    with pytest.raises(UserInputError) as error:
        load_controller(bad)
    assert "simbicon" in str(error.value)
    # a sketch asks for it the same way, and the controller written from its system keeps it
    sketch_file = tmp_path / "layer.yaml"
    sketch_file.write_text(resolve("sketch", "basic-run").read_text() + "simbicon: {lean: 0.2}\n")
    sketched = gait_system(load_sketch(sketch_file))
    assert sketched.balance_layer is not None
    written = to_file(sketched, to_parameters(load_controller(good), system))
    assert written.simbicon == SimbiconSettings(lean=0.2)


def test_an_optimized_gait_with_the_layer_is_written_without_plans(tmp_path):
    """`optimize` writes a lookahead section for the sketch's speed, but not for a gait with the
    layer: plans made without it would replace the pulses it was optimized with."""
    sketch_file = tmp_path / "layer.yaml"
    sketch_file.write_text(resolve("sketch", "kangaroo").read_text() + "simbicon: {speed: 1.5}\n")
    written = {}
    for name, sketch in (("plain", resolve("sketch", "kangaroo")), ("layer", sketch_file)):
        problem = Problem.from_sketch(load_sketch(sketch), sketch)
        x = problem.space.initial()
        outcome = Outcome(
            cost=1.0, cycle=np.zeros(1), fell=False, mean_velocity=np.zeros(3), energy=0.0
        )
        folder = tmp_path / name
        folder.mkdir()
        write_best(folder, problem, MomState(x_start=x, best_x=x, best=outcome))
        written[name] = load_controller(folder / "best_controller.json")
    assert written["plain"].lookahead is not None and written["plain"].simbicon is None
    assert written["layer"].lookahead is None
    assert written["layer"].simbicon == SimbiconSettings(speed=1.5)


def test_play_says_the_layer_was_played_and_its_torques_are_in_the_motion(eigengait_cli, tmp_path):
    data = json.loads(resolve("gait", "humanoid-basic-run").read_text())
    data.pop("lookahead")
    plain = tmp_path / "plain.json"
    plain.write_text(json.dumps(data))
    data["simbicon"] = {"speed": 1.5}
    layer = tmp_path / "layer.json"
    layer.write_text(json.dumps(data))
    played = {}
    for path in (plain, layer):
        run = eigengait_cli("play", path, "--cycles", "1", "--json")
        assert run.returncode == 0, run.stderr
        played[path.stem] = json.loads(run.stdout)
    assert played["layer"]["simbicon"] is True and played["plain"]["simbicon"] is False
    assert played["layer"]["lookahead"] is False
    torque = [played[k]["mean_squared_torque"] for k in ("layer", "plain")]
    assert torque[0] != pytest.approx(torque[1], rel=1e-3)


def test_each_leg_is_read_along_its_own_foots_chain():
    """The direction a leg is placed by runs from its first joint's body to that body's child on
    the way to the foot: on the dog, whose front legs hang from the chest joint, the upper leg
    and not the neck (the chest's first child)."""
    world = build_world(load_character("dog"))
    model = world.model
    layer = SimbiconLayer(world, list(world.character.feet), SimbiconSettings())
    names = {
        foot: (model.body(t).name, model.body(k).name) for foot, (t, k, *_) in layer.legs.items()
    }
    assert names["front_left"] == ("chest", "front_left_upper")
    assert names["rear_right"] == ("rear_right_upper", "rear_right_lower")
