"""Pulse state machine, mirroring, objective terms: each against hand-computed values."""

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.control.mirror import Mirror
from eigengait.control.pulse import control_sequence, schedule, state_torques
from eigengait.optimize import terms
from eigengait.sim import build_world


def test_biped_schedule_splits_the_period_by_foot_and_air_ratio():
    states = schedule(["left", "right"], period=1.0, air_ratio=0.3, pulse_air=0.1, pulse_ground=0.5)
    assert [(s.foot, s.phase) for s in states] == [
        ("left", "air"),
        ("left", "ground"),
        ("right", "air"),
        ("right", "ground"),
    ]
    np.testing.assert_allclose([s.duration for s in states], [0.15, 0.35, 0.15, 0.35])
    np.testing.assert_allclose([s.start for s in states], [0.0, 0.15, 0.5, 0.65])
    assert states[1].pulse == pytest.approx(0.35)  # a pulse never outlasts its state


def test_rectangular_pulses_in_the_control_sequence():
    states = schedule(["foot"], period=0.4, air_ratio=0.5, pulse_air=0.05, pulse_ground=0.1)
    torques = [np.array([1.0, 0.0]), np.array([0.0, 2.0])]
    u = control_sequence(states, torques, timestep=0.001, cycles=2)
    assert u.shape == (800, 2)
    assert np.count_nonzero(u[:400, 0]) == 50 and np.count_nonzero(u[:400, 1]) == 100
    assert np.all(u[200:300, 1] == 2.0) and np.all(u[300:400] == 0.0)
    np.testing.assert_array_equal(u[:400], u[400:])  # cyclic


def test_second_foot_uses_mirrored_torques():
    world = build_world(load_character("humanoid"))
    mirror = Mirror(world)
    states = schedule(["left", "right"], 1.0, 0.5, 0.1, 0.1)
    rng = np.random.default_rng(0)
    bases = {(s.foot, s.phase): rng.normal(size=(world.nmotor, 4)) for s in states}
    acts = {("left", "air"): rng.normal(size=4), ("left", "ground"): rng.normal(size=4)}
    tau = state_torques(bases, acts, states, mirror)
    np.testing.assert_allclose(tau[2], mirror.dofs(tau[0]))
    np.testing.assert_allclose(tau[3], mirror.dofs(tau[1]))
    labels = [f"{j}:{a}" for j in world.character.joints for a in "xyz"]
    i, k = labels.index("left_thigh:y"), labels.index("right_thigh:y")
    assert tau[2][k] == pytest.approx(tau[0][i])  # pitch torque keeps its sign on the other leg
    i, k = labels.index("left_thigh:x"), labels.index("right_thigh:x")
    assert tau[2][k] == pytest.approx(-tau[0][i])  # roll torque flips


def test_each_dof_is_clipped_at_its_own_motor_limit():
    world = build_world(load_character("humanoid"))  # its sidecar states strength: 1.0
    assert np.isfinite(world.motor_limits).all()
    states = schedule(["left", "right"], 1.0, 0.5, 0.1, 0.1)
    bases = {(s.foot, s.phase): np.eye(world.nmotor) for s in states}
    big = np.full(world.nmotor, 1000.0)
    limits = np.minimum(400.0, world.motor_limits)
    acts = {(s.foot, s.phase): (-1) ** i * big for i, s in enumerate(states)}
    for i, tau in enumerate(state_torques(bases, acts, states, torque_limit=limits)):
        np.testing.assert_array_equal(tau, (-1) ** i * limits)


def test_mirroring_a_state_reflects_every_body_and_is_an_involution():
    world = build_world(load_character("monster"))
    mirror = Mirror(world)
    rng = np.random.default_rng(3)
    d = world.new_data()
    mujoco.mj_integratePos(world.model, d.qpos, rng.normal(size=world.model.nv) * 0.4, 1.0)
    d.qvel[:] = rng.normal(size=world.model.nv)
    mujoco.mj_forward(world.model, d)
    qp, qv = mirror.state(d.qpos, d.qvel)
    m = mujoco.MjData(world.model)
    m.qpos[:], m.qvel[:] = qp, qv
    mujoco.mj_forward(world.model, m)
    S = np.diag([1.0, -1.0, 1.0])
    pairs = dict(world.character.meta.mirror.pairs)
    pairs.update({b: a for a, b in list(pairs.items())})
    for b in range(1, world.model.nbody):
        name = world.model.body(b).name
        other = world.model.body(pairs.get(name, name)).id
        np.testing.assert_allclose(S @ d.xpos[b], m.xpos[other], atol=1e-9)
        v, w = np.zeros(6), np.zeros(6)
        mujoco.mj_objectVelocity(world.model, d, mujoco.mjtObj.mjOBJ_BODY, b, v, 0)
        mujoco.mj_objectVelocity(world.model, m, mujoco.mjtObj.mjOBJ_BODY, other, w, 0)
        np.testing.assert_allclose(S @ v[3:], w[3:], atol=1e-9)
        np.testing.assert_allclose(-S @ v[:3], w[:3], atol=1e-9)
    back = mirror.state(qp, qv)
    np.testing.assert_allclose(back[0], d.qpos, atol=1e-12)
    np.testing.assert_allclose(back[1], d.qvel, atol=1e-12)


def test_soft_constraint_functions():
    assert terms.q_upper(0.2, 0.5) == pytest.approx(0.09 + 1.0)
    assert terms.q_upper(0.6, 0.5) == 0.0
    assert terms.q_both(0.3, 0.25) == pytest.approx(0.05**2 + 1.0)
    assert terms.q_both(-0.3, 0.25) == pytest.approx(0.05**2 + 1.0)
    assert terms.q_both(0.1, 0.25) == 0.0
    assert terms.speed_objective(2.0) == pytest.approx(0.25)
    assert terms.energy_objective(np.array([[3.0, 4.0], [0.0, 0.0]])) == pytest.approx(12.5)
    assert terms.energy_limit_term(6e5, 5e5) == pytest.approx(1e10 + 1.0)
    assert terms.priority_term([(np.array([5.0]), np.array([2.0, -2.0]))]) == 0.0
    assert terms.priority_term([(np.array([1.0]), np.array([2.0, -2.0]))]) == pytest.approx(
        9.0 + 1.0
    )
    assert terms.mean_speed_term(np.array([2.5, 0.0, 0.0]), 2.0, 0.25, 0.25) == 0.0
    assert terms.stance_contact_term(np.array([0.01, 0.004])) == pytest.approx(0.003**2 + 1.0)
    # push-off rise below 2 cm
    assert terms.stance_rise_term(0.005) == pytest.approx(0.015**2 + 1.0)
    assert terms.stance_rise_term(0.03) == 0.0
    # one sample
    assert terms.anti_stumble_term([0.9, 0.7, 0.8], [0.8, 0.8, 0.8]) == pytest.approx(0.1**2 + 1.0)
    assert terms.stance_slip_term(np.array([0.01, 0.05, 0.04]), 0.03) == pytest.approx(
        0.02**2 + 0.01**2 + 2.0
    )


def test_push_off_rise_counts_only_the_thesis_conditions():
    """Eq. 4.18 on a hand-built push-off: the COM falls, then rises; the toe rises 3 cm below a
    raised heel."""
    dt = 0.01
    com_vz = np.r_[np.full(5, -0.5), np.full(10, 0.5)]
    toe = np.r_[np.zeros(5), np.linspace(0.0, 0.03, 10)]
    heel = toe + 0.05
    assert terms.push_off_rise(com_vz, toe, heel, dt) == pytest.approx(0.03)
    assert terms.push_off_rise(com_vz, toe, toe - 0.01, dt) == 0.0  # heel below the toe
    assert terms.push_off_rise(np.full(15, 0.5), toe, heel, dt) == 0.0  # the COM never fell
    fast = np.r_[np.zeros(5), np.linspace(0.0, 0.3, 10)]  # toe 3.3 m/s faster than the COM
    assert terms.push_off_rise(com_vz, fast, fast + 0.05, dt) == 0.0


def test_activations_convert_between_mode_numbers_and_columns():
    """Mode numbers count from 1, columns from 0: sparse ψ -> dense and back, zeros dropped, bad
    numbers named."""
    from eigengait.control.activations import (
        dense_to_sparse,
        mode_index,
        mode_indices,
        psi_key,
        sparse_to_dense,
    )
    from eigengait.errors import UserInputError

    sparse = {1: 10.0, 4: -2.5}
    dense = sparse_to_dense(sparse, 5)
    np.testing.assert_array_equal(dense, [10.0, 0.0, 0.0, -2.5, 0.0])
    assert dense_to_sparse(dense) == sparse  # the zeros are left out
    assert dense_to_sparse(np.zeros(3)) == {}
    assert all(type(m) is int and type(v) is float for m, v in dense_to_sparse(dense).items())
    np.testing.assert_array_equal(sparse_to_dense(dense_to_sparse(dense), 5), dense)
    assert mode_index(1) == 0 and mode_indices([3, 1]) == [2, 0]
    assert psi_key("left", "air", 3) == "psi/left/air/3"
    for bad in (0, 6):
        with pytest.raises(UserInputError, match=f"mode {bad} does not exist \\(5 modes\\)") as err:
            sparse_to_dense({bad: 1.0}, 5, "gait.json", "activations.left.air")
        assert err.value.file == "gait.json" and err.value.field == "activations.left.air"
