"""The .OBT reader and writer."""

import numpy as np
import pytest

from eigengait.cloth.obt import Mesh, format_obt, read_obt, write_obt
from eigengait.cloth.library import example_path
from eigengait.errors import UserInputError


def test_round_trip(tmp_path):
    mesh = Mesh(
        "tri",
        np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 2.5]]),
        [[0, 1, 2]],
        [3],
        {3: (0.1, 0.2, 0.3, 0.5, 0.25, 0.125)},
    )
    write_obt(mesh, tmp_path / "t.OBT")
    back = read_obt(tmp_path / "t.OBT")
    assert back.name == "tri" and back.faces == [[0, 1, 2]] and back.face_material == [3]
    np.testing.assert_allclose(back.vertices, mesh.vertices, atol=1e-6)
    assert back.materials == mesh.materials


def test_table_is_a_box_in_zup():
    mesa = read_obt(example_path("tablecloth").parent / "mesa.obt")
    assert len(mesa.faces) == 6 and mesa.triangles.shape == (12, 3)
    # FLEX3D y is the world's z
    assert mesa.vertices[:, 2].min() == 0 and mesa.vertices[:, 2].max() == 10


def test_bad_face_index_names_the_line(tmp_path):
    text = format_obt(Mesh("t", np.eye(3), [[0, 1, 2]], [0])).replace("3 0 1 2 0", "3 0 1 7 0")
    (tmp_path / "b.obt").write_text(text)
    with pytest.raises(UserInputError, match="line 7"):
        read_obt(tmp_path / "b.obt")


def test_missing_obstacle_file(tmp_path):
    with pytest.raises(UserInputError, match="cannot read the obstacle"):
        read_obt(tmp_path / "mesa.obt")
