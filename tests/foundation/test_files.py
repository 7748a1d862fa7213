"""`files.load_model`, the one reader of validated YAML/JSON files (sidecars, mapping files): errors
name the file, the field and the caller's fix."""

import pytest

from eigengait.character.metadata import CharacterMetadata, load_metadata
from eigengait.errors import UserInputError
from eigengait.motion.retarget import load_mapping

MAPPING_FIX = (
    "write 'joints: {BVH_JOINT: MJCF_JOINT, ...}' and optionally 'axes: {x: +z, y: +x, z: +y}'."
)


def test_an_empty_sidecar_gives_the_defaults(tmp_path):
    side = tmp_path / "c.eigengait.yaml"
    side.write_text("")
    assert load_metadata(side) == CharacterMetadata()


def test_an_empty_mapping_names_the_missing_field_and_the_fix(tmp_path):
    path = tmp_path / "map.yaml"
    path.write_text("")
    with pytest.raises(UserInputError) as err:
        load_mapping(path)
    assert (err.value.file, err.value.field, err.value.fix) == (str(path), "joints", MAPPING_FIX)


def test_a_bad_sidecar_field_keeps_its_fix(tmp_path):
    side = tmp_path / "c.eigengait.yaml"
    side.write_text("eigengait: 2\n")
    with pytest.raises(UserInputError) as err:
        load_metadata(side)
    assert (err.value.field, err.value.fix) == (
        "eigengait",
        "see the sidecar format in the README (Characters)",
    )


@pytest.mark.parametrize("text", ["{ [ unclosed", "- 1\n- 2\n"])
def test_unreadable_or_non_mapping_files_name_the_file(tmp_path, text):
    for load in (load_metadata, load_mapping):
        path = tmp_path / "f.yaml"
        path.write_text(text)
        with pytest.raises(UserInputError) as err:
            load(path)
        assert err.value.file == str(path)
