"""The locomotion commands as a user runs them: sketch, optimize (resume, refusal), play, bad
input."""

import csv
import json

import pytest
import yaml

from eigengait.control.library import resolve


def write_sketch(tmp_path, **changes):
    data = yaml.safe_load(resolve("sketch", "basic-run").read_text())
    for path, value in changes.items():
        node = data
        keys = path.split(".")
        for k in keys[:-1]:
            node = node[k]
        node[keys[-1]] = value
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


@pytest.mark.parametrize(
    "change, message",
    [
        ({"air.priority": {99: 10.0}}, "mode 99 does not exist"),
        ({"ground.excluded": [2]}, "both priority and excluded"),
        ({"timing.period": 0.0}, "timing.period"),
        ({"timing.air_ratio": 1.5}, "timing.air_ratio"),
        ({"character": "dragon"}, "unknown character"),
    ],
)
def test_invalid_sketches_exit_2_with_one_message(tmp_path, eigengait_cli, change, message):
    path = write_sketch(tmp_path, **change)
    result = eigengait_cli("sketch", path, "--seconds", "0.2")
    assert result.returncode == 2
    assert message in result.stderr.replace("\n", "") and "Traceback" not in result.stderr


def test_optimize_resume_and_play(tmp_path, eigengait_cli):
    run = tmp_path / "run"
    first = eigengait_cli(
        "optimize", "basic-run", "-o", run, "--max-evaluations", "40", "--seed", "2"
    )
    assert first.returncode == 0, first.stderr
    for name in (
        "sketch.yaml",
        "settings.json",
        "log.csv",
        "checkpoint.npz",
        "best_controller.json",
        "objective.png",
        "violation.png",
    ):
        assert (run / name).exists(), name
    rows = (run / "log.csv").read_text().splitlines()
    # the figures printed are the whole run's: both stages, each stopped after the generation that
    # spent its share of the budget
    last = [list(csv.DictReader(open(run / stage / "log.csv")))[-1] for stage in ("open-loop", ".")]
    spent = [int(row["evaluations"]) for row in last]
    generations = sum(int(row["generation"]) for row in last)
    assert all(spent) and f"{sum(spent)} evaluations, {generations} generations" in first.stdout
    before = (run / "best_controller.json").read_text()
    again = eigengait_cli("optimize", "basic-run", "-o", run, "--max-evaluations", "40")
    assert again.returncode == 2 and "--resume" in again.stderr and "--force" in again.stderr
    assert (run / "best_controller.json").read_text() == before  # nothing overwritten
    other_seed = eigengait_cli(
        "optimize", "basic-run", "-o", run, "--max-evaluations", "80", "--resume", "--seed", "3"
    )
    assert other_seed.returncode == 2 and "--seed 2" in other_seed.stderr
    other_sketch = eigengait_cli(
        "optimize", "crouched", "-o", run, "--max-evaluations", "80", "--resume"
    )
    assert other_sketch.returncode == 2 and "another sketch" in other_sketch.stderr
    resumed = eigengait_cli(
        "optimize", "basic-run", "-o", run, "--max-evaluations", "80", "--resume"
    )
    assert resumed.returncode == 0, resumed.stderr
    assert len((run / "log.csv").read_text().splitlines()) > len(rows)
    assert json.loads((run / "settings.json").read_text())["settings"]["seed"] == 2
    assert json.loads((run / "status.json").read_text())["finished"] is True
    restarted = eigengait_cli(
        "optimize", "basic-run", "-o", run, "--max-evaluations", "20", "--force"
    )
    assert restarted.returncode == 0, restarted.stderr
    assert json.loads((run / "settings.json").read_text())["settings"]["seed"] == 1
    assert not list(run.rglob(".*.part.*"))

    played = eigengait_cli(
        "play", run / "best_controller.json", "--cycles", "2", "--json", "--no-lookahead"
    )
    assert played.returncode == 0, played.stderr
    out = json.loads(played.stdout)
    for key in (
        "cycles_completed",
        "fell",
        "mean_speed_mps",
        "active_energy",
        "cost_of_transport",
        "cycle_violation",
    ):
        assert key in out
    assert isinstance(out["fell"], bool) and out["cycles_completed"] <= 2
    # the controller remembers its sketch's modes, so play shows how much of the gait is still the
    # sketch
    sketch = yaml.safe_load((run / "sketch.yaml").read_text())
    kept = json.loads((run / "best_controller.json").read_text())["sketch"]
    assert {int(m) for m in kept["ground"]["priority"]} == {
        int(m) for m in sketch["ground"]["priority"]
    }
    assert sum(out["energy_split"].values()) == pytest.approx(1.0, abs=1e-3)
    assert 0 < out["psi_priority_share"] <= 1 and -1 <= out["psi_cosine"] <= 1


def test_controller_for_another_relax_pose_is_refused(tmp_path, eigengait_cli):
    run = tmp_path / "run"
    assert (
        eigengait_cli("optimize", "basic-run", "-o", run, "--max-evaluations", "20").returncode == 0
    )
    controller = json.loads((run / "best_controller.json").read_text())
    controller["relax_pose"] = "crouched"
    bad = tmp_path / "crouched.json"
    bad.write_text(json.dumps(controller))
    result = eigengait_cli("play", bad, "--json")
    assert result.returncode == 2 and "was made for character" in result.stderr.replace("\n", "")
    # the same character and pose whose model has changed since: said so, with the frequencies
    controller = json.loads((run / "best_controller.json").read_text())
    controller["air_frequencies_hz"] = [1.1 * f for f in controller["air_frequencies_hz"]]
    changed = tmp_path / "changed.json"
    changed.write_text(json.dumps(controller))
    result = eigengait_cli("play", changed, "--json")
    message = " ".join(result.stderr.split())
    assert result.returncode == 2 and "have changed since" in message
    shipped = ", ".join(f"{f:.2f}" for f in controller["air_frequencies_hz"][:3])
    assert f"air modes at {shipped} Hz" in message
    (tmp_path / "broken.json").write_text("{ not json")
    result = eigengait_cli("play", tmp_path / "broken.json")
    assert result.returncode == 2 and "cannot parse" in result.stderr


def test_corrupt_checkpoint_via_cli_leaves_files_alone(tmp_path, eigengait_cli):
    run = tmp_path / "run"
    assert (
        eigengait_cli("optimize", "basic-run", "-o", run, "--max-evaluations", "20").returncode == 0
    )
    (run / "checkpoint.npz").write_bytes(b"garbage")
    log = (run / "log.csv").read_text()
    result = eigengait_cli(
        "optimize", "basic-run", "-o", run, "--max-evaluations", "60", "--resume"
    )
    assert result.returncode == 2 and "corrupt" in result.stderr
    assert (run / "log.csv").read_text() == log


def test_nothing_to_resume_names_the_parameter_and_the_command_prints_the_flag(
    tmp_path, eigengait_cli
):
    from eigengait.control.sketch import load_sketch
    from eigengait.errors import UserInputError
    from eigengait.optimize.mom import MomSettings
    from eigengait.optimize.run import optimize

    sketch = load_sketch(resolve("sketch", "basic-run"))
    with pytest.raises(UserInputError) as caught:
        optimize(sketch, tmp_path / "run", MomSettings(), resume=True, progress=False)
    assert "without resume=True" in caught.value.fix and "--" not in str(caught.value)
    result = eigengait_cli("optimize", "basic-run", "-o", tmp_path / "run", "--resume")
    assert (
        result.returncode == 2
        and "without --resume" in result.stderr
        and "resume=True" not in result.stderr
    )


def test_the_adaptive_al_run_records_its_method_and_only_its_settings(tmp_path, eigengait_cli):
    run = tmp_path / "run"
    result = eigengait_cli(
        "optimize", "basic-run", "-o", run, "--max-evaluations", "20", "--method", "al"
    )
    assert result.returncode == 0, result.stderr
    saved = json.loads((run / "settings.json").read_text())
    assert (
        saved["method"] == "al"
        and "penalty" not in saved["settings"]
        and "method" not in saved["settings"]
    )
    assert saved["settings"]["tol_flat_fitness"] == 1000 and saved["settings"]["tol_fun"] == 0
    resumed = eigengait_cli(
        "optimize", "basic-run", "-o", run, "--max-evaluations", "40", "--resume"
    )
    assert resumed.returncode == 0, resumed.stderr
    unknown = eigengait_cli("optimize", "basic-run", "-o", tmp_path / "other", "--method", "sqp")
    assert unknown.returncode == 2 and "field '--method'" in unknown.stderr
