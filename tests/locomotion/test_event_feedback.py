"""Event-based feedback: the pulse correction read once per state against absolute targets, its
controller-file form, and the hardening terms that search it (tilt, footfall pattern)."""

import json
from dataclasses import replace

import mujoco
import numpy as np
import pytest
from pydantic import ValidationError

from eigengait.control.activations import mode_indices
from eigengait.control.binding import gait_system
from eigengait.control.closed_loop import FeedbackPlan
from eigengait.control.controller import (
    ControllerFile,
    FeedbackFile,
    load_controller,
    to_file,
    to_parameters,
)
from eigengait.control.feedback import (
    EVENT_FEATURES,
    EVENT_MIRROR_SIGNS,
    EventGains,
    FeatureReader,
    hip_motors_by_foot,
    root_tilt,
)
from eigengait.control.library import resolve
from eigengait.optimize.survival import (
    PAIR_MISSING,
    PAIR_TOLERANCE,
    SurvivalSpace,
    footfall_pattern_cost,
)
from eigengait.sim.world import GRAVITY

SPEED = 1.5  # m/s


@pytest.fixture(scope="module")
def run_gait():
    path = resolve("gait", "humanoid-basic-run")
    c = load_controller(path)
    system = gait_system(c, source=path)
    p = to_parameters(c, system, path)
    rng = np.random.default_rng(4)
    event = EventGains(
        speed=SPEED,
        phases={
            "air": ([2, 15], rng.normal(0, 20, (2, 10))),
            "ground": ([2, 1, 5], rng.normal(0, 20, (3, 10))),
        },
    )
    # the hip feedback off, so that the plan's torque is the event correction alone
    return system, replace(p, feedback=replace(p.feedback, hip=None, event=event)), c


def features_by_hand(system, state, support):
    """The ten event features from MuJoCo's own COM, COM velocity and sites (not the sensors)."""
    model, world = system.world.model, system.world
    data = mujoco.MjData(model)
    mujoco.mj_setState(model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    mujoco.mj_forward(model, data)
    mujoco.mj_subtreeVel(model, data)
    root = world.root_body
    com, vel = data.subtree_com[root], data.subtree_linvel[root]
    toe = data.site_xpos[model.site(world.character.feet[support].toe).id]
    h = world.standing_com_height
    gh = np.sqrt(GRAVITY * h)
    tilt = root_tilt(data.qpos[3:7], data.qvel[3:6])
    return np.r_[
        (com[:2] - toe[:2]) / h,  # the support toe
        (vel[0] - SPEED) / gh,
        vel[1] / gh,
        tilt[:2],
        tilt[2:] / np.sqrt(GRAVITY / h),
        com[2] / h - 1.0,
        vel[2] / gh,
    ]


def test_the_correction_is_the_state_modes_times_the_gains_and_is_held_for_the_pulse(run_gait):
    system, p, _ = run_gait
    plan = FeedbackPlan(system, p, hip_motors_by_foot(system.world, system.feet))
    reader = FeatureReader(system.world)
    state, sensors = system.initial_state(p), system.initial_sensors(p)
    k = next(i for i, s in enumerate(plan.states) if s.duration - s.pulse > 0.005)
    first = plan.states[k]
    f = features_by_hand(system, state, plan.roles[k].support)
    modes, K = p.feedback.event.phases[first.phase]
    expected = system.basis_matrix(first.foot, first.phase)[:, mode_indices(modes)] @ K @ f
    tau = plan.torque(reader, 0, first.start, state, sensors)
    np.testing.assert_allclose(tau, expected, rtol=1e-6, atol=1e-6)
    # later in the same pulse, from another state, the correction read at the start is held
    other = state.copy()
    other[1:4] += 0.05
    held = plan.torque(reader, 0, first.start + 0.5 * first.pulse, other, sensors)
    np.testing.assert_allclose(held, expected, rtol=1e-12)
    # after the pulse (and with no other mechanism) nothing is added
    assert np.all(plan.torque(reader, 0, first.start + first.pulse + 1e-3, state, sensors) == 0)


def test_the_second_foot_gets_the_first_foot_correction_mirrored(run_gait):
    system, p, _ = run_gait
    plan = FeedbackPlan(system, p, hip_motors_by_foot(system.world, system.feet))
    reader = FeatureReader(system.world)
    state, sensors = system.initial_state(p), system.initial_sensors(p)
    half = len(plan.states) // 2
    mirrored, canon = plan.states[half], plan.states[0]
    assert mirrored.foot != canon.foot and mirrored.phase == canon.phase
    f = features_by_hand(system, state, plan.roles[half].support)
    modes, K = p.feedback.event.phases[canon.phase]
    B = system.basis_matrix(canon.foot, canon.phase)[:, mode_indices(modes)]
    expected = system.mirror.dofs(B @ K @ (f * EVENT_MIRROR_SIGNS))
    tau = plan.torque(reader, 1, mirrored.start, state, sensors)
    np.testing.assert_allclose(tau, expected, rtol=1e-6, atol=1e-6)


def test_event_gains_round_trip_through_the_controller_file_and_refuse_lookahead(run_gait):
    system, p, c = run_gait
    saved = to_file(system, p, "with-event")
    back = saved.feedback.gains().event
    assert back.speed == SPEED
    for phase, (modes, K) in p.feedback.event.phases.items():
        assert back.phases[phase][0] == sorted(modes)
        order = np.argsort(modes)
        np.testing.assert_allclose(back.phases[phase][1], K[order])
    document = json.loads(saved.model_dump_json())
    document["lookahead"] = c.lookahead.model_dump()
    with pytest.raises(ValidationError, match="feedback.event"):
        ControllerFile.model_validate(document)
    row = {"speed": 1.0, "air": {"2": [0.0] * 9}}
    with pytest.raises(ValidationError, match=f"needs {len(EVENT_FEATURES)} gains"):
        FeedbackFile.model_validate({"event": row})


def test_the_search_space_adds_ten_gains_per_mode_at_the_mass_scale(run_gait):
    system, p, _ = run_gait
    start = replace(p, feedback=replace(p.feedback, event=None))
    plain = SurvivalSpace(system, start)
    space = SurvivalSpace(
        system, start, event_modes={"air": (2, 15), "ground": (1,)}, target_speed=2
    )
    # the event search keeps the timing (4) and hip gains (8): no coordinates for them
    assert space.size == plain.size - 12 + 3 * len(EVENT_FEATURES)
    zero = space.decode(np.zeros(space.size)).feedback.event
    assert zero.speed == 2 and all(np.all(K == 0) for _, K in zero.phases.values())
    z = np.zeros(space.size)
    z[-1] = 1.0  # the last gain: ground mode 1, feature vz
    moved = space.decode(z).feedback.event.phases["ground"][1]
    world = system.world
    assert moved[0, -1] == pytest.approx(0.6 * world.mass() * GRAVITY * world.standing_com_height)


def test_the_footfall_pattern_cost_of_a_trot_a_pace_and_a_stopped_foot():
    pairs = (("front_right", "rear_left"), ("front_left", "rear_right"))
    trot = {"front_right": 0.10, "rear_left": 0.15, "front_left": 0.62, "rear_right": 0.58}
    assert footfall_pattern_cost(trot, pairs) == pytest.approx(0.0)
    pace = {"front_left": 0.30, "rear_left": 0.30, "front_right": 0.75, "rear_right": 0.75}
    # each diagonal pair 0.45 of a cycle apart, both centred on 0.525: the pairs together
    expected = 2 * (0.45 - PAIR_TOLERANCE) + (0.5 - PAIR_TOLERANCE)
    assert footfall_pattern_cost(pace, pairs) == pytest.approx(expected)
    pronk = {"front_left": 0.2, "rear_left": 0.2, "front_right": 0.2, "rear_right": 0.2}
    assert footfall_pattern_cost(pronk, pairs) == pytest.approx(0.5 - PAIR_TOLERANCE)
    assert footfall_pattern_cost({**trot, "rear_left": None}, pairs) == PAIR_MISSING
