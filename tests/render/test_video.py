import numpy as np
import pytest

from eigengait.errors import UserInputError
from eigengait.motion.modal_mix import build_mix, mix_trajectory, parse_mix
from eigengait.render.video import FrameRenderer, iter_frames, render_video


@pytest.fixture(scope="module")
def leg_swing(humanoid):
    """Mode 2 (legs swing) sampled at 0, ¼ and ½ of its period."""
    world, modes = humanoid
    mix = build_mix(world, modes, parse_mix("2:2"))
    quarter = 1 / (4 * mix.frequencies_hz[0])
    return mix_trajectory(world, mix, seconds=2 * quarter, fps=1 / quarter)[1]


def test_frames_show_the_character_and_its_motion(humanoid, leg_swing):
    world, _ = humanoid
    with FrameRenderer(world, 160, 120) as renderer:
        first, moved = renderer.render(leg_swing[0]), renderer.render(leg_swing[1])
        empty = world.model.qpos0.copy()
        empty[:3] += [0, 0, 50.0]      # lift the creature far above the camera: only the floor remains
        floor = renderer.render(empty)
    assert first.shape == (120, 160, 3) and first.dtype == np.uint8
    assert first.std() > 10
    character = np.abs(first.astype(int) - floor.astype(int)).max(axis=2) > 40
    assert 0.02 < character.mean() < 0.5                                 # visible, and not filling the frame
    rows, cols = np.nonzero(character)
    assert 0.25 < cols.mean() / 160 < 0.75 and 0.25 < rows.mean() / 120 < 0.75   # framed near the centre
    assert rows.max() > 0.6 * 120                                       # feet in the lower part, on the floor
    changed = np.abs(moved.astype(int) - first.astype(int)).max(axis=2) > 40
    assert changed.mean() > 0.005


def test_mp4_is_h264_yuv420p_and_gif_loops(humanoid, leg_swing, tmp_path):
    import imageio.v2 as imageio
    from PIL import Image

    world, _ = humanoid
    assert render_video(world, leg_swing, 10, tmp_path / "a.mp4", 96, 64) == 3
    reader = imageio.get_reader(tmp_path / "a.mp4")
    meta = reader.get_meta_data()
    assert meta["codec"] == "h264" and meta["pix_fmt"].startswith("yuv420p") and meta["size"] == (96, 64)
    assert sum(1 for _ in reader) == 3
    reader.close()
    assert render_video(world, leg_swing, 10, tmp_path / "a.gif", 96, 64) == 3
    with Image.open(tmp_path / "a.gif") as gif:
        assert gif.n_frames == 3 and gif.size == (96, 64) and gif.info.get("loop") == 0


def test_bad_sizes_and_formats_are_refused(humanoid, leg_swing, tmp_path):
    world, _ = humanoid
    with pytest.raises(UserInputError):
        next(iter_frames(world, leg_swing, 101, 64))
    with pytest.raises(UserInputError):
        render_video(world, leg_swing, 10, tmp_path / "a.avi", 96, 64)
    assert not (tmp_path / "a.avi").exists()
