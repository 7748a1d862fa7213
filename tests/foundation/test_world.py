"""The simulated world: standing on the floor, springs at rest, and the thesis's stance-foot contact
filter."""

import mujoco
import numpy as np
import pytest
from mujoco import rollout

from eigengait.character import load_character
from eigengait.errors import UserInputError
from eigengait.sim import WorldOptions, build_world


def test_character_stands_on_the_floor_and_springs_hold_it_without_gravity():
    world = build_world(load_character("humanoid"), options=WorldOptions(gravity=False))
    data = world.new_data()
    toe = world.model.site("left_toe").id
    radius = world.model.geom_size[world.foot_spheres["left"][0], 0]
    assert abs(data.site_xpos[toe][2] - radius) < 1e-9  # lowest contact sphere touches z = 0
    mujoco.mj_step(world.model, data, 2000)
    assert np.abs(data.qvel).max() < 1e-6  # at rest: springs rest at the relax pose


def test_only_the_stance_foot_collides_when_filtered():
    world = build_world(load_character("humanoid"), options=WorldOptions(contact="feet"))
    world.set_stance_foot("left")
    data = world.new_data()
    mujoco.mj_step(world.model, data, 1000)  # 0.5 s of gravity
    left = data.site_xpos[world.model.site("left_toe").id][2]
    right = data.site_xpos[world.model.site("right_toe").id][2]
    assert left > 0.0 and right < left - 0.02  # the swing foot sinks through the floor
    world.set_stance_foot(None)
    data = world.new_data()
    mujoco.mj_step(world.model, data, 1000)
    right = data.site_xpos[world.model.site("right_toe").id][2]
    assert right > 0.0  # both feet collide again


def test_default_damping_is_a_tenth_of_the_stiffness():
    world = build_world(load_character("humanoid"))
    j = world.model.joint("left_thigh").id
    dof = world.model.jnt_dofadr[j]
    assert world.model.dof_damping[dof] == np.float64(0.1 * world.model.jnt_stiffness[j])


def test_motor_limits_are_the_joint_stiffness_times_the_strength_angle():
    character = load_character("humanoid")
    assert character.meta.strength == 1.0  # the built-in sidecar states it
    character.meta.strength = None
    # no strength stated: no per-joint limit
    assert np.isinf(build_world(character).motor_limits).all()
    character.meta.strength = 1.0
    world = build_world(character)
    model = world.model
    joints = model.dof_jntid[world.internal_qvel]
    springs = model.jnt_stiffness[joints] > 0  # isotropic joints carry MuJoCo's own stiffness
    assert springs.sum() > 10
    np.testing.assert_allclose(world.motor_limits[springs], model.jnt_stiffness[joints][springs])
    forearm, thigh = (
        world.motor_limits[joints == model.joint(n).id][0] for n in ("left_forearm", "left_thigh")
    )
    assert forearm < thigh / 5  # a light forearm cannot be driven like a leg


def test_activation_time_lags_each_motor_torque_as_a_first_order_filter():
    """A step command u from rest: the applied torque is u (1 − exp(−t/τ)) (MuJoCo's exact filter),
    and the torques read from full-physics rollout states are those applied; with no activation time
    they are the commands."""
    character = load_character("humanoid")
    instant = build_world(character, options=WorldOptions(gravity=False))
    assert instant.model.na == 0
    commands = np.ones((3, instant.nmotor))
    assert instant.applied_motor_torques(np.zeros((3, 99)), commands) is commands
    tau = 0.02
    world = build_world(character, options=WorldOptions(gravity=False, activation_time=tau))
    model, data = world.model, world.new_data()
    assert model.na == world.nmotor
    u = np.linspace(-30.0, 30.0, world.nmotor)
    steps = 80
    controls = np.zeros((1, steps, model.nu))
    controls[0, :, : world.nmotor] = u
    state = np.empty(mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_FULLPHYSICS))
    mujoco.mj_getState(model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    states, _ = rollout.rollout(model, data, state[None], controls)
    applied = world.applied_motor_torques(states[0], controls[0, :, : world.nmotor])
    t = model.opt.timestep * np.arange(1, steps + 1)
    np.testing.assert_allclose(applied, np.outer(1 - np.exp(-t / tau), u), atol=1e-9)
    data.act[:] = applied[-2]  # the activation before the last step
    data.ctrl[: world.nmotor] = u
    mujoco.mj_forward(model, data)
    # what the joints got in it
    np.testing.assert_allclose(data.actuator_force[: world.nmotor], applied[-1])


def test_an_impossible_activation_time_is_one_clear_error():
    with pytest.raises(UserInputError) as err:
        WorldOptions(activation_time=-0.01)
    assert err.value.field == "activation_time" and "0.01-0.05" in err.value.fix


def test_sidecar_strength_scales_each_axis_of_an_anisotropic_joint(tmp_path):
    xml = """<mujoco><worldbody><body name="a"><freejoint/><geom type="box" size="0.3 0.05 0.1" pos="-0.3 0 0"/>
      <body name="b"><joint name="j" type="ball"/><geom type="box" size="0.3 0.05 0.1" pos="0.3 0 0"/>
      </body></body></worldbody></mujoco>"""  # noqa: E501
    (tmp_path / "pair.xml").write_text(xml)
    (tmp_path / "pair.eigengait.yaml").write_text(
        "eigengait: 1\nstiffness: {j: [30, 70, 110]}\nstrength: 0.5\n"
    )
    world = build_world(
        load_character(tmp_path / "pair.xml"), options=WorldOptions(gravity=False, floor=False)
    )
    np.testing.assert_allclose(world.motor_limits, [15.0, 35.0, 55.0])
