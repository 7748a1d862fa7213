"""Lookahead (predictive sampling of the modal pulses at each state start): its cost, its effect,
its files."""

import dataclasses
import json
from pathlib import Path

import mujoco
import numpy as np
import pytest

from eigengait.control.closed_loop import ClosedLoopRunner, Push
from eigengait.control.feedback import FeedbackGains
from eigengait.control.binding import gait_system
from eigengait.control.controller import ControllerFile, load_controller, to_file, to_parameters
from eigengait.control.lookahead import (
    FALL_COST,
    SPEED_WEIGHT,
    LookaheadRunner,
    LookaheadSettings,
    TaskCost,
    plan_size,
    plan_weights,
    sliding_cost,
)
from eigengait.errors import UserInputError
from eigengait.files import validate

QUICK = dict(samples=12, horizon_cycles=1.5, refinements=0)


@pytest.fixture(scope="module")
def hopper():
    """An open-loop hop (no feedback gains) that drifts from cycle to cycle and falls in its
    fifth."""
    path = Path(__file__).parent / "data" / "kangaroo_open_loop.json"
    controller = load_controller(path)
    system = gait_system(controller)
    return system, to_parameters(controller, system), path


def test_root_heading_is_the_yaw_of_the_root_x_axis(hopper):
    system, p, _ = hopper
    root = system.world.root
    qpos = np.tile(p.qpos0, (3, 1))
    for row, yaw in zip(qpos, (0.0, 0.7, -2.5)):
        mujoco.mju_axisAngle2Quat(
            row[root.quat_qpos : root.quat_qpos + 4], np.array([0.0, 0.0, 1.0]), yaw
        )
    np.testing.assert_allclose(root.heading(qpos), [0.0, 0.7, -2.5], atol=1e-12)


def test_task_cost_is_zero_on_target_and_a_fall_costs_most(hopper):
    system, p, _ = hopper
    world = system.world
    height, speed = 0.9, 1.2
    cost = TaskCost(system, speed, height, p.qpos0, system.initial_com(p))
    state = system.initial_state(p)
    sensors = system.initial_sensors(p)
    a = 1 + world.root.quat_qpos
    # upright, heading kept
    mujoco.mju_axisAngle2Quat(state[a : a + 4], np.array([0.0, 0.0, 1.0]), cost.heading)
    sensors[world.com_sensor : world.com_sensor + 3] = [0.3, cost.side, height]
    sensors[world.comvel_sensor : world.comvel_sensor + 3] = [speed, 0.0, 0.0]
    on_target = cost(np.tile(state, (1, 4, 1)), np.tile(sensors, (1, 4, 1)), 1)
    assert on_target[0] == pytest.approx(0.0, abs=1e-12)
    slow = sensors.copy()
    slow[world.comvel_sensor] = 0.0
    # SPEED_WEIGHT × (Δv / √(g h))²
    expected = SPEED_WEIGHT * (speed / np.sqrt(9.81 * world.standing_com_height)) ** 2
    assert cost(np.tile(state, (1, 4, 1)), np.tile(slow, (1, 4, 1)), 1)[0] == pytest.approx(
        expected
    )
    # a gait's own speed weight scales that term alone
    harder = TaskCost(system, speed, height, p.qpos0, system.initial_com(p), speed_weight=10.0)
    assert harder(np.tile(state, (1, 4, 1)), np.tile(slow, (1, 4, 1)), 1)[0] == pytest.approx(
        expected * 10.0 / SPEED_WEIGHT
    )
    down = sensors.copy()
    down[world.com_sensor + 2] = 0.1 * world.standing_com_height
    assert cost(np.tile(state, (1, 4, 1)), np.tile(down, (1, 4, 1)), 1)[0] >= FALL_COST


def test_sliding_cost_counts_spheres_touching_at_both_samples_by_their_ground_speed():
    r, dt, v_unit = 0.02, 0.01, 2.0
    points = np.zeros((2, 3, 2, 3))  # plans × samples × spheres × xyz
    points[..., 2] = r  # resting on the floor
    points[:, :, 0, 0] = [0.0, 0.03, 0.06]  # sphere 0 slides at 3 m/s
    points[:, :, 1, 1] = [0.0, 0.5, 1.0]  # sphere 1 sweeps at 50 m/s…
    points[:, :, 1, 2] = r + 0.05  # …5 cm above the floor: not touching
    points[1, 2, 0, 2] = r + 0.01  # plan 1 lifts sphere 0 (1 cm up) before its last sample
    np.testing.assert_allclose(
        sliding_cost(points, r, dt, v_unit), [(3.0 / v_unit) ** 2, (3.0 / v_unit) ** 2 / 2]
    )


def test_plan_size_is_the_mean_squared_offset_over_the_spread_and_the_directions_drawn_in():
    directions = [np.eye(3)[:, :2], np.eye(3)]  # state 0 draws in 2 directions, state 1 in 3
    plans = np.zeros((2, 3, 3))  # plans × knots × motors (N·m)
    plans[0, 0] = [3.0, 4.0, 0.0]  # knot 0 (state 1): |Δτ|² = 25
    plans[0, 1] = [1.0, 0.0, 0.0]  # knot 1 (state 0): 1
    plans[0, 2] = [0.0, 0.0, 2.0]  # knot 2 (state 1): 4
    sigma = 2.0
    expected = (25 / (4 * 3) + 1 / (4 * 2) + 4 / (4 * 3)) / 3
    np.testing.assert_allclose(plan_size(plans, directions, 1, sigma), [expected, 0.0])
    rng = np.random.default_rng(0)  # plans drawn at the spread from unit directions: about 1
    drawn = rng.normal(0.0, sigma, (4000, 3, 2)) @ directions[0].T
    assert plan_size(drawn, [directions[0]], 0, sigma).mean() == pytest.approx(1.0, abs=0.05)


def test_task_cost_charges_sliding_feet_only_with_a_slip_weight(hopper):
    system, p, _ = hopper
    world, view = system.world, system.world.view
    state, sensors = system.initial_state(p), system.initial_sensors(p)
    states, rows = np.tile(state, (1, 4, 1)), np.tile(sensors, (1, 4, 1))
    states[..., 0] = 0.01 * np.arange(4)  # s: one cost sample every 10 ms
    foot = next(iter(view.foot_radius))
    radius, toe = view.foot_radius[foot], view.foot_points_at[foot][0]
    rows[..., toe + 2] = radius  # the toe sphere rests on the floor…
    rows[..., toe] = 0.01 * np.arange(4)  # …and slides forward at 1 m/s
    for other in view.foot_points_at[foot][1:]:
        rows[..., other + 2] = radius + 0.1  # the heel is lifted
    args = (system, 1.2, 0.9, p.qpos0, system.initial_com(p))
    plain = TaskCost(*args)(states, rows, 1)[0]
    weighted = TaskCost(*args, slip_weight=2.0)(states, rows, 1)[0]
    v_unit = np.sqrt(9.81 * world.standing_com_height)
    assert weighted - plain == pytest.approx(2.0 * (1.0 / v_unit) ** 2)


def test_a_plan_tilting_past_the_bound_counts_as_falling_from_that_sample(hopper):
    system, p, _ = hopper
    root = system.world.root
    state, sensors = system.initial_state(p), system.initial_sensors(p)
    states, rows = np.tile(state, (1, 4, 1)), np.tile(sensors, (1, 4, 1))
    a = 1 + root.quat_qpos
    for k, tilt in enumerate((0.0, 20.0, 35.0, 35.0)):  # degrees, about world x (a roll)
        mujoco.mju_axisAngle2Quat(
            states[0, k, a : a + 4], np.array([1.0, 0.0, 0.0]), np.radians(tilt)
        )
    args = (system, 1.2, 0.9, p.qpos0, system.initial_com(p))
    assert TaskCost(*args)(states, rows, 1)[0] < FALL_COST
    assert TaskCost(*args, max_tilt_deg=40.0)(states, rows, 1)[0] < FALL_COST
    # tilted past 30° from the third of four samples on: half the horizon was left
    assert TaskCost(*args, max_tilt_deg=30.0)(states, rows, 1)[0] == pytest.approx(FALL_COST * 1.5)


def test_lookahead_keeps_a_falling_hop_going(hopper):
    """The open-loop hop falls in its fifth cycle; with lookahead (32 plans a decision) it plays
    six, and the played (not planned) motion scores better by the planner's own cost up to the
    unaided fall."""
    system, p, _ = hopper
    alone = ClosedLoopRunner(system).run([p], 6)
    assert alone.fell[0] and alone.fell_time[0] < 5 * p.period
    runner = LookaheadRunner(system, LookaheadSettings(speed=1.0, samples=32))
    seen = []
    run = runner.run(p, 6, progress=lambda k, n: seen.append((k, n)))
    runner.close()
    assert not run.fell[0] and len(run.cycle_ends[0]) == 6
    assert seen == [(k, 6) for k in range(1, 7)]
    com_z = system.world.com_sensor + 2
    cost = TaskCost(
        system, 1.0, float(np.mean(run.sensors[0, :, com_z])), p.qpos0, system.initial_com(p)
    )
    n = int(alone.ended[0])
    played = cost(run.states[:, :n], run.sensors[:, :n], 20)[0]
    unaided = cost(alone.states[:, :n], alone.sensors[:, :n], 20)[0]
    assert played < unaided


def test_lookahead_is_deterministic_and_pushes_act_on_the_played_motion(hopper):
    system, p, _ = hopper
    settings = LookaheadSettings(speed=1.0, **QUICK)
    runs = []
    for pushes in ((), (), (Push(time=0.3, force=200.0 * system.world.mass()),)):
        runner = LookaheadRunner(system, settings)
        runs.append(runner.run(p, 2, pushes))
        runner.close()
    np.testing.assert_array_equal(runs[0].states, runs[1].states)
    vy = system.world.comvel_sensor + 1
    after = int(round(0.4 / system.world.model.opt.timestep))
    assert runs[2].sensors[0, after, vy] - runs[0].sensors[0, after, vy] > 5.0  # 20 N·s/kg sideways


class RecordingRunner(LookaheadRunner):
    """Keeps every batch of simulated plans: (start time s, states, sensors)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.predicted = []

    def _simulate_plans(self, x, controls, time, sensors, feedback):
        states, out = super()._simulate_plans(x, controls, time, sensors, feedback)
        self.predicted.append((time, states, out))
        return states, out


def test_with_feedback_the_plans_predict_the_played_motion_feedback_included(hopper):
    """Hip feedback on, plans at the physics timestep: the first cycle (the feedback's reference)
    plays as without feedback; after it, the plan that was chosen simulated exactly the motion then
    played, the feedback's torques included (so the feedback acts in the plans as in the played
    motion), and those torques differ from the pulses'."""
    system, p, _ = hopper
    gains = dataclasses.replace(p, feedback=FeedbackGains(hip=np.full(8, 50.0)))
    runs, runners = {}, {}
    for on in (True, False):
        runners[on] = RecordingRunner(
            system, LookaheadSettings(speed=1.0, feedback=on, plan_substeps=1, **QUICK)
        )
        runs[on] = runners[on].run(gains, 2)
        runners[on].close()
    dt = system.world.model.opt.timestep
    n0 = int(round(p.period / dt))
    np.testing.assert_array_equal(runs[True].torques[0, :n0], runs[False].torques[0, :n0])
    time, predicted, _ = next(batch for batch in runners[True].predicted if batch[0] >= p.period)
    start = int(round(time / dt))
    played = runs[True].states[0, start : start + 50]
    assert np.abs(predicted[:, :50] - played[None]).max(axis=(1, 2)).min() < 1e-6
    assert np.abs(runs[True].torques[0, start:] - runs[False].torques[0, start:]).max() > 1.0


def test_controller_file_keeps_lookahead_and_refuses_it_with_touchdown_timing(hopper, tmp_path):
    system, p, path = hopper
    settings = LookaheadSettings(
        speed=0.9, samples=16, speed_weight=10.0, slip_weight=2.0, max_tilt_deg=30.0
    )
    written = to_file(system, p, "hop", lookahead=settings)
    assert written.lookahead.settings() == settings
    data = json.loads(written.model_dump_json())
    data["trigger"] = "touchdown"
    with pytest.raises(UserInputError) as err:
        validate(ControllerFile, data, path, "fix it")
    assert "lookahead" in str(err.value) and str(path) in str(err.value)
    data["trigger"], data["lookahead"]["samples"] = "clock", 1
    with pytest.raises(UserInputError) as err:
        validate(ControllerFile, data, path, "fix it")
    assert "samples" in str(err.value)
    data["lookahead"]["samples"], data["lookahead"]["speed_weight"] = 16, -1.0
    with pytest.raises(UserInputError) as err:
        validate(ControllerFile, data, path, "fix it")
    assert "speed_weight" in str(err.value)
    data["lookahead"]["speed_weight"], data["lookahead"]["slip_weight"] = 10.0, -2.0
    with pytest.raises(UserInputError) as err:
        validate(ControllerFile, data, path, "fix it")
    assert "slip_weight" in str(err.value)
    data["lookahead"]["slip_weight"], data["lookahead"]["effort_weight"] = 2.0, -0.1
    with pytest.raises(UserInputError) as err:
        validate(ControllerFile, data, path, "fix it")
    assert "effort_weight" in str(err.value)
    data["lookahead"]["effort_weight"], data["lookahead"]["max_tilt_deg"] = 0.1, 0.0
    with pytest.raises(UserInputError) as err:
        validate(ControllerFile, data, path, "fix it")
    assert "max_tilt_deg" in str(err.value)


def test_play_uses_the_controllers_lookahead_unless_told_not_to(hopper, tmp_path, eigengait_cli):
    system, p, _ = hopper
    controller = tmp_path / "hop.json"
    controller.write_text(
        to_file(system, p, "hop", lookahead=LookaheadSettings(speed=1.0, **QUICK)).model_dump_json()
    )
    on = eigengait_cli("play", str(controller), "--cycles", "2", "--json")
    assert on.returncode == 0, on.stderr
    assert json.loads(on.stdout)["lookahead"] is True and "lookahead: cycle 2/2" in on.stderr
    off = json.loads(
        eigengait_cli("play", str(controller), "--cycles", "2", "--json", "--no-lookahead").stdout
    )
    assert off["lookahead"] is False and off["lookahead_plans"] is None
    fewer = eigengait_cli("play", str(controller), "--cycles", "1", "--json", "--plans", "4")
    assert json.loads(fewer.stdout)["lookahead_plans"] == 4
    assert json.loads(on.stdout)["lookahead_plans"] == QUICK["samples"]
    refused = eigengait_cli("play", str(controller), "--cycles", "1", "--plans", "1")
    assert refused.returncode != 0 and "--plans" in refused.stderr
    for option, key, default, value, bad in (
        ("--slip-weight", "lookahead_slip_weight", 0.0, "2", "-1"),
        ("--effort-weight", "lookahead_effort_weight", 0.0, "0.1", "-1"),
        ("--max-tilt", "lookahead_max_tilt_deg", None, "30", "0"),
    ):
        assert json.loads(on.stdout)[key] == default
        chosen = eigengait_cli("play", str(controller), "--cycles", "1", "--json", option, value)
        assert json.loads(chosen.stdout)[key] == float(value)
        refused = eigengait_cli("play", str(controller), "--cycles", "1", option, bad)
        assert refused.returncode != 0 and option in refused.stderr
    # another planner seed is another draw of the same plans: other torques, the same ones again
    # with the same seed
    assert json.loads(on.stdout)["lookahead_seed"] == 0

    def drawn(seed: str) -> dict:
        args = ("play", str(controller), "--cycles", "1", "--json", "--planner-seed", seed)
        return json.loads(eigengait_cli(*args).stdout)

    first, again, other = drawn("0"), drawn("0"), drawn("7")
    assert other["lookahead_seed"] == 7
    assert first["mean_squared_torque"] == again["mean_squared_torque"]
    assert first["mean_squared_torque"] != other["mean_squared_torque"]
    refused = eigengait_cli("play", str(controller), "--cycles", "1", "--planner-seed", "-1")
    assert refused.returncode != 0 and "--planner-seed" in refused.stderr


def test_plans_can_keep_to_the_sketchs_modes():
    """With `in_sketch` the plans move only the sketch's priority and allowed modes: the played
    torque stays in the sketch (what leaves it is clipping at the motor limits), where plans in
    every mode put most of it outside."""
    from eigengait.control.library import resolve
    from eigengait.control.playback import play
    from eigengait.control.sketch_character import energy_split

    # instant motors: a lag carries each state's torque into the next state's basis for a few tens
    # of ms
    controller = load_controller(resolve("gait", "kangaroo-hop")).model_copy(
        update={"activation_time": None}
    )
    system = gait_system(controller)
    p = to_parameters(controller, system)
    shares = {}
    for in_sketch in (False, True):
        kept = controller.model_copy(
            update={
                "lookahead": controller.lookahead.model_copy(
                    update={"in_sketch": in_sketch, "samples": 16, "horizon_cycles": 2.0}
                )
            }
        )
        result = play(system, p, cycles=2, lookahead=kept.planner())
        shares[in_sketch] = energy_split(system, p, controller.sketch, result.torques)["excluded"]
    pulses = energy_split(
        system, p, controller.sketch, system.controls(p, cycles=1)[:, : system.world.nmotor]
    )
    assert shares[True] <= pulses["excluded"] + 0.05 < shares[False]
    # the file keeps the choice, and refuses it without the sketch it needs
    data = json.loads(kept.model_dump_json())
    assert ControllerFile.model_validate(data).planner() == kept.planner()
    assert kept.planner().chosen["air"] == tuple(controller.sketch["air"].optimized_modes(1000))
    data["sketch"] = None
    with pytest.raises(UserInputError) as err:
        validate(ControllerFile, data, Path("dog.json"), "fix it")
    assert "in_sketch" in str(err.value)


def test_a_controller_with_an_activation_time_plays_torques_that_lag_their_commands(
    hopper, tmp_path
):
    """The file's activation time builds motors with a first-order lag: the first step applies u
    (1 − e^(−dt/τ)) of the instant controller's u, in the feedback runner and under lookahead
    alike."""
    instant, p, path = hopper
    data = json.loads(path.read_text())
    data["activation_time"] = 0.03
    lagged_file = tmp_path / "lagged.json"
    lagged_file.write_text(json.dumps(data))
    lagged = gait_system(load_controller(lagged_file))
    assert lagged.world.model.na == lagged.world.nmotor and instant.world.model.na == 0
    assert to_file(lagged, p).activation_time == 0.03
    first = [ClosedLoopRunner(s).run([p], 0.1).torques[0, 0] for s in (instant, lagged)]
    share = 1 - np.exp(-instant.world.model.opt.timestep / 0.03)
    assert np.abs(first[0]).max() > 1.0
    np.testing.assert_allclose(first[1], share * first[0], atol=1e-9)
    run = LookaheadRunner(lagged, LookaheadSettings(speed=1.0, **QUICK))
    try:
        played = run.run(p, 0.5)
    finally:
        run.close()
    assert (
        np.abs(played.torques[0, 0]).max() < share * np.abs(lagged.torque_limits).max() * 1.000001
    )


def test_plans_move_the_light_limbs_in_proportion_to_their_mass(hopper):
    """With `min_mass_share` 0.5 a plan's torque on a joint off the foot's chain is scaled by its
    subtree's mass share over 0.5: on the kangaroo a forearm gets less than its upper arm, which
    carries it, the arms and the tail tip under a tenth, and the foot (4 % of the mass) its full
    share because it is on the foot's chain. With 0 the plans move every joint in full. Played, the
    plans' offsets on the light limbs shrink with their weights while the legs' stay."""
    system, p, _ = hopper
    world, model = system.world, system.world.model
    dof_names = [model.body(b).name for b in model.dof_bodyid[np.asarray(world.internal_qvel)]]
    weights = plan_weights(world, 0.5)
    weight = dict(zip(dof_names, weights))
    mass = {name: model.body(name).subtreemass[0] / world.mass() for name in weight}
    for side in ("left", "right"):
        assert weight[f"{side}_forearm"] < weight[f"{side}_upper_arm"] < 0.1
        assert weight[f"{side}_forearm"] == pytest.approx(mass[f"{side}_forearm"] / 0.5)
    assert weight["tail_tip"] < 0.1
    assert weight["foot"] == 1.0 and mass["foot"] < 0.05
    assert (plan_weights(world, 0.0) == 1.0).all()
    n_motor = world.nmotor
    cycle = system.controls(p, cycles=1)[:, :n_motor]  # the lookahead repeats one cycle's pulses
    limit = system.torque_limits
    pulses = np.clip(np.vstack([cycle] * 3), -limit, limit)
    light = weights < 0.1
    offsets = {}
    for share in (0.0, 0.5):
        settings = LookaheadSettings(speed=1.0, min_mass_share=share, **QUICK)
        runner = LookaheadRunner(system, settings)
        run = runner.run(p, 2)
        runner.close()
        n = int(run.ended[0])
        offsets[share] = np.abs(run.torques[0, :n] - pulses[:n])
    assert offsets[0.5][:, light].max() < 0.5 * offsets[0.0][:, light].max()
    assert offsets[0.5][:, ~light].max() > 1.0  # N·m: the plans still act on the rest


def test_a_charge_on_the_plans_size_picks_smaller_offsets(hopper):
    """Among plans that do not fall, the size charge makes the smaller win: the played torques
    stay closer to the pulses than without it, and the hop still stands."""
    system, p, _ = hopper
    n_motor = system.world.nmotor
    limit = system.torque_limits
    pulses = np.clip(np.vstack([system.controls(p, cycles=1)[:, :n_motor]] * 3), -limit, limit)
    rms = {}
    for weight in (0.0, 5.0):
        runner = LookaheadRunner(
            system, LookaheadSettings(speed=1.0, effort_weight=weight, **QUICK)
        )
        run = runner.run(p, 2)
        runner.close()
        assert not run.fell[0]
        n = int(run.ended[0])
        rms[weight] = float(np.sqrt(np.mean((run.torques[0, :n] - pulses[:n]) ** 2)))
    assert rms[5.0] < 0.5 * rms[0.0]
