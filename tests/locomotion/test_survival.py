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


def test_harden_command_writes_a_playable_controller_and_refuses_to_clobber(tmp_path):
    import subprocess
    import sys

    run = tmp_path / "run"
    args = [
        sys.executable,
        "-m",
        "eigengait",
        "harden",
        "kangaroo-hop",
        "-o",
        str(run),
        "--popsize",
        "4",
    ]
    done = subprocess.run(
        [*args, "--max-minutes", "0.05", "--sketch", "kangaroo"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert "survival with no reset (20 cycles):" in done.stdout
    assert (run / "best_controller.json").is_file() and (run / "log.csv").is_file()
    # the sketch's timing bounds hold (the shipped hop's own period lies below them)
    low, high = timing_bounds(load_sketch(resolve("sketch", "kangaroo")).timing)["period"]
    assert low <= json.loads((run / "best_controller.json").read_text())["period"] <= high
    played = subprocess.run(
        [
            sys.executable,
            "-m",
            "eigengait",
            "play",
            str(run / "best_controller.json"),
            "--cycles",
            "1",
            "--json",
            "--plans",
            "8",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    # the file loads and plays with the lookahead it kept (a short search may still fall)
    assert played.returncode == 0, played.stderr
    out = json.loads(played.stdout)
    assert out["controller"] == str(run / "best_controller.json")
    assert out["lookahead"] is True and out["lookahead_plans"] == 8
    again = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert again.returncode == 2 and "--resume" in again.stderr
    other = subprocess.run(
        [*args[:5], "-o", str(tmp_path / "other"), "--sketch", "dog-trot"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    message = " ".join(other.stderr.split())
    assert other.returncode == 2 and "--sketch" in message and "'dog'" in message
    assert not (tmp_path / "other").exists()


def test_the_cost_charges_lost_speed_and_extra_effort(kangaroo):
    from eigengait.optimize.survival import SurvivalScorer

    system, start = kangaroo
    settings = SurvivalSettings(minutes=1, copies=1, horizon=4)

    def cost(speed, effort):
        scorer = SurvivalScorer(
            system, start, settings, StartingFigures(speed=speed, effort=effort)
        )
        try:
            return scorer.score([start], generation=0, horizon=4)
        finally:
            scorer.close()

    free, survived = cost(0.0, 1e12)  # no speed to keep, effort far below the reference
    assert free[0] == pytest.approx(1 - survived[0] / 4)
    # nearly all speed lost
    assert cost(100.0, 1e12)[0][0] == pytest.approx(free[0] + 0.5 * (1 - 0), abs=0.02)
    assert cost(0.0, 1.0)[0][0] > free[0] + 100  # thousands of times the reference effort


def test_the_slip_term_reads_the_slip_that_playback_reports(kangaroo):
    from eigengait.control.playback import play
    from eigengait.optimize.survival import SLIP_WEIGHT, SurvivalScorer

    system, start = kangaroo
    reported = play(system, start, cycles=4).quality["stance_slip_max_m"]
    costs = {}
    for max_slip in (None, 0.001):
        scorer = SurvivalScorer(
            system, start, SurvivalSettings(minutes=1, copies=1, max_slip=max_slip), FIGURES
        )
        try:
            costs[max_slip] = scorer.score([start], generation=0, horizon=4)[0][0]
            run = scorer.runner.run([start], 4)
            measured = scorer._slip(start, run.sensors[0, : int(run.ended[0])])
        finally:
            scorer.close()
    assert reported > 0.002  # the hop's foot slides a little: the term has something to charge
    assert measured == pytest.approx(reported, abs=1e-4)  # the same frames as playback records
    assert costs[0.001] - costs[None] == pytest.approx(
        SLIP_WEIGHT * (measured / 0.001 - 1), rel=1e-6
    )


def test_harden_event_searches_the_sketch_modes_and_plays_without_lookahead(tmp_path):
    import subprocess
    import sys

    run = tmp_path / "run"
    command = [sys.executable, "-m", "eigengait"]
    done = subprocess.run(
        [
            *command,
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
        ],
        capture_output=True,
        text=True,
        timeout=300,
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
    played = subprocess.run(
        [*command, "play", str(run / "best_controller.json"), "--cycles", "1", "--json"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert played.returncode == 0, played.stderr
    assert json.loads(played.stdout)["lookahead"] is False
