"""The reference-free mode: `eigengait balance` through the CLI, its push syntax and push
counting."""

import json

import pytest
import typer
from typer.testing import CliRunner

from eigengait.cli.balance import register
from eigengait.control.balance.pushes import sideways_pushes
from eigengait.control.playback import pushes_survived
from eigengait.errors import UserInputError


def _invoke(*args):
    """`eigengait balance walker ARGS` through the CLI; the runner's result."""
    app = typer.Typer()
    register(app)
    app.command("noop")(lambda: None)
    return CliRunner().invoke(app, ["balance", "walker", *args])


def _balance(*args):
    result = _invoke("--json", *args)
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


def test_a_half_newton_second_per_kg_push_is_survived_at_robustness_half():
    out = _balance("--robustness", "0.5", "--push", "350@0.2", "--duration", "2.2")
    assert out["character"] == "walker" and out["pose"] == "default" and out["robustness"] == 0.5
    assert (
        out["fell"] is False
        and out["fall_time_s"] is None
        and out["duration_s"] == pytest.approx(2.2, abs=1e-3)
    )
    assert out["at_rest"] is True and out["end_speed_mps"] < 0.05
    assert out["pushes_given"] == 1 and out["pushes_survived"] == 1
    push = out["pushes"][0]
    assert push["force_n"] == 350 and push["time_s"] == 0.2 and push["body"] == "pelvis"
    assert push["impulse_n_s_per_kg"] == pytest.approx(35.0 / out["mass_kg"], abs=1e-3)
    assert push["impulse_n_s_per_kg"] >= 0.5  # the target: 0.5 N·s/kg at robustness 0.5
    assert out["com_error_m"] < 0.05 and out["joint_rms_deg"] < 2.0
    assert out["artificial_torque"] > 0.0 and out["foot_skate_m"] < 0.05
    assert (out["foot_radius_m"], out["foot_com_height_m"], out["foot_friction"]) == (
        0.1,
        0.05,
        1.0,
    )


def test_with_no_artificial_torque_the_walker_stands_still():
    """Robustness 0, no push: physics alone holds the pose. The stance legs used to press the feet
    apart (each holding the moment of its load about its own foot), the feet crept outward and at
    about 3 s the load tipped onto one foot: COM error 7 cm, joint RMS 3°, still moving at 4 s."""
    out = _balance("--robustness", "0", "--duration", "4")
    assert out["fell"] is False and out["at_rest"] is True
    assert out["com_error_m"] < 0.005 and out["joint_rms_deg"] < 0.5
    assert out["foot_skate_m"] < 0.005 and out["artificial_torque"] == 0.0


def test_without_artificial_torque_the_qp_controller_recovers_from_the_target_push():
    """Robustness 0 (physics alone, no artificial torque): the whole-body controller recovers from
    the 0.5 N·s/kg push that the issue asks of robustness 0.5 (the momentum controller, at 0, does
    not recover from 100 N)."""
    out = _balance("--robustness", "0", "--push", "350@0.2", "--duration", "2.2")
    assert out["controller"] == "qp" and out["artificial_torque"] == 0.0
    assert out["pushes"][0]["impulse_n_s_per_kg"] >= 0.5
    assert out["fell"] is False and out["at_rest"] is True


def test_a_foot_model_of_no_size_cancels_no_horizontal_torque():
    # the foot model is the momentum controller's; pushed, so that the balance asks more of the
    # feet than they carry (standing still it does not)
    pushed = ("--controller", "momentum", "--robustness", "0.5", "--push", "350@0.1")
    pushed += ("--duration", "0.3")
    out = _balance(*pushed, "--foot-radius", "0", "--foot-height", "0")
    assert out["foot_radius_m"] == 0 and out["foot_com_height_m"] == 0
    # ‖τ_comp‖ = GRF_max (h cos θ + r sin θ) = 0: only R × the vertical (yaw) torque is still
    # cancelled, a small part of what the sized foot cancels (measured: 2.0 against 64 N·m on
    # average)
    sized = _balance(*pushed)
    assert sized["artificial_torque"] > 10.0
    assert out["artificial_torque"] < 0.1 * sized["artificial_torque"]
    # standing still, unpushed, the no-size foot cancels nothing worth naming
    still = _balance(
        "--robustness", "0.5", "--foot-radius", "0", "--foot-height", "0", "--duration", "0.3"
    )
    assert still["artificial_torque_max"] < 1.0


def test_a_huge_push_fells_the_character_soon_after_it():
    out = _balance("--robustness", "0.5", "--push", "5000@0.1", "--duration", "1.2")
    assert out["fell"] is True and 0.1 < out["fall_time_s"] < 1.2
    assert out["duration_s"] == pytest.approx(out["fall_time_s"])
    assert out["pushes_given"] == 1 and out["pushes_survived"] == 0 and out["at_rest"] is False


def test_pushes_use_the_play_syntax_and_come_out_in_time_order_along_y():
    pushes = sideways_pushes(["100@0.5,-200@1.5", "50@0.2"], "pelvis")
    assert [p.time_s for p in pushes] == [0.2, 0.5, 1.5]
    assert [p.force for p in pushes] == [(0.0, 50.0, 0.0), (0.0, 100.0, 0.0), (0.0, -200.0, 0.0)]
    assert {p.body for p in pushes} == {"pelvis"}


@pytest.mark.parametrize(
    "text", ["lots", "100", "100@", "@1", "100@-1", "100@nan", "1e9@1", "100@1,"]
)
def test_malformed_pushes_name_the_parameter_and_the_syntax(text):
    with pytest.raises(UserInputError) as err:
        sideways_pushes([text], "pelvis")
    assert err.value.field == "push"  # the command line shows it as --push
    assert "FORCE@TIME" in str(err.value) or "out of range" in str(err.value)


def test_a_push_is_survived_when_the_fall_comes_after_the_next_one():
    assert pushes_survived([1.0, 2.0], None) == 2
    # fell after the second push: the first was survived
    assert pushes_survived([2.0, 1.0], 2.5) == 1
    assert pushes_survived([1.0, 2.0], 1.05) == 0  # fell during the first push
    assert pushes_survived([], 0.3) == 0


def test_an_unknown_controller_is_refused_before_any_simulation():
    result = _invoke("--controller", "pid")
    assert result.exit_code != 0 and isinstance(result.exception, UserInputError)
    assert result.exception.field == "controller" and "qp" in str(result.exception)


def _balance_model(model, *args):
    """`eigengait balance MODEL --json ARGS` on a user's MJCF file; its JSON."""
    app = typer.Typer()
    register(app)
    app.command("noop")(lambda: None)
    result = CliRunner().invoke(app, ["balance", str(model), "--json", *args])
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


def test_dm_control_humanoids_stand_without_stiffness_in_their_files():
    """The suite's humanoid (no joint stiffness: the tracker's springs are off anyway) survives a
    0.5 N·s/kg push; the CMU humanoid, whose root frame is turned 90° about x in its zero pose,
    stands (it read as upside down, a fall at its first step)."""
    from shared_data import DM_CONTROL

    suite = DM_CONTROL / "suite"
    out = _balance_model(suite / "humanoid.xml", "--push", "204@0.5", "--duration", "2")
    assert out["mass_kg"] == pytest.approx(40.84, abs=0.01)
    assert out["pushes"][0]["impulse_n_s_per_kg"] == pytest.approx(0.5, abs=0.01)
    assert out["fell"] is False and out["pushes_survived"] == 1
    out = _balance_model(suite / "humanoid_CMU.xml", "--duration", "1")
    assert out["fell"] is False and out["duration_s"] == pytest.approx(1.0, abs=1e-3)


def test_a_planar_model_is_refused_with_its_root_named():
    """dm_control's planar walker moves its root on two slides and a hinge: the 3D balance
    controller cannot act on it (its torques came out NaN at the first step); one error names the
    file, the root body and the fix."""
    from shared_data import DM_CONTROL

    app = typer.Typer()
    register(app)
    app.command("noop")(lambda: None)
    model = DM_CONTROL / "suite" / "walker.xml"
    result = CliRunner().invoke(app, ["balance", str(model), "--duration", "0.1"])
    error = result.exception
    assert result.exit_code != 0 and isinstance(error, UserInputError)
    assert error.file == str(model) and error.field == "body 'torso'"
    assert "rootz, rootx, rooty" in error.message and "<freejoint/>" in error.fix
