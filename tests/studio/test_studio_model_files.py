"""Character files the studio opens read nothing outside its folder: includes, meshes, textures,
sidecars."""

import pytest

from eigengait.character.library import library_dir
from eigengait.errors import UserInputError
from eigengait.studio.model_files import confine_character
from eigengait.studio.sandbox import Sandbox
from eigengait.studio.state import StudioState

HUMANOID = (library_dir() / "humanoid.xml").read_text()


@pytest.fixture
def folders(tmp_path):
    """(studio folder, a folder beside it with an MJCF fragment and a mesh)."""
    root, outside = tmp_path / "studio", tmp_path / "outside"
    (root / "parts").mkdir(parents=True)
    outside.mkdir()
    (outside / "fragment.xml").write_text("<mujoco><option timestep='0.002'/></mujoco>")
    (outside / "mesh.stl").write_bytes(b"solid x\nendsolid x\n")
    return root, outside


def humanoid_with(root, name, extra):
    path = root / name
    path.write_text(HUMANOID.replace("<worldbody>", f"{extra}<worldbody>", 1))
    return path


@pytest.mark.parametrize(
    "extra",
    [
        '<include file="../outside/fragment.xml"/>',
        '<include file="{outside}/fragment.xml"/>',
        '<compiler meshdir="../outside"/><asset><mesh name="m" file="mesh.stl"/></asset>',
        '<asset><mesh name="m" file="{outside}/mesh.stl"/></asset>',
        '<asset><texture name="sky" type="skybox" fileright="/etc/hostname"/></asset>',
        '<asset><hfield name="h" file="../../etc/hostname"/></asset>',
        '<include file="parts/nested.xml"/>',
    ],
)
def test_an_mjcf_that_reads_outside_the_folder_is_refused(folders, extra):
    root, outside = folders
    (root / "parts" / "nested.xml").write_text(
        f"<mujoco><asset><mesh name='n' file='{outside}/mesh.stl'/></asset></mujoco>"
    )
    path = humanoid_with(root, "creature.xml", extra.format(outside=outside))
    state = StudioState(Sandbox(root))
    with pytest.raises(UserInputError, match="outside the studio folder"):
        state.load_character("creature.xml")
    assert state.sketch is None and not state.autosave_path.exists()
    with pytest.raises(UserInputError, match="outside the studio folder"):
        confine_character(Sandbox(root), path)


def test_a_symlink_inside_the_folder_that_leads_out_is_refused(folders):
    root, outside = folders
    (root / "parts" / "fragment.xml").symlink_to(outside / "fragment.xml")
    path = humanoid_with(root, "creature.xml", '<include file="parts/fragment.xml"/>')
    with pytest.raises(UserInputError, match="outside the studio folder"):
        confine_character(Sandbox(root), path)


def test_a_sidecar_that_leads_out_is_refused(folders):
    root, outside = folders
    (outside / "creature.eigengait.yaml").write_text("feet: {}\n")
    (root / "creature.eigengait.yaml").symlink_to(outside / "creature.eigengait.yaml")
    with pytest.raises(UserInputError, match="sidecar"):
        confine_character(Sandbox(root), humanoid_with(root, "creature.xml", ""))
    (root / "named.eigengait.yaml").write_text("model: ../outside/creature.xml\n")
    with pytest.raises(UserInputError, match="model is outside"):
        confine_character(Sandbox(root), root / "named.eigengait.yaml")


def test_files_inside_the_folder_are_accepted_and_the_character_loads(folders):
    root, _ = folders
    (root / "parts" / "options.xml").write_text("<mujoco><option timestep='0.002'/></mujoco>")
    (root / "parts" / "mesh.stl").write_bytes(b"solid x\nendsolid x\n")
    humanoid_with(root, "creature.xml", '<include file="parts/options.xml"/>')
    confine_character(
        Sandbox(root),
        humanoid_with(
            root,
            "meshed.xml",
            '<compiler meshdir="parts"/><asset><mesh name="m" file="mesh.stl"/></asset>',
        ),
    )
    state = StudioState(Sandbox(root))
    state.load_character("creature.xml")
    assert state.sketch.character == str((root / "creature.xml").resolve())
