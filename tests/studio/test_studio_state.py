"""The studio's path sandbox and shared state, without a browser."""

import os

import pytest

from eigengait.character.library import library_dir
from eigengait.control.sketch import load_sketch
from eigengait.errors import UserInputError
from eigengait.studio.sandbox import Sandbox
from eigengait.studio.state import AUTOSAVE_NAME, StudioState


@pytest.mark.parametrize(
    "outside", ["../x.xml", "/etc/passwd", "a/../../b.yaml", "~/.bashrc/../../../etc/x.xml"]
)
def test_sandbox_refuses_paths_outside_the_root(tmp_path, outside):
    with pytest.raises(UserInputError, match="outside the studio folder|not found"):
        Sandbox(tmp_path).resolve(outside, must_exist=True)


@pytest.mark.parametrize("name", ["a\x00b.yaml", "run\n.yaml", "\x1b[2Jx.yaml"])
def test_sandbox_refuses_control_characters_with_a_clean_error(tmp_path, name):
    with pytest.raises(UserInputError, match="control character"):
        Sandbox(tmp_path).resolve(name)


def test_sandbox_refuses_a_symlink_that_leaves_the_root(tmp_path):
    (tmp_path / "escape.xml").symlink_to("/etc/hostname")
    with pytest.raises(UserInputError, match="outside the studio folder"):
        Sandbox(tmp_path).resolve("escape.xml")


def test_sandbox_accepts_files_inside_and_checks_suffixes(tmp_path):
    (tmp_path / "sub").mkdir()
    assert (
        Sandbox(tmp_path).resolve("sub/../run.yaml", (".yaml",)) == tmp_path.resolve() / "run.yaml"
    )
    with pytest.raises(UserInputError, match="must end with"):
        Sandbox(tmp_path).resolve("notes.txt", (".yaml",))


def test_edits_are_autosaved_as_a_sketch_the_cli_reads(tmp_path):
    state = StudioState(Sandbox(tmp_path))
    state.open("humanoid")
    state.set_status("air", 2, "priority")
    state.set_activation("air", 2, -35.0)
    state.set_status("ground", 7, "excluded")
    state.set_timing(period=0.9)
    saved = load_sketch(tmp_path / AUTOSAVE_NAME)
    assert saved.air.priority == {2: -35.0}
    assert 7 in saved.ground.excluded and saved.timing.period == 0.9
    with pytest.raises(UserInputError, match="non-zero"):
        state.set_activation("air", 2, 0.0)
    reopened = StudioState(Sandbox(tmp_path))
    reopened.open(None)
    assert reopened.sketch == state.sketch


def test_a_character_file_in_the_folder_is_saved_relative_to_the_sketch(tmp_path):
    for name in ("humanoid.xml", "humanoid.eigengait.yaml"):
        (tmp_path / "chars").mkdir(exist_ok=True)
        (tmp_path / "chars" / name).write_bytes((library_dir() / name).read_bytes())
    state = StudioState(Sandbox(tmp_path))
    state.open("chars/humanoid.xml")
    path = state.save_sketch("sketches/mine.yaml")
    assert "character: ../chars/humanoid.xml" in path.read_text()
    assert load_sketch(path).character == str((tmp_path / "chars" / "humanoid.xml").resolve())
    state.set_relax_pose("crouched")
    assert state.sketch.relax_pose == "crouched" and state.modes("air").count == 30
    with pytest.raises(UserInputError, match="unknown relax pose"):
        state.set_relax_pose("sitting")
    assert state.sketch.relax_pose == "crouched"
    assert os.path.isfile(tmp_path / AUTOSAVE_NAME)


def test_tracking_panel_tracks_a_clip_inside_the_folder_only(tmp_path):
    import shutil

    from conftest import MOCAP_WALK, free_port
    from eigengait.studio.app import Studio

    shutil.copy(MOCAP_WALK, tmp_path / "walk.bvh")
    studio = Studio(tmp_path, "humanoid", port=free_port())
    try:
        result = studio.track_panel.track_file("walk.bvh")
        assert not result.fell and result.com_error_m < 0.15 and studio.stage.showing == "tracking"
        assert "joint RMS" in studio.track_panel.report.content
        assert "(qp controller)" in studio.track_panel.report.content
        # the controller dropdown reaches the tracker: the chapter's law tracks the same walk
        # differently (measured: joint RMS 1.4° with qp, 2.3° with momentum)
        studio.track_panel.controller.value = "momentum"
        chapter = studio.track_panel.track_file("walk.bvh")
        assert not chapter.fell and chapter.joint_rms_deg > result.joint_rms_deg + 0.3
        assert "(momentum controller)" in studio.track_panel.report.content
        with pytest.raises(UserInputError):
            studio.track_panel.track_file(str(MOCAP_WALK))  # outside the studio folder
    finally:
        studio.stop()


def test_tracking_panel_reports_a_fall_it_searched_past(tmp_path):
    # The walk's first 100 frames shoved with 5 000 N at 0.1 s: it falls at 0.28 s, the default
    # recovery searches 8 samples from the clip's start, and the report says so.
    from conftest import MOCAP_WALK, free_port
    from eigengait.studio.app import Studio
    from shared_data import clip_start

    clip_start(MOCAP_WALK, 100, tmp_path / "walk.bvh")
    studio = Studio(tmp_path, "humanoid", port=free_port())
    try:
        studio.track_panel.push.value = "5000@0.1"
        result = studio.track_panel.track_file("walk.bvh")
        assert result.fell and result.recovery_simulations == 8
        assert "Recovery: 0 fall(s) searched past in 8 simulations" in (
            studio.track_panel.report.content
        )
    finally:
        studio.stop()
