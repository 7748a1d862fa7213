"""The swing-foot servo: the force it asks for, the joints it acts through, where it is silent, and
the files that switch it on."""

import json

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_file, to_parameters
from eigengait.control.library import resolve
from eigengait.control.sketch import load_sketch
from eigengait.control.swing_servo import ServoSettings, SwingServo
from eigengait.errors import UserInputError
from eigengait.sim.world import GRAVITY, build_world


@pytest.fixture(scope="module")
def humanoid():
    return build_world(load_character("humanoid"))


def _state(world, qpos, qvel):
    """A full-physics state with these coordinates (time 0, motors at rest)."""
    size = mujoco.mj_stateSize(world.model, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    data = mujoco.MjData(world.model)
    data.qpos[:], data.qvel[:] = qpos, qvel
    state = np.zeros(size)
    mujoco.mj_getState(world.model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    return state


def _lowest_sphere(world, qpos, foot):
    """(site id, height of its sphere's bottom above the floor, m) of the foot's lowest sphere."""
    data = mujoco.MjData(world.model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(world.model, data)
    points = world.character.feet[foot]
    sites = [world.model.site(s).id for s in (points.toe, points.heel) if s]
    heights = data.site_xpos[sites, 2] - world.foot_radius(foot)
    k = int(np.argmin(heights))
    return sites[k], float(heights[k])


def _at_height(world, z):
    """The standing pose raised so that the feet's lowest sphere bottoms are `z` above the floor
    (both feet stand level)."""
    qpos = world.model.qpos0.copy()
    _, now = _lowest_sphere(world, qpos, "left")
    qpos[world.root.height_qpos] += z - now
    return qpos


def _site_jacobian(world, qpos, site):
    """d(site position)/d(qvel) (3 × nv) by finite differences of the integrated pose: an
    independent check of the servo's analytic Jacobian."""
    eps = 1e-6
    data = mujoco.MjData(world.model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(world.model, data)
    base = data.site_xpos[site].copy()
    J = np.zeros((3, world.model.nv))
    for d in range(world.model.nv):
        moved, step = qpos.copy(), np.zeros(world.model.nv)
        step[d] = 1.0
        mujoco.mj_integratePos(world.model, moved, step, eps)
        data.qpos[:] = moved
        mujoco.mj_kinematics(world.model, data)
        J[:, d] = (data.site_xpos[site] - base) / eps
    return J


LEGS = {"left": ("left_thigh", "left_shin"), "right": ("right_thigh", "right_shin")}


@pytest.mark.parametrize("lift", [0.0, 1.0])
def test_servo_torques_are_the_legs_jacobian_transpose_of_the_stated_force(humanoid, lift):
    """τ = Σ_feet J_legᵀ m a with a_xy = −2ω v_xy (1 − z/c), a_z = l ω² (c − z) min(1, |v_xy| /
    0.1√(g h)), m the leg's mass: recomputed here from finite-difference Jacobians."""
    world, model = humanoid, humanoid.model
    settings = ServoSettings(lift=lift)
    h = world.standing_com_height
    band, omega = settings.band * h, settings.omega * np.sqrt(GRAVITY / h)
    z = 0.4 * band
    qpos = _at_height(world, z)
    qvel = np.zeros(model.nv)
    qvel[world.internal_qvel] = np.random.default_rng(3).normal(0.0, 1.0, world.nmotor)
    qvel[world.root.forward_qvel] = 0.3
    tau = SwingServo(world, settings).torque(_state(world, qpos, qvel)[None])[0]

    expected = np.zeros(model.nv)
    for foot, bodies in LEGS.items():
        site, height = _lowest_sphere(world, qpos, foot)
        assert height == pytest.approx(z, abs=1e-9)
        J = _site_jacobian(world, qpos, site)
        v = J @ qvel
        speed = np.hypot(v[0], v[1])
        a = np.array(
            [
                *(-2 * omega * v[:2] * (1 - z / band)),
                lift * omega**2 * (band - z) * min(1.0, speed / (0.1 * np.sqrt(GRAVITY * h))),
            ]
        )
        mass = float(model.body_subtreemass[model.body(bodies[0]).id])
        leg = np.isin(model.dof_bodyid, [model.body(b).id for b in bodies])
        expected[leg] += J[:, leg].T @ (mass * a)
    np.testing.assert_allclose(tau, expected[world.internal_qvel], atol=1e-3 * np.abs(tau).max())
    assert np.abs(tau).max() > 1.0
    if lift == 0.0:  # damping alone takes energy out of the motion
        assert tau @ qvel[world.internal_qvel] < 0


def test_a_foot_on_the_floor_or_above_the_band_gets_nothing(humanoid):
    world = humanoid
    servo = SwingServo(world)
    band = ServoSettings().band * world.standing_com_height
    qvel = np.zeros(world.model.nv)
    qvel[world.internal_qvel] = 1.0
    states = np.stack([_state(world, _at_height(world, z), qvel) for z in (-0.001, 1.2 * band)])
    np.testing.assert_array_equal(servo.torque(states), 0.0)


def test_controller_and_sketch_files_switch_the_servo_on_and_refuse_bad_values(tmp_path):
    path = resolve("gait", "dog-trot")
    data = json.loads(path.read_text())
    data["swing_servo"] = {"band": 0.05, "omega": 3.0, "lift": 0.0}
    good = tmp_path / "servo.json"
    good.write_text(json.dumps(data))
    controller = load_controller(good)
    system = gait_system(controller)
    assert system.servo is not None and system.servo.lift == 0.0
    data["swing_servo"] = {"band": -0.05}
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data))
    with pytest.raises(UserInputError) as error:
        load_controller(bad)
    assert "swing_servo" in str(error.value) and str(bad) in str(error.value)
    # a sketch asks for it the same way, and the controller written from its system keeps it
    sketch_text = resolve("sketch", "dog-trot").read_text()
    sketch_file = tmp_path / "servo.yaml"
    sketch_file.write_text(sketch_text + "swing_servo: {omega: 2.5}\n")
    sketched = gait_system(load_sketch(sketch_file))
    assert sketched.servo is not None and sketched.swing_servo == ServoSettings(omega=2.5)
    written = to_file(sketched, to_parameters(controller, system))
    assert written.swing_servo == ServoSettings(omega=2.5)


def test_a_one_footed_creatures_leg_stops_below_its_root():
    """The kangaroo's one foot: the servo moves its thigh, shin and foot with their own mass, not
    the whole body's through the root."""
    world = build_world(load_character("kangaroo"))
    model = world.model
    servo = SwingServo(world)
    (leg,) = servo.legs
    bodies = {model.body(int(model.dof_bodyid[d])).name for d in leg.dofs}
    assert bodies == {"thigh", "shin", "foot"}
    assert leg.mass == pytest.approx(float(model.body_subtreemass[model.body("thigh").id]))
    assert leg.mass < 0.5 * world.mass()
