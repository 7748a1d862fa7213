"""Simulation health: a blow-up is an exit-2 error naming the time and the body, and no JSON ever
holds NaN."""

from __future__ import annotations

import json

import numpy as np
import pytest

from eigengait.character.library import resolve_character
from eigengait.control.library import resolve
from eigengait.json_text import dumps
from eigengait.sim.stepping import (
    MAX_CONTROL,
    MAX_SPEED,
    blown_up_dof,
    blown_up_steps,
    first_bad_torque,
)
from test_hostile_inputs import assert_clean_refusal, run_cli

DOFS = np.array([6, 7, 8])  # motor i drives dof DOFS[i]


def first(mask: np.ndarray) -> int | None:
    rows = np.flatnonzero(mask)
    return int(rows[0]) if rows.size else None


def test_the_first_blown_up_step_and_its_dof_are_found():
    qvel = np.zeros((10, 9))
    assert first(blown_up_steps(qvel)) is None
    qvel[6, 4] = np.nan
    qvel[8, 2] = 2 * MAX_SPEED
    assert first(blown_up_steps(qvel)) == 6 and blown_up_dof(qvel, 6) == 4
    assert blown_up_dof(qvel, 8) == 2


def test_an_impossible_torque_is_found_on_its_motors_dof():
    torques = np.zeros((10, 3))
    assert first_bad_torque(torques, DOFS) is None
    torques[3, 1] = 2 * MAX_CONTROL
    torques[5, 0] = np.inf
    assert first_bad_torque(torques, DOFS) == (3, 7)


def test_a_clock_that_jumps_back_is_a_reset_blow_up():
    dt = 0.001
    times = np.arange(11) * dt
    qvel = np.zeros((10, 9))
    qvel[:, 5] = np.linspace(0, 100, 10)
    assert first(blown_up_steps(qvel, times, dt)) is None
    times[7:] = dt * np.arange(4)  # MuJoCo restarted the simulation at step 6
    assert first(blown_up_steps(qvel, times, dt)) == 6 and blown_up_dof(qvel, 6) == 5


def test_blow_ups_are_found_for_a_whole_batch_at_once():
    qvel = np.zeros((3, 10, 9))
    qvel[1, 4, 0] = np.nan
    blown = blown_up_steps(qvel)
    assert blown.shape == (3, 10) and [first(row) for row in blown] == [None, 4, None]


def test_json_text_has_no_nan_or_infinity():
    text = dumps(
        {"a": float("nan"), "b": [np.inf, np.float32(1.5)], "c": np.int64(3), "d": np.bool_(True)}
    )
    assert json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} in JSON")) == {
        "a": None,
        "b": [None, 1.5],
        "c": 3,
        "d": True,
    }


def _controller(tmp_path, scale_activations=1.0, **fields):
    data = json.loads(resolve("gait", "kangaroo-hop").read_text())
    data["activations"] = {
        f: {
            ph: {m: v * scale_activations for m, v in modes.items()} for ph, modes in phases.items()
        }
        for f, phases in data["activations"].items()
    }
    data.update(fields)
    path = tmp_path / "c.json"
    path.write_text(json.dumps(data))
    return path


def _kangaroo_without_strength(tmp_path) -> str:
    """A sidecar of the built-in kangaroo with no `strength`: its motors are limited by
    `torque_limit` only."""
    model = resolve_character("kangaroo")
    text = model.with_name("kangaroo.eigengait.yaml").read_text().replace("strength: 1.0\n", "")
    assert "strength" not in text
    out = tmp_path / "kangaroo.eigengait.yaml"
    out.write_text(f"model: {model}\n{text}")
    return str(out)


def test_a_blow_up_during_play_names_time_and_body(tmp_path, capsys, monkeypatch):
    # the built-in one's strength would clip the torques
    character = _kangaroo_without_strength(tmp_path)
    path = _controller(tmp_path, scale_activations=1e7, torque_limit=1e9, character=character)
    code, err = run_cli(capsys, monkeypatch, ["play", path, "--cycles", "1", "--json"])
    assert_clean_refusal(code, err)
    assert "blew up at t = " in err and "body '" in err and "c.json" in err
    assert capsys.readouterr().out == ""  # nothing printed as a result


@pytest.mark.parametrize(
    "fields", [{"initial_qvel": [1e8]}, {"torque_limit": 1e12}], ids=["runaway-speed", "torque"]
)
def test_controllers_beyond_what_simulation_takes_are_refused(
    fields, tmp_path, capsys, monkeypatch
):
    data = json.loads(resolve("gait", "kangaroo-hop").read_text())
    if "initial_qvel" in fields:
        fields = {"initial_qvel": fields["initial_qvel"] + data["initial_qvel"][1:]}
    code, err = run_cli(
        capsys, monkeypatch, ["play", _controller(tmp_path, **fields), "--cycles", "1"]
    )
    assert_clean_refusal(code, err)
    assert next(iter(fields)) in err


def test_nan_in_a_controller_is_refused(tmp_path, capsys, monkeypatch):
    path = _controller(tmp_path, period=float("nan"))
    assert "NaN" in path.read_text()
    code, err = run_cli(capsys, monkeypatch, ["play", path, "--cycles", "1"])
    assert_clean_refusal(code, err)
    assert "period" in err and "finite" in err


def test_a_sketch_preview_that_blows_up_names_time_body_and_sketch(tmp_path, capsys, monkeypatch):
    import yaml

    sketch = yaml.safe_load(resolve("sketch", "kangaroo").read_text())
    sketch.update(character=_kangaroo_without_strength(tmp_path), torque_limit=1e9)
    sketch["ground"]["priority"] = {1: 1e8}
    sketch["air"]["priority"] = {1: 1e8}
    path = tmp_path / "wild.yaml"
    path.write_text(yaml.safe_dump(sketch))
    code, err = run_cli(capsys, monkeypatch, ["sketch", str(path), "--seconds", "1", "--json"])
    assert_clean_refusal(code, err)
    assert "blew up at t = " in err and "body '" in err and "wild.yaml" in err
