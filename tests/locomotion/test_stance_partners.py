"""Ground modes with several feet on the floor: a trot's diagonal pair pinned together, from the
modal analysis through the sketch, the gait system and the controller file to the CLI."""

import json

import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.control.binding import gait_system
from eigengait.control.controller import ControllerFile, to_file
from eigengait.control.gait import GaitParameters
from eigengait.control.sketch import Sketch
from eigengait.errors import UserInputError
from eigengait.modal import ModeSet, compute_modes
from eigengait.modal.reduced import point_jacobian
from eigengait.sim import WorldOptions, build_world


@pytest.fixture(scope="module")
def dog_world():
    return build_world(load_character("dog"), options=WorldOptions(gravity=False, floor=False))


def _toe_motion(world, modes: ModeSet, foot: str) -> float:
    """Largest toe velocity any unit-amplitude mode shape gives `foot`'s toe (m per unit)."""
    toe = point_jacobian(world, world.character.feet[foot].toe)
    return float(np.abs(toe @ modes.shapes).max())


def test_a_partner_foot_is_pinned_with_the_stance_foot(dog_world):
    alone = compute_modes(dog_world, "ground", "rear_left")
    paired = compute_modes(dog_world, "ground", "rear_left", partners=["front_right"])
    # two pinned points leave the body one rigid motion: the turn about the line through them
    assert (alone.rigid_modes, paired.rigid_modes) == (3, 1)
    assert paired.count == alone.count - 1
    for foot in ("rear_left", "front_right"):
        assert _toe_motion(dog_world, paired, foot) < 1e-9
    assert _toe_motion(dog_world, alone, "rear_left") < 1e-9
    assert _toe_motion(dog_world, alone, "front_right") > 1e-2
    # a stiffer problem: no mode of the pair is slower than the single pin's lowest
    assert paired.frequencies_hz[0] >= alone.frequencies_hz[0]
    assert paired.pinned_text() == "rear_left + front_right toes pinned"
    assert alone.pinned_text() == "rear_left toe pinned"


def test_partners_survive_a_saved_mode_set(dog_world, tmp_path):
    paired = compute_modes(dog_world, "ground", "rear_left", partners=["front_right"])
    paired.save(tmp_path / "pair.npz")
    loaded = ModeSet.load(tmp_path / "pair.npz")
    assert loaded.partners == ["front_right"] and loaded.pinned_feet == ["rear_left", "front_right"]
    np.testing.assert_array_equal(loaded.torque_basis, paired.torque_basis)


@pytest.mark.parametrize(
    "phase, partners, message",
    [
        ("air", ["front_right"], "only in the ground phase"),
        ("ground", ["tail"], "'tail' cannot be pinned"),
        ("ground", ["rear_left"], "'rear_left' cannot be pinned"),
    ],
)
def test_impossible_partners_are_refused(dog_world, phase, partners, message):
    with pytest.raises(UserInputError, match=message) as error:
        compute_modes(dog_world, phase, "rear_left", partners=partners)
    assert error.value.field == "partners"


def _trot_sketch(**changes) -> Sketch:
    fields = dict(
        character="dog",
        feet=["rear_left", "rear_right"],
        stance_partners={"rear_left": ["front_right"], "rear_right": ["front_left"]},
    )
    return Sketch(**{**fields, **changes})


def test_a_sketch_with_partners_gives_its_gait_the_paired_ground_modes(dog_world):
    system = gait_system(_trot_sketch())
    for foot, partner in (("rear_left", "front_right"), ("rear_right", "front_left")):
        expected = compute_modes(dog_world, "ground", foot, partners=[partner])
        np.testing.assert_allclose(system.basis_matrix(foot, "ground"), expected.torque_basis)
    # the controller file keeps the partners, so a played controller has the same bases
    count = {phase: system.mode_count(phase) for phase in ("air", "ground")}
    params = GaitParameters(
        period=0.5,
        air_ratio=0.3,
        pulse_air=0.1,
        pulse_ground=0.1,
        activations={("rear_left", p): np.zeros(count[p]) for p in ("air", "ground")},
        qpos0=system.world.model.qpos0.copy(),
        qvel0=np.zeros(system.world.model.nv),
    )
    saved = ControllerFile.model_validate(json.loads(to_file(system, params).model_dump_json()))
    assert saved.stance_partners == {"rear_left": ["front_right"], "rear_right": ["front_left"]}
    replayed = gait_system(saved)
    np.testing.assert_allclose(
        replayed.basis_matrix("rear_right", "ground"), system.basis_matrix("rear_right", "ground")
    )


def test_partners_of_a_foot_the_gait_does_not_clock_are_refused():
    with pytest.raises(UserInputError, match="front_left") as error:
        gait_system(_trot_sketch(stance_partners={"front_left": ["rear_right"]}))
    assert error.value.field == "stance_partners"


def test_a_sketch_naming_an_unknown_partner_is_blamed():
    sketch = _trot_sketch(stance_partners={"rear_left": ["tail"], "rear_right": ["front_left"]})
    with pytest.raises(UserInputError, match="'tail' cannot be pinned") as error:
        gait_system(sketch, source="my_trot.yaml")
    assert (error.value.file, error.value.field) == ("my_trot.yaml", "stance_partners.rear_left")


def test_modes_command_pins_the_partner(eigengait_cli):
    result = eigengait_cli(
        "modes", "dog", "--phase", "ground", "--foot", "rear_left", "--partner", "front_right",
        "--json",
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    out = json.loads(result.stdout)
    assert out["partners"] == ["front_right"] and out["rigid_modes"] == 1
    refused = eigengait_cli("modes", "dog", "--partner", "front_right")
    assert refused.returncode != 0 and "ground phase" in refused.stderr


@pytest.mark.parametrize(
    "partners",
    [
        {"rear_left": ["front_right"], "rear_right": ["front_right"]},
        {"rear_left": ["front_right"]},
    ],
)
def test_a_symmetric_gait_needs_mirrored_partners(partners):
    with pytest.raises(UserInputError, match="not mirror images") as error:
        gait_system(_trot_sketch(stance_partners=partners))
    assert error.value.field == "stance_partners"
    gait_system(_trot_sketch(stance_partners=partners, symmetric=False))  # each foot its own
