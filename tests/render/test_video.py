import numpy as np
import pytest

from eigengait.errors import UserInputError
from eigengait.motion.modal_mix import build_mix, mix_trajectory, parse_mix
from eigengait.render.video import CameraView, FrameRenderer, iter_frames, render_video


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
        empty[:3] += [0, 0, 50.0]  # lift the creature far above the camera: only the floor remains
        floor = renderer.render(empty)
    assert first.shape == (120, 160, 3) and first.dtype == np.uint8
    assert first.std() > 10
    character = np.abs(first.astype(int) - floor.astype(int)).max(axis=2) > 40
    assert 0.02 < character.mean() < 0.5  # visible, and not filling the frame
    rows, cols = np.nonzero(character)
    # framed near the centre
    assert 0.25 < cols.mean() / 160 < 0.75 and 0.25 < rows.mean() / 120 < 0.75
    assert rows.max() > 0.6 * 120  # feet in the lower part, on the floor
    changed = np.abs(moved.astype(int) - first.astype(int)).max(axis=2) > 40
    assert changed.mean() > 0.005


def test_mp4_is_h264_yuv420p_and_gif_loops(humanoid, leg_swing, tmp_path):
    import imageio.v2 as imageio
    from PIL import Image

    world, _ = humanoid
    assert render_video(world, leg_swing, 10, tmp_path / "a.mp4", 96, 64, fps=10) == 3
    reader = imageio.get_reader(tmp_path / "a.mp4")
    meta = reader.get_meta_data()
    assert (
        meta["codec"] == "h264"
        and meta["pix_fmt"].startswith("yuv420p")
        and meta["size"] == (96, 64)
    )
    assert sum(1 for _ in reader) == 3
    reader.close()
    assert render_video(world, leg_swing, 10, tmp_path / "a.gif", 96, 64, fps=10) == 3
    with Image.open(tmp_path / "a.gif") as gif:
        assert gif.n_frames == 3 and gif.size == (96, 64) and gif.info.get("loop") == 0


def test_bad_sizes_and_formats_are_refused(humanoid, leg_swing, tmp_path):
    world, _ = humanoid
    with pytest.raises(UserInputError):
        next(iter_frames(world, leg_swing, 101, 64))
    with pytest.raises(UserInputError):
        render_video(world, leg_swing, 10, tmp_path / "a.avi", 96, 64)
    assert not (tmp_path / "a.avi").exists()


def test_shadow_follows_a_character_far_from_the_origin():
    """Standing 4 m from the origin, the character still casts a shadow on the floor under its
    feet."""
    from eigengait.character import load_character
    from eigengait.sim.world import build_world

    world = build_world(load_character("humanoid"))
    here = world.model.qpos0.copy()
    here[0] += 4.0
    away = here.copy()
    away[2] += 50.0  # above the light: no shadow, and out of the camera's view
    with FrameRenderer(
        world, 160, 120, CameraView(azimuth_deg=100.0, elevation_deg=-24.0)
    ) as renderer:
        image, floor = renderer.render(here).astype(int), renderer.render(away).astype(int)
        renderer.renderer.enable_segmentation_rendering()
        segments = renderer.render(here)
    creature = np.isin(segments[..., 0], renderer.geoms) & (segments[..., 1] == 5)  # 5: mjOBJ_GEOM
    shadow = ~creature & ((floor - image).sum(axis=2) > 60)
    rows, cols = np.nonzero(creature)
    feet = rows > rows.max() - 6
    near_feet = shadow[rows.max() - 6 : rows.max() + 6, cols[feet].min() - 6 : cols[feet].max() + 6]
    assert near_feet.sum() >= 8
    assert shadow.sum() < 0.05 * shadow.size  # a shadow, not a darkened frame


def test_video_has_exactly_the_requested_frame_rate_and_speed(humanoid, tmp_path):
    import imageio.v2 as imageio

    world, _ = humanoid
    source_fps = 1 / (33 * 0.0005)  # 60.606…: a rounded stride of the 0.5 ms physics step
    qpos = np.repeat(world.model.qpos0[None], 62, axis=0)  # 61 intervals ≈ 1.0065 s
    assert render_video(world, qpos, source_fps, tmp_path / "a.mp4", 64, 48, fps=25) == 26
    reader = imageio.get_reader(tmp_path / "a.mp4")
    assert reader.get_meta_data()["fps"] == 25
    reader.close()
    assert (
        render_video(world, qpos, source_fps, tmp_path / "slow.gif", 64, 48, fps=20, speed=0.5)
        == 41
    )


def test_fixed_camera_shows_travel_and_frames_carry_time_and_contacts():
    from eigengait.character import load_character
    from eigengait.sim.world import build_world

    world = build_world(load_character("humanoid"))
    qpos = np.repeat(world.model.qpos0[None], 2, axis=0)
    qpos[1, 0] += 1.5
    fixed = list(iter_frames(world, qpos, 160, 120, CameraView(azimuth_deg=90.0, follow=False)))
    follow = list(iter_frames(world, qpos, 160, 120, CameraView(azimuth_deg=90.0)))

    def centre_column(frame):  # of the dark character on the light floor
        return np.nonzero(frame.astype(int).sum(axis=2) < 350)[1].mean()

    assert centre_column(fixed[1]) - centre_column(fixed[0]) > 40  # crosses the fixed frame
    # stays put in the following one
    assert abs(centre_column(follow[1]) - centre_column(follow[0])) < 3
    plain = next(iter_frames(world, qpos[:1], 160, 120))
    stamped = next(iter_frames(world, qpos[:1], 160, 120, times=np.array([0.0])))
    changed = np.abs(stamped.astype(int) - plain.astype(int)).max(axis=2) > 40
    # time stamp and foot boxes
    assert changed[:20, :60].mean() > 0.1 and changed[:20, 100:].mean() > 0.1


def test_foot_contacts_and_the_footfall_diagram():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from eigengait.character import load_character
    from eigengait.render.contacts import contact_diagram, foot_contacts
    from eigengait.sim.world import build_world

    world = build_world(load_character("humanoid"))
    standing = world.model.qpos0.copy()
    hopping = standing.copy()
    hopping[2] += 0.05  # 5 cm up: both feet in the air
    qpos = np.array([standing, standing, hopping, hopping, standing])
    flags = foot_contacts(world, qpos)
    assert flags.tolist() == [[True, True]] * 2 + [[False, False]] * 2 + [[True, True]]
    fig, ax = plt.subplots()
    contact_diagram(ax, np.arange(5) * 0.1, flags, list(world.foot_spheres), period_s=0.2)
    bars = [patch for collection in ax.collections for patch in collection.get_paths()]
    assert len(bars) == 4  # two stance spans per foot
    assert [t.get_text() for t in ax.get_yticklabels()] == ["left", "right"]
    plt.close(fig)
