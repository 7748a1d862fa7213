"""The survival stage: its sampled pushes, its search space, and a resumed run that replays the same
search."""

import json
from dataclasses import replace

import numpy as np
import pytest

from eigengait.control.closed_loop import PUSH_SECONDS
from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_parameters
from eigengait.control.library import resolve
from eigengait.control.sketch import load_sketch
from eigengait.optimize.parameters import timing_bounds
from eigengait.optimize.survival import (
    CHECKPOINT,
    StartingFigures,
    SurvivalSettings,
    SurvivalSpace,
    generation_pushes,
    harden,
)


FIGURES = StartingFigures(speed=1.0, effort=6000.0)


@pytest.fixture(scope="module")
def kangaroo():
    path = resolve("gait", "kangaroo-hop")
    c = load_controller(path)
    system = gait_system(c, source=path)
    return system, to_parameters(c, system, path)


def test_pushes_are_reproducible_and_within_their_ranges():
    settings = SurvivalSettings(minutes=1, copies=50, push_impulse=(0.2, 0.6), seed=3)
    mass, period, horizon = 70.0, 0.5, 12
    pushes = generation_pushes(settings, 7, period, horizon, mass)
    assert pushes[0] is None and len(pushes) == 50
    impulses = np.array([abs(p.force) * PUSH_SECONDS / mass for p in pushes[1:]])
    times = np.array([p.time for p in pushes[1:]])
    assert impulses.min() >= 0.2 and impulses.max() <= 0.6
    assert times.min() >= period and times.max() <= (horizon - 3) * period
    assert {np.sign(p.force) for p in pushes[1:]} == {-1.0, 1.0}
    # common to every candidate
    assert generation_pushes(settings, 7, period, horizon, mass) == pushes
    assert generation_pushes(settings, 8, period, horizon, mass) != pushes


def test_zero_offsets_decode_to_the_starting_gait(kangaroo):
    system, start = kangaroo
    space = SurvivalSpace(system, start)
    p = space.decode(np.zeros(space.size))
    assert (p.period, p.air_ratio, p.pulse_air, p.pulse_ground) == pytest.approx(
        (start.period, start.air_ratio, start.pulse_air, start.pulse_ground)
    )
    for key, psi in start.activations.items():
        np.testing.assert_allclose(p.activations[key], psi)
    np.testing.assert_allclose(p.feedback.hip, start.feedback.hip)
    moved = space.decode(np.r_[np.zeros(4), np.ones(space.size - 4)])
    changed = [
        k for k in start.activations if not np.allclose(moved.activations[k], start.activations[k])
    ]
    assert changed and not np.allclose(moved.feedback.hip, start.feedback.hip)


def test_with_the_sketch_timing_the_search_stays_within_the_optimizer_bounds(kangaroo):
    system, start = kangaroo
    timing = load_sketch(resolve("sketch", "kangaroo")).timing
    bounds = timing_bounds(timing)
    free, kept = SurvivalSpace(system, start), SurvivalSpace(system, start, bounds)
    for push in (-10.0, 0.0, 10.0):
        z = np.zeros(free.size)
        z[:4] = push
        p, q = free.decode(z), kept.decode(z)
        for key, (low, high) in bounds.items():
            assert low <= getattr(q, key) <= high
            assert getattr(q, key) == pytest.approx(np.clip(getattr(p, key), low, high))
    # the shipped hop's period had already left the sketch's bounds: free, hardening goes further
    assert start.period < bounds["period"][0]
    z = np.zeros(free.size)
    z[0] = -10.0
    assert free.decode(z).period < 0.81 * start.period


def test_a_run_bounded_by_a_sketch_resumes_only_with_the_same_bounds(kangaroo, tmp_path):
    from eigengait.errors import UserInputError

    system, start = kangaroo
    timing = load_sketch(resolve("sketch", "kangaroo")).timing
    settings = SurvivalSettings(minutes=60, popsize=4, copies=1, horizon=4, generations=1)
    harden(system, start, FIGURES, tmp_path, settings, progress=lambda _: None, timing=timing)
    with pytest.raises(UserInputError) as caught:
        harden(system, start, FIGURES, tmp_path, settings, resume=True, progress=lambda _: None)
    assert "sketch_timing_bounds" in str(caught.value)
    resumed = replace(settings, generations=2)
    harden(system, start, FIGURES, tmp_path, resumed, True, progress=lambda _: None, timing=timing)
    generations = json.loads((tmp_path / CHECKPOINT).read_text())["generations"]
    assert len(generations) == 2


def test_a_resumed_run_continues_the_same_search(kangaroo, tmp_path):
    system, start = kangaroo
    settings = SurvivalSettings(minutes=60, popsize=4, copies=2, horizon=4, generations=3)
    harden(system, start, FIGURES, tmp_path / "straight", settings, progress=lambda _: None)
    harden(
        system,
        start,
        FIGURES,
        tmp_path / "split",
        SurvivalSettings(**{**settings.__dict__, "generations": 2}),
        progress=lambda _: None,
    )
    harden(
        system, start, FIGURES, tmp_path / "split", settings, resume=True, progress=lambda _: None
    )
    straight = json.loads((tmp_path / "straight" / "survival.json").read_text())["generations"]
    split = json.loads((tmp_path / "split" / "survival.json").read_text())["generations"]
    assert len(straight) == len(split) == 3
    np.testing.assert_allclose(straight[2]["candidates"], split[2]["candidates"])
    assert straight[2]["costs"] == pytest.approx(split[2]["costs"])


def test_resume_errors_name_the_parameter_and_the_command_line_shows_its_flag(kangaroo, tmp_path):
    from eigengait.cli.flags import for_command_line
    from eigengait.errors import UserInputError

    system, start = kangaroo
    (tmp_path / "damaged").mkdir()
    (tmp_path / "damaged" / CHECKPOINT).write_text("{")
    for folder in (tmp_path / "empty", tmp_path / "damaged"):
        with pytest.raises(UserInputError) as caught:
            harden(
                system,
                start,
                FIGURES,
                folder,
                SurvivalSettings(minutes=1),
                resume=True,
                progress=lambda _: None,
            )
        assert "without resume=True" in caught.value.fix and "--" not in str(caught.value)
        shown = str(for_command_line(caught.value))
        assert "without --resume" in shown and "resume=True" not in shown


def eigengait(*args: str):
    """Run the command line as a user does."""
    import subprocess
    import sys

    return subprocess.run(
        [sys.executable, "-m", "eigengait", *args], capture_output=True, text=True, timeout=300
    )


def test_harden_command_writes_a_playable_controller_and_refuses_to_clobber(tmp_path):
    run = tmp_path / "run"
    args = ["harden", "kangaroo-hop", "-o", str(run), "--popsize", "4"]
    done = eigengait(*args, "--max-minutes", "0.05", "--sketch", "kangaroo")
    assert done.returncode == 0, done.stderr
    assert "survival with no reset (20 cycles):" in done.stdout
    assert (run / "best_controller.json").is_file() and (run / "log.csv").is_file()
    # the sketch's timing bounds hold (the shipped hop's own period lies below them)
    low, high = timing_bounds(load_sketch(resolve("sketch", "kangaroo")).timing)["period"]
    assert low <= json.loads((run / "best_controller.json").read_text())["period"] <= high
    played = eigengait(
        "play", str(run / "best_controller.json"), "--cycles", "1", "--json", "--plans", "8"
    )
    # the file loads and plays with the lookahead it kept (a short search may still fall)
    assert played.returncode == 0, played.stderr
    out = json.loads(played.stdout)
    assert out["controller"] == str(run / "best_controller.json")
    assert out["lookahead"] is True and out["lookahead_plans"] == 8
    again = eigengait(*args)
    assert again.returncode == 2 and "--resume" in again.stderr


def test_harden_event_searches_the_sketch_modes_and_plays_without_lookahead(tmp_path):
    run = tmp_path / "run"
    done = eigengait(
        "harden",
        "kangaroo-hop",
        "-o",
        str(run),
        "--popsize",
        "4",
        "--max-minutes",
        "0.05",
        "--sketch",
        "kangaroo",
        "--event",
        "--max-tilt",
        "30",
    )
    assert done.returncode == 0, done.stderr
    saved = json.loads((run / "best_controller.json").read_text())
    sketch = load_sketch(resolve("sketch", "kangaroo"))
    event = saved["feedback"]["event"]
    assert event["speed"] == sketch.targets.mean_speed
    for phase in ("air", "ground"):
        part = getattr(sketch, phase)
        assert sorted(int(m) for m in event[phase]) == sorted({*part.priority, *part.allowed})
    assert saved["lookahead"] is None
    # the search keeps the gait's timing as it is, even where it lies outside the sketch's bounds
    low, high = timing_bounds(sketch.timing)["period"]
    own = load_controller(resolve("gait", "kangaroo-hop"))
    assert not low <= own.period <= high
    for key in ("period", "air_ratio", "pulse_air", "pulse_ground"):
        assert saved[key] == pytest.approx(getattr(own, key))
    played = eigengait("play", str(run / "best_controller.json"), "--cycles", "1", "--json")
    assert played.returncode == 0, played.stderr
    assert json.loads(played.stdout)["lookahead"] is False


def test_the_staged_event_search_adds_slip_and_paired_feet_in_its_second_stage(tmp_path):
    """Stage 1 charges survival, speed and tilt; stage 2 adds the slip and the sketch's paired feet;
    both search the sketch's modes and the result carries event feedback and no lookahead."""
    from eigengait.control.gait_targets import MAX_SLIP_M, MAX_TILT_DEG
    from eigengait.optimize.survival import EVENT_POPSIZE, harden_event_in_stages

    path = resolve("gait", "dog-trot")
    c = load_controller(path)
    system = gait_system(c, source=path)
    sketch = load_sketch(resolve("sketch", "dog-trot"))
    result = harden_event_in_stages(
        system, to_parameters(c, system, path), sketch, tmp_path, 0.05, progress=lambda _: None
    )
    first, second = (
        json.loads((tmp_path / stage / CHECKPOINT).read_text()) for stage in ("stage1", "stage2")
    )
    for run in (first, second):
        settings = run["settings"]
        assert settings["popsize"] == EVENT_POPSIZE and settings["max_tilt_deg"] == MAX_TILT_DEG
        assert settings["event_modes"] and settings["effort_share"] is None
    assert first["settings"]["max_slip"] is None and first["settings"]["paired_feet"] == []
    assert second["settings"]["max_slip"] == MAX_SLIP_M
    assert second["settings"]["paired_feet"] == [list(p) for p in sketch.targets.paired_feet]
    stage1 = load_controller(tmp_path / "stage1" / "best_controller.json")
    stage2 = load_controller(tmp_path / "stage2" / "best_controller.json")
    assert stage2.lookahead is None and result.feedback.event is not None
    assert stage2.feedback.event.speed == sketch.targets.mean_speed
    assert stage1.feedback.event.air.keys() == stage2.feedback.event.air.keys()


def test_only_settings_relative_to_the_starting_gait_need_its_figures(kangaroo):
    """A fixed target speed without an effort term reads nothing of the starting gait; a speed
    share or an effort term does, and refuses to start without its figures."""
    from eigengait.optimize.survival import SurvivalScorer

    system, start = kangaroo
    fixed = SurvivalSettings(minutes=1, target_speed=0.8, effort_share=None)
    assert not fixed.reads_starting_figures
    scorer = SurvivalScorer(system, start, fixed, None)
    assert scorer.target_speed == 0.8 and scorer.target_effort is None
    scorer.close()
    for relative in (replace(fixed, target_speed=None), replace(fixed, effort_share=1.2)):
        assert relative.reads_starting_figures
        with pytest.raises(ValueError, match="StartingFigures"):
            SurvivalScorer(system, start, relative, None)


def test_the_speed_weight_prices_a_shortfall_of_the_target_speed(kangaroo):
    """With a target far beyond the hop's speed, the cost grows by the weight times the shortfall
    (v* − v) / v*, and nothing else in it changes."""
    from eigengait.optimize.survival import SurvivalScorer

    system, start = kangaroo
    costs = []
    for weight in (0.0, 1.0, 3.0):
        settings = SurvivalSettings(
            minutes=1, copies=1, target_speed=10.0, effort_share=None, speed_weight=weight
        )
        scorer = SurvivalScorer(system, start, settings, None)
        costs.append(scorer.score([start], generation=0, horizon=4)[0][0])
        scorer.close()
    shortfall = costs[1] - costs[0]
    assert 0.85 < shortfall < 1.0  # the hop moves at well under 1.5 m/s
    assert costs[2] - costs[0] == pytest.approx(3 * shortfall)


def test_the_hand_on_the_root_weakens_as_candidates_survive_and_the_horizon_waits_for_it(
    kangaroo, tmp_path
):
    """Under a hand at level 2 the hop's candidates survive a 4-cycle horizon: each such generation
    weakens the hand by ASSIST_DECAY, the horizon does not grow while there is one, and the best
    candidate is the one found under the weakest hand."""
    from eigengait.optimize.survival import ASSIST_DECAY, _better

    system, start = kangaroo
    settings = SurvivalSettings(
        minutes=60, popsize=4, copies=1, horizon=4, generations=3, assist=2.0
    )
    harden(system, start, FIGURES, tmp_path, settings, progress=lambda _: None)
    generations = json.loads((tmp_path / CHECKPOINT).read_text())["generations"]
    levels = [2.0] + [g["next_assist"] for g in generations]
    assert levels[-1] < 2.0  # it weakened
    for before, after in zip(levels, levels[1:]):
        assert after == pytest.approx(before) or after == pytest.approx(before * ASSIST_DECAY)
    assert {g["next_horizon"] for g in generations} == {4}
    assert generations[-1]["best"]["assist"] == pytest.approx(min(levels[:-1]))
    best = {"assist": 1.0, "horizon": 8, "cost": 0.5}
    assert _better(0.8, 4, 0.9, best)  # a weaker hand wins over a longer horizon and a lower cost
    assert not _better(1.0, 4, 0.1, best) and _better(1.0, 8, 0.4, best)


def test_harden_assist_from_the_command_line_refuses_a_planar_root(tmp_path):
    done = eigengait(
        "harden",
        "planar-walker-walk",
        "-o",
        str(tmp_path / "run"),
        "--assist",
        "1",
        "--max-minutes",
        "0.05",
    )
    assert done.returncode == 2
    assert "planar" in done.stderr and "without --assist" in done.stderr
    bad = eigengait("harden", "kangaroo-hop", "-o", str(tmp_path / "r2"), "--assist", "-1")
    assert bad.returncode == 2 and "--assist" in bad.stderr


def test_a_run_saved_before_a_setting_existed_resumes_with_its_default(kangaroo, tmp_path):
    system, start = kangaroo
    settings = SurvivalSettings(minutes=60, popsize=4, copies=1, horizon=4, generations=1)
    harden(system, start, FIGURES, tmp_path, settings, progress=lambda _: None)
    saved = json.loads((tmp_path / CHECKPOINT).read_text())
    for added in ("speed_weight", "assist"):
        del saved["settings"][added]
    (tmp_path / CHECKPOINT).write_text(json.dumps(saved))
    again = replace(settings, generations=2)
    harden(system, start, FIGURES, tmp_path, again, resume=True, progress=lambda _: None)
    assert len(json.loads((tmp_path / CHECKPOINT).read_text())["generations"]) == 2
