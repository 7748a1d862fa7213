"""Bad characters and arguments: one clear message naming the file and field, exit status 2, no
traceback."""

import json

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.errors import EigengaitError, SimulationBlowUp, UserInputError
from eigengait.modal import compute_modes
from eigengait.sim import WorldOptions, build_world
from eigengait.sim.stepping import step

GOOD_BODY = '<geom type="box" size=".1 .1 .1"/>'
CASES = {
    "malformed": ("<mujoco><worldbody><body>", "malformed MJCF"),
    "ball_root": (
        '<mujoco><worldbody><body><joint name="j" type="ball" '
        f'stiffness="5"/>{GOOD_BODY}</body></worldbody></mujoco>',
        "root joint must be a named slide or hinge",
    ),
    "reserved_name": (
        f'<mujoco><worldbody><body><freejoint/>{GOOD_BODY}<body pos="0 0 .2">'
        '<joint name="j" type="ball" stiffness="5"/><geom name="eigengait:floor" '
        'size=".1"/></body>'
        "</body></worldbody></mujoco>",
        "geom 'eigengait:floor'",
    ),
    "no_stiffness": (
        f'<mujoco><worldbody><body><freejoint/>{GOOD_BODY}<body pos="0 0 .2">'
        f'<joint name="elbow" type="ball"/>{GOOD_BODY}</body></body></worldbody></mujoco>',
        "joint 'elbow' stiffness",
    ),
    "slide_joint": (
        f'<mujoco><worldbody><body><freejoint/>{GOOD_BODY}<body pos="0 0 .2">'
        '<joint name="s" type="slide" '
        f'stiffness="5"/>{GOOD_BODY}</body></body></worldbody></mujoco>',
        "not supported",
    ),
}


@pytest.mark.parametrize("case", CASES)
def test_bad_mjcf_names_file_and_problem(tmp_path, eigengait_cli, case):
    xml, expected = CASES[case]
    path = tmp_path / f"{case}.xml"
    path.write_text(xml)
    with pytest.raises(UserInputError) as err:
        load_character(path)
    assert str(path) in str(err.value) and expected in str(err.value)
    result = eigengait_cli("modes", path, "--json")
    assert result.returncode == 2
    assert "Traceback" not in result.stderr and expected in result.stderr.replace("\n", "")


def test_bad_sidecar_field_is_named(tmp_path):
    (tmp_path / "c.xml").write_text(
        f'<mujoco><worldbody><body><freejoint/>{GOOD_BODY}<body pos="0 0 .2">'
        f'<joint name="j" type="ball" stiffness="5"/>{GOOD_BODY}</body></body>'
        "</worldbody></mujoco>"
    )
    (tmp_path / "c.eigengait.yaml").write_text("eigengait: 1\nstiffness:\n  j: [1, -2, 3]\n")
    with pytest.raises(UserInputError, match=r"c\.eigengait\.yaml.*stiffness"):
        load_character(tmp_path / "c.xml")


def test_unknown_names_exit_2(eigengait_cli):
    for args, expected in (
        (["modes", "dragon"], "unknown character"),
        (["modes", "humanoid", "--relax", "sitting"], "unknown relax pose"),
        (["modes", "humanoid", "--phase", "ground", "--foot", "tail"], "unknown foot"),
        (["modes", "humanoid", "--phase", "water"], "unknown phase"),
        (["modes", "missing.xml"], "file not found"),
    ):
        result = eigengait_cli(*args)
        assert result.returncode == 2, args
        assert expected in result.stderr and "Traceback" not in result.stderr


def test_modes_json_contract(eigengait_cli):
    result = eigengait_cli("modes", "humanoid", "--phase", "ground", "--json")
    assert result.returncode == 0, result.stderr
    out = json.loads(result.stdout)
    assert out["character"] == "humanoid" and out["phase"] == "ground" and out["dofs"] == 30
    assert out["rigid_modes"] == 3 and len(out["frequencies_hz"]) == 30
    assert out["frequencies_hz"] == sorted(out["frequencies_hz"])


def test_exported_mjcf_is_the_simulated_model(tmp_path, eigengait_cli):
    out = tmp_path / "h.xml"
    assert (
        eigengait_cli(
            "character", "export", "humanoid", "--relax", "crouched", "-o", out
        ).returncode
        == 0
    )
    exported = mujoco.MjModel.from_xml_path(str(out))
    world = build_world(load_character("humanoid"), "crouched")
    assert (exported.nv, exported.nu, exported.ngeom) == (
        world.model.nv,
        world.model.nu,
        world.model.ngeom,
    )
    # XML keeps ~7 digits
    np.testing.assert_allclose(exported.body_quat, world.model.body_quat, atol=1e-6)
    again = eigengait_cli("character", "export", "humanoid", "-o", out)
    assert again.returncode == 2 and "--force" in again.stderr  # nothing overwritten silently


def test_feetless_character_has_no_ground_phase():
    with pytest.raises(UserInputError, match="no feet"):
        compute_modes(load_character(_feetless()), "ground")


def _feetless(tmp=[]):
    import tempfile
    from pathlib import Path

    folder = Path(tempfile.mkdtemp())
    path = folder / "blob.xml"
    path.write_text(
        f'<mujoco><worldbody><body><freejoint/>{GOOD_BODY}<body pos="0 0 .2">'
        f'<joint name="j" type="ball" stiffness="5"/>{GOOD_BODY}</body></body></worldbody></mujoco>'
    )
    return path


def test_blow_up_names_time_and_body():
    world = build_world(load_character("humanoid"), options=WorldOptions(gravity=False))
    data = world.new_data()
    data.ctrl[:] = 1e9
    with pytest.raises(SimulationBlowUp, match=r"t = [0-9.]+ s.*body '") as caught:
        for _ in range(100):
            step(world, data, 10)
    assert isinstance(caught.value, EigengaitError) and not isinstance(caught.value, UserInputError)


def test_a_nan_control_is_a_blow_up_reported_at_its_time():
    # A NaN control is only a warning to MuJoCo, which drops it and steps on: it is a blow-up,
    # reported at its time (not after a reset's restarted clock) and naming the actuated body.
    world = build_world(load_character("humanoid"), options=WorldOptions(gravity=False))
    data = world.new_data()
    step(world, data, 2000)
    started = float(data.time)
    data.ctrl[0] = np.nan
    body = world.model.body(world.model.jnt_bodyid[world.model.actuator_trnid[0, 0]]).name
    with pytest.raises(SimulationBlowUp, match=rf"t = {started:.3f}\d s \(body '{body}'"):
        step(world, data, 1)
