import numpy as np
import pytest

from eigengait.errors import UserInputError
from eigengait.render.palette import BACKGROUND, palette_image, palette_layout


def test_palette_has_one_tile_per_requested_mode(humanoid):
    world, modes = humanoid
    image = palette_image(world, modes, count=5, columns=3, tile_px=64)
    layout = palette_layout(5, 3, 64)
    assert image.shape == (*layout.size, 3)
    assert (layout.rows, layout.columns) == (2, 3)
    tiles = []
    for index in range(6):
        top, left = layout.tile_origin(index)
        tiles.append(image[top : top + 64, left : left + 64].astype(int))
    assert all(tile.std() > 10 for tile in tiles[:5])
    assert np.all(tiles[5] == BACKGROUND)  # the sixth cell stays empty
    for a in range(5):
        for b in range(a + 1, 5):
            assert np.abs(tiles[a] - tiles[b]).mean() > 0.5  # every mode looks different


def test_palette_refuses_more_modes_than_exist(humanoid):
    world, modes = humanoid
    with pytest.raises(UserInputError, match="31"):
        palette_image(world, modes, count=31, tile_px=64)


def test_only_the_moving_parts_are_coloured(humanoid):
    from eigengait.render.palette import _corners, _ghost_opacity
    from eigengait.render.video import FrameRenderer

    world, _ = humanoid
    model = world.model
    extreme = model.qpos0.copy()
    body = model.body("left_forearm").id
    joint = model.body_jntadr[body]
    adr = model.jnt_qposadr[joint]
    extreme[adr : adr + 4] = [np.cos(0.2), np.sin(0.2), 0, 0]  # the forearm turns 23°
    with FrameRenderer(world, 32, 32) as renderer:
        opacity = _ghost_opacity(renderer, _corners(world, model.qpos0), extreme, 25.0)
        owner = model.geom_bodyid[renderer.geoms]
    assert opacity[-1] == 0  # background pixels
    assert np.all(opacity[:-1][owner == body] > 0.6)
    assert np.all(opacity[:-1][owner != body] == 0)


def test_ground_palette_marks_the_pinned_toe_and_both_show_the_facing(humanoid):
    from eigengait.modal import compute_modes

    world, air = humanoid
    ground = compute_modes(world, "ground")

    def reds_and_darks(modes):
        tile = palette_image(world, modes, count=1, tile_px=128)[-128:].astype(int)
        red = (tile[..., 0] > 150) & (tile[..., 1] < 60) & (tile[..., 2] < 60)
        dark = tile.max(axis=2) < 60  # the black facing arrow (and shadow)
        return red.sum(), dark.sum()

    red_air, dark_air = reds_and_darks(air)
    red_ground, dark_ground = reds_and_darks(ground)
    assert red_air == 0 and red_ground >= 4
    assert dark_air >= 10 and dark_ground >= 10
