"""Method of multipliers, checkpoints, batched evaluation (threads, processes, Ray) against single
stepping."""

import json
import pickle
from dataclasses import asdict, fields

import mujoco
import numpy as np
import pytest

from eigengait.control.library import resolve
from eigengait.control.sketch import load_sketch
from eigengait.optimize.evaluate import BatchEvaluator, Outcome
from eigengait.optimize.evaluators import ProcessEvaluator, RayEvaluator
from eigengait.optimize.checkpoint import load_state, save_state
from eigengait.optimize.adaptive_al import AdaptiveAugmentedLagrangian, AlSettings
from eigengait.optimize.methods import make_optimizer, method_settings
from eigengait.optimize.mom import CmaOptions, MethodOfMultipliers, MomSettings, MomState
from eigengait.optimize.problem import Problem
from eigengait.optimize.parameters import ParameterSpace, feedback_gain_count


def toy_evaluate(X):
    """f = 0.01‖x − 0.2‖², cyclic constraint φ = x[:2] − 0.7 (the constrained optimum is x
    = (.7, .7, .2, …))."""
    X = np.atleast_2d(X)
    return [
        Outcome(
            cost=0.01 * float(np.sum((x - 0.2) ** 2)),
            cycle=x[:2] - 0.7,
            fell=False,
            mean_velocity=np.zeros(3),
            energy=0.0,
        )
        for x in X
    ]


def run_toy(settings, state, generations=None):
    mom = make_optimizer(toy_evaluate, settings, state)
    rows = []
    while (generations is None or len(rows) < generations) and (row := mom.step()) is not None:
        rows.append(row)
    return rows


def test_method_of_multipliers_meets_the_cyclic_constraint():
    settings = MomSettings(seed=3, inner_generations=60, cycle_tolerance=1e-3, penalty=10.0)
    state = MomState(x_start=np.full(5, 0.5))
    run_toy(settings, state)
    assert state.finished == "cyclic"
    np.testing.assert_allclose(state.best_x[:2], 0.7, atol=1e-3)
    assert state.outer >= 1  # the first run (k = 0) ignores φ


@pytest.mark.parametrize("generations", [17, 32], ids=["in-the-first-inner-run", "in-the-second"])
@pytest.mark.parametrize("method", ["mom", "al"])
def test_runs_are_seeded_and_a_checkpoint_resumes_exactly(tmp_path, method, generations):
    settings = method_settings(
        method, seed=5, inner_generations=30, max_evaluations=1200, cycle_tolerance=1e-3
    )
    straight = MomState(x_start=np.full(4, 0.5))
    run_toy(settings, straight)
    # the second interruption is past the first run
    assert straight.outer >= 1 and straight.log[31]["outer"] == 1
    interrupted = MomState(x_start=np.full(4, 0.5))
    run_toy(settings, interrupted, generations=generations)
    save_state(interrupted, tmp_path / "checkpoint.npz")
    resumed = load_state(tmp_path / "checkpoint.npz")
    run_toy(settings, resumed)
    assert [r["best_cost"] for r in resumed.log] == [r["best_cost"] for r in straight.log]
    np.testing.assert_array_equal(resumed.best_x, straight.best_x)


def test_each_method_has_its_own_settings():
    assert isinstance(
        make_optimizer(toy_evaluate, method_settings("mom"), MomState(np.zeros(2))),
        MethodOfMultipliers,
    )
    al = make_optimizer(toy_evaluate, method_settings("al"), MomState(np.zeros(2)))
    assert isinstance(al, AdaptiveAugmentedLagrangian)
    with pytest.raises(TypeError, match="penalty"):
        # pycma adapts its own penalties: one given here would be ignored
        method_settings("al", penalty=10.0)
    with pytest.raises(TypeError, match="method"):
        MomSettings(method="al")
    from eigengait.errors import UserInputError

    with pytest.raises(UserInputError, match="unknown method 'sqp'"):
        method_settings("sqp")


def test_the_cma_options_are_settings_with_the_former_defaults():
    options = CmaOptions(seed=4, popsize=9).pycma_options(run=2)
    assert options == {
        "bounds": [0, 1],
        "seed": 6,
        "tolx": 1e-4,
        "maxiter": 1000,
        "verbose": -9,
        "verb_log": 0,
        "verb_disp": 0,
        "tolfun": 0,
        "tolflatfitness": 1000,
        "popsize": 9,
    }
    assert "popsize" not in CmaOptions().pycma_options(run=0)
    shared = {f.name for f in fields(CmaOptions)}
    assert shared < {f.name for f in fields(AlSettings)} < {f.name for f in fields(MomSettings)}
    state = MomState(x_start=np.full(4, 0.5))
    mom = make_optimizer(toy_evaluate, MomSettings(tol_flat_fitness=3, inner_generations=50), state)
    mom.start_inner_run()
    assert state.es.opts["tolflatfitness"] == 3 and state.es.opts["maxiter"] == 50


def test_the_adaptive_al_state_is_declared_and_no_log_folder_is_left(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    state = MomState(x_start=np.full(4, 0.5))
    assert "al" in {f.name for f in fields(MomState)}
    run_toy(AlSettings(seed=2, inner_generations=5), state, generations=3)
    assert state.al is not None and state.al.multipliers.shape == (4,)
    assert set(vars(state)) == {f.name for f in fields(MomState)}
    assert not (tmp_path / "outcmaes").exists()


@pytest.mark.parametrize("method", ["mom", "al"])
def test_run_folders_of_earlier_versions_resume_with_their_method(tmp_path, method):
    """settings.json once kept the method among one settings class's fields, and the AL a penalty it
    ignored."""
    from eigengait.optimize.run import prepare_folder

    sketch = load_sketch(resolve("sketch", "basic-run"))
    run = tmp_path / "run"
    prepare_folder(run, sketch, method_settings(method, seed=4), "threads", resume=False)
    earlier = {**asdict(MomSettings(seed=4, penalty=2.0)), "method": method}
    earlier = {k: v for k, v in earlier.items() if k not in ("tol_fun", "tol_flat_fitness")}
    (run / "settings.json").write_text(json.dumps({"settings": earlier, "evaluator": "processes"}))
    save_state(MomState(x_start=np.full(3, 0.5)), run / "checkpoint.npz")
    budget = MomSettings(max_evaluations=50)
    settings, evaluator, state = prepare_folder(run, sketch, budget, "threads", resume=True)
    assert settings.method == method and evaluator == "processes" and state is not None
    assert settings.seed == 4 and settings.max_evaluations == 50
    assert settings.penalty == 2.0 if method == "mom" else not hasattr(settings, "penalty")
    (run / "settings.json").write_text(
        json.dumps({"method": "nope", "settings": {}, "evaluator": "threads"})
    )
    from eigengait.errors import UserInputError

    with pytest.raises(UserInputError, match="settings.json is missing or damaged") as caught:
        prepare_folder(run, sketch, budget, "threads", resume=True)
    assert caught.value.file == str(run / "settings.json") and "new run" in caught.value.fix


class _Payload:
    """A pickle that runs code when loaded (it would create the file `marker`)."""

    def __init__(self, marker):
        self.marker = marker

    def __reduce__(self):
        return (open, (str(self.marker), "w"))


def test_damaged_or_foreign_checkpoints_are_refused_without_running_code(tmp_path):
    from eigengait.errors import UserInputError

    (tmp_path / "checkpoint.npz").write_bytes(b"not a checkpoint")
    with pytest.raises(UserInputError, match="corrupt"):
        load_state(tmp_path / "checkpoint.npz")
    marker = tmp_path / "code-ran"
    (tmp_path / "pickled.npz").write_bytes(pickle.dumps(_Payload(marker)))
    with pytest.raises(UserInputError, match="corrupt"):
        load_state(tmp_path / "pickled.npz")
    np.savez(tmp_path / "object.npz", meta=np.array([_Payload(marker)], dtype=object))
    with pytest.raises(UserInputError, match="corrupt"):
        load_state(tmp_path / "object.npz")
    assert not marker.exists()
    np.savez(tmp_path / "other.npz", meta=np.array('{"format": "something else"}'))
    with pytest.raises(UserInputError, match="not an eigengait checkpoint"):
        load_state(tmp_path / "other.npz")
    np.savez(tmp_path / "partial.npz", meta=np.array('{"format": "eigengait-checkpoint-1"}'))
    with pytest.raises(UserInputError, match="incomplete"):
        load_state(tmp_path / "partial.npz")


@pytest.fixture(scope="module")
def problem():
    return Problem.from_sketch(load_sketch(resolve("sketch", "basic-run")))


def population(problem, n=6, seed=0):
    rng = np.random.default_rng(seed)
    return np.clip(problem.space.initial() + 0.15 * rng.normal(size=(n, problem.space.size)), 0, 1)


def test_batched_rollout_matches_plain_stepping(problem):
    """The chunked batch (feedback read between chunks) against a plain per-step loop applying the
    same torques."""
    evaluator = BatchEvaluator(
        problem.system, problem.space, problem.sketch.targets, threads=2, cycles=2
    )
    X = population(problem, 4)
    run = evaluator.simulate([problem.space.decode(x) for x in X])
    model = problem.system.world.model
    for i, x in enumerate(X):
        p = problem.space.decode(x)
        data = mujoco.MjData(model)
        data.qpos[:], data.qvel[:] = p.qpos0, p.qvel0
        for s in range(run.ended[i]):
            data.ctrl[:] = 0
            data.ctrl[: problem.system.world.nmotor] = run.torques[i, s]
            mujoco.mj_step(model, data)
        np.testing.assert_allclose(
            data.qpos, run.states[i, run.ended[i] - 1, 1 : 1 + model.nq], atol=1e-6
        )


def test_a_falling_candidate_stops_early_and_still_ranks(problem):
    evaluator = BatchEvaluator(problem.system, problem.space, problem.sketch.targets, threads=2)
    x = problem.space.initial()
    params = problem.space.decode(x)
    params.qpos0[2] -= 0.5  # start half a metre into the floor: the creature is thrown and falls
    params.qvel0[:3] = [0.0, 6.0, -3.0]
    run = evaluator.simulate([params, problem.space.decode(x)])
    assert run.fell[0] and run.ended[0] < run.steps[0]
    outcomes = evaluator.evaluate(np.stack([x, x]))
    assert outcomes[0].cost == outcomes[1].cost  # same candidate, same result


def test_the_slip_term_charges_the_stances_that_playback_measures(problem):
    """With a stance-slip target the evaluator charges, per stance, what `play` reports as that
    stance's slip."""
    from eigengait.control.gait_metrics import rollout_stance_slips
    from eigengait.optimize import terms

    x = problem.space.initial()
    p = problem.space.decode(x)
    targets = problem.sketch.targets.model_copy(update={"stance_slip": 0.001})
    evaluator = BatchEvaluator(problem.system, problem.space, targets, threads=2, cycles=2)
    run = evaluator.simulate([p])
    end = int(run.ended[0])
    slips = rollout_stance_slips(
        problem.system.world.view,
        problem.system.initial_sensors(p),
        run.sensors[0, :end],
        evaluator.dt,
    )
    charged = evaluator.evaluate(x[None])[0].soft["stance_slip"]
    stances = np.concatenate(list(slips.values()))
    # two cycles of a run: stances, some sliding a millimetre
    assert stances.size >= 2 and (stances > 0.001).any()
    assert charged == pytest.approx(terms.stance_slip_term(stances, 0.001))
    assert charged >= (stances > 0.001).sum()  # each sliding stance adds at least the step h = 1
    plain = BatchEvaluator(
        problem.system, problem.space, problem.sketch.targets, threads=2, cycles=2
    )
    assert "stance_slip" not in plain.evaluate(x[None])[0].soft  # no target, no term


def test_the_paired_feet_term_charges_each_cycle_the_pair_spends_apart(problem):
    """With `targets.paired_feet`, a cycle in which one foot of a pair touches the ground while the
    other does not for more than the tolerance adds Q_u: read here from the feet's sphere heights
    at every 10 ms sample of one cycle, the contact rule applied by hand."""
    from eigengait.errors import UserInputError
    from eigengait.sim.contacts import CONTACT_TOLERANCE

    x = problem.space.initial()
    p = problem.space.decode(x)
    left, right = problem.system.world.character.feet
    targets = problem.sketch.targets.model_copy(
        update={"paired_feet": [(left, right)], "pair_tolerance": 0.05}
    )
    evaluator = BatchEvaluator(problem.system, problem.space, targets, threads=2, cycles=1)
    run = evaluator.simulate([p])
    assert not run.fell[0]
    view = problem.system.world.view
    sampled = run.sensors[0, evaluator.sample_every - 1 :: evaluator.sample_every]
    down = {
        f: (view.foot_points(sampled, f)[..., 2] - view.foot_radius[f]).min(axis=1)
        <= CONTACT_TOLERANCE
        for f in (left, right)
    }
    share = (down[left] != down[right]).mean()
    assert share > 0.05  # a run's feet alternate
    charged = evaluator.evaluate(x[None])[0].soft["paired_feet"]
    assert charged == pytest.approx(1.0 + (share - 0.05) ** 2)
    alone = targets.model_copy(update={"paired_feet": [(left, left)]})
    same = BatchEvaluator(problem.system, problem.space, alone, threads=2, cycles=1)
    assert same.evaluate(x[None])[0].soft["paired_feet"] == 0.0  # a foot is always with itself
    wrong = targets.model_copy(update={"paired_feet": [(left, "tail")]})
    with pytest.raises(UserInputError, match="tail") as error:
        BatchEvaluator(problem.system, problem.space, wrong, threads=2, cycles=1)
    assert "targets.paired_feet" in str(error.value)


def test_process_and_ray_evaluators_agree_with_threads(problem):
    X = population(problem, 4, seed=1)
    reference = BatchEvaluator(
        problem.system, problem.space, problem.sketch.targets, threads=2
    ).evaluate(X)
    processes = ProcessEvaluator(problem.sketch, workers=2)
    try:
        by_process = processes(X)
    finally:
        processes.close()
    import ray

    ray_eval = RayEvaluator(problem.sketch, workers=2)
    try:
        by_ray = ray_eval(X)
    finally:
        ray_eval.close()
        ray.shutdown()
    for a, b, c in zip(reference, by_process, by_ray):
        assert a.cost == pytest.approx(b.cost, rel=1e-9) == pytest.approx(c.cost, rel=1e-9)
        np.testing.assert_allclose(a.cycle, c.cycle, atol=1e-9)


def test_adaptive_augmented_lagrangian_meets_the_cyclic_constraint(tmp_path):
    settings = AlSettings(seed=3, inner_generations=200, cycle_tolerance=1e-3)
    state = MomState(x_start=np.full(5, 0.5))
    optimizer = make_optimizer(toy_evaluate, settings, state)
    generations = 0
    while optimizer.step() is not None:
        generations += 1
        if generations == 5:  # checkpoints survive the AL's own state
            save_state(state, tmp_path / "al.npz")
            state = load_state(tmp_path / "al.npz")
            optimizer = make_optimizer(toy_evaluate, settings, state)
    assert state.finished == "cyclic"
    np.testing.assert_allclose(state.best_x[:2], 0.7, atol=1e-3)


@pytest.mark.parametrize("mechanisms", [[], ["hip"], ["modal"], ["hip", "modal"]])
def test_the_gain_count_matches_the_parameter_space(problem, mechanisms):
    sketch = problem.sketch.model_copy(
        update={"feedback": problem.sketch.feedback.model_copy(update={"mechanisms": mechanisms})}
    )
    space = ParameterSpace(problem.system, sketch)
    assert feedback_gain_count(sketch) == sum(e.name.startswith("fb/") for e in space.entries)


@pytest.mark.parametrize("preset", ["canonical-basis", "dog-trot"])
def test_initial_states_stay_within_the_simulations_speed_limit(preset):
    """A canonical sketch's initial state spans the lowest modes only (its numbers are joint dofs,
    not modes), and however many fast modes sit at their bounds, q̇₀ stays within what a controller
    file accepts."""
    from eigengait.sim.stepping import MAX_SPEED

    sketch = load_sketch(resolve("sketch", preset))
    # every air mode in the initial state, as a canonical dog sketch once had
    if preset == "dog-trot":
        sketch = sketch.model_copy(update={"air": sketch.air.model_copy(update={"allowed": None})})
    space = Problem.from_sketch(sketch).space
    if sketch.basis == "canonical":
        assert space.pose_modes == list(range(1, sketch.initial.modes + 1))
    for corner in (np.zeros(space.size), np.ones(space.size)):
        assert np.abs(space.decode(corner).qvel0).max() <= MAX_SPEED


def test_no_initial_pose_starts_inside_the_floor():
    """The lowest root height the space allows would sink the feet 15 cm into the floor (a launch no
    torque paid for, which the optimizer used to exploit); decoded poses are lifted onto it instead:
    touching, not inside."""
    from eigengait.sim.limits import floor_penetration

    space = Problem.from_sketch(load_sketch(resolve("sketch", "vertical-rotation"))).space
    model = space.system.world.model
    x = space.initial()
    x[space.index["root_height"]] = 0.0  # −0.15 m
    lowered = space.decode(x)
    assert floor_penetration(model, lowered.qpos0, space.floor_geom) == pytest.approx(0.0, abs=1e-9)
    # on the floor
    assert lowered.qpos0[2] == pytest.approx(space.decode(space.initial()).qpos0[2], abs=2e-3)
    for x in np.random.default_rng(5).random((20, space.size)):
        assert floor_penetration(model, space.decode(x).qpos0, space.floor_geom) < 1e-9
