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
        tiles.append(image[top:top + 64, left:left + 64].astype(int))
    assert all(tile.std() > 10 for tile in tiles[:5])
    assert np.all(tiles[5] == BACKGROUND)                       # the sixth cell stays empty
    for a in range(5):
        for b in range(a + 1, 5):
            assert np.abs(tiles[a] - tiles[b]).mean() > 0.5     # every mode looks different


def test_palette_refuses_more_modes_than_exist(humanoid):
    world, modes = humanoid
    with pytest.raises(UserInputError, match="31"):
        palette_image(world, modes, count=31, tile_px=64)
