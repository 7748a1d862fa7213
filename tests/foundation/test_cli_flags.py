"""Library errors name Python parameters; the command line prints the same errors with its flags."""

from __future__ import annotations

import sys

import pytest
import typer

from eigengait.cli import build_app, main
from eigengait.cli.flags import FLAGS, for_command_line
from eigengait.errors import SimulationBlowUp, UserInputError
from shared_data import MOCAP


def _stiffness_rule():
    from eigengait.character import load_character

    load_character("humanoid", stiffness="sag")


def _phase():
    from eigengait.character import load_character
    from eigengait.modal import compute_modes

    compute_modes(load_character("humanoid"), "water")


def _frame_rate():
    from eigengait.motion.resample import frame_times

    frame_times(1.0, 0.0)


def _mix():
    from eigengait.motion.modal_mix import parse_mix

    parse_mix("1")


def _robustness():
    from eigengait.motion.tracking import run_track

    run_track(MOCAP / "cmu_02_01_walk.bvh", "walker", 1.5, None, None, 1, 0.0)


def _existing_output(tmp_path):
    from eigengait.outputs import check_output

    (tmp_path / "old.png").write_text("keep")
    check_output(tmp_path / "old.png", force=False)


def _port():
    from eigengait.studio.listen import check_listen_address

    check_listen_address("127.0.0.1", 99999)


LIBRARY_CALLS = {
    "stiffness": (_stiffness_rule, "stiffness", "stiffness='auto'"),
    "phase": (_phase, "phase", None),
    "fps": (_frame_rate, "fps", "fps=30"),
    "mix": (_mix, "mix", None),
    "robustness": (_robustness, "robustness", None),
    "force": (_existing_output, None, "force=True"),
    "port": (_port, "port", "port=8090"),
}


@pytest.mark.parametrize("call, field, keyword", LIBRARY_CALLS.values(), ids=LIBRARY_CALLS.keys())
def test_a_library_error_names_its_parameter_and_no_flag(call, field, keyword, tmp_path):
    with pytest.raises(UserInputError) as caught:
        call(tmp_path) if call is _existing_output else call()
    err = caught.value
    assert "--" not in str(err), err
    if field is not None:
        assert err.field == field
    if keyword is not None:
        assert keyword in err.fix


def run_cli(capsys, monkeypatch, args) -> tuple[int, str]:
    monkeypatch.setattr(sys, "argv", ["eigengait", *map(str, args)])
    with pytest.raises(SystemExit) as stop:
        main()
    return stop.value.code, capsys.readouterr().err


def test_the_command_prints_the_same_errors_with_flags(capsys, monkeypatch, tmp_path):
    code, err = run_cli(
        capsys,
        monkeypatch,
        ["character", "export", "humanoid", "--stiffness", "sag", "-o", "x.xml"],
    )
    assert code == 2 and "field '--stiffness'" in err and "pass --stiffness auto" in err, err
    code, err = run_cli(capsys, monkeypatch, ["modes", "humanoid", "--phase", "water"])
    assert code == 2 and "field '--phase'" in err and "phase=" not in err, err
    (tmp_path / "old.png").write_text("keep")
    code, err = run_cli(capsys, monkeypatch, ["palette", "humanoid", "-o", tmp_path / "old.png"])
    assert code == 2 and "pass --force to replace it" in err and "force=True" not in err, err


def test_translation_keeps_file_fields_and_the_error_type():
    blowup = SimulationBlowUp(
        "diverged", file="a.par", field="line 3: DELTA_t", fix="or integrator='implicit'."
    )
    shown = for_command_line(blowup)
    assert type(shown) is SimulationBlowUp and shown.field == "line 3: DELTA_t"
    assert shown.fix == "or --integrator implicit." and blowup.fix == "or integrator='implicit'."
    in_file = for_command_line(UserInputError("bad", file="s.yaml", field="robustness"))
    assert in_file.field == "robustness"  # a sketch file's key, not the option
    both = for_command_line(
        UserInputError("odd size", field="width/height", fix="use e.g. width=640")
    )
    assert (
        both.field == "--width/--height"
        and both.fix == "use e.g. --width 640"
        and "--width/--height" in str(both)
    )
    other = for_command_line(UserInputError("bad", field="joints", fix='give it stiffness="10"'))
    # an MJCF attribute stays
    assert other.field == "joints" and other.fix == 'give it stiffness="10"'


def _options(command) -> set[str]:
    found = {
        o
        for p in getattr(command, "params", [])
        for o in getattr(p, "opts", []) + getattr(p, "secondary_opts", [])
    }
    for sub in getattr(command, "commands", {}).values():
        found |= _options(sub)
    return found


def test_every_flag_in_the_mapping_is_an_option_of_some_command():
    assert set(FLAGS.values()) <= _options(typer.main.get_command(build_app()))
