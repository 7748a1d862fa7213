"""The .PAR parser: every lenient variant the dissertation's scripts use, and line-numbered
errors."""

import numpy as np
import pytest

from eigengait.cloth import EXAMPLES, example_path, parse_par, read_par
from eigengait.errors import UserInputError

MINIMAL = """DURACAO = 2
QUADROS_SEG = 1
DELTA_t = 0.001
FORCA_EXTERNA (0 0 1)
ATRITO = 0.5
OBJETOS_NA_CENA = 0
NUM_SUPERFICIES = 1
SUPERFICIE pano
  MALHA (3 4)
  DENSIDADE = 1.0
  POSIC_NO_SRU (0 10 0)
  VETOR_NORMAL (0 0 1)
  MASSA = 0.1
  CONST_ELASTICIDADE (1 2 3)
  CONST_CURVATURA = 5
  RESTRICOES
    PONTOS_FIXOS = 2
    0 0
    0 3
    TRANSLACAO (1 0 0)
    INI_TRANSL = 0
    FIM_TRANSL = 1
  FIM_RESTRICOES
FIM_SUPERFICIE
"""


def test_unaccented_minimal_script_and_yup_conversion():
    s = parse_par(MINIMAL, "m.PAR")
    assert (s.duration, s.frames_per_second, s.time_step, s.friction) == (2, 1, 0.001, 0.5)
    np.testing.assert_allclose(s.external_force, [0, -1, 0])  # FLEX3D +z is the world's -y
    surf = s.surfaces[0]
    assert (surf.name, surf.rows, surf.cols) == ("pano", 3, 4)
    np.testing.assert_allclose(surf.position, [0, 0, 10])
    assert surf.stiffness == (1, 2, 3) and surf.bending == (5, 5, 5)
    assert surf.fixed == [(0, 0), (0, 3)]
    assert len(surf.translations) == 1 and surf.translations[0].end == 1


def test_accents_equals_before_tuples_and_spelling_variants():
    text = (
        MINIMAL.replace("DURACAO", "DURAÇÃO")
        .replace("FORCA_EXTERNA (", "FORÇA_EXTERNA = (")
        .replace("RESTRICOES", "RESTRICÇÕES")
        .replace("INI_TRANSL", "INL_TRANSL")
        .replace("CONST_CURVATURA = 5", "CONST_CURVATURA = (1.0 2.0 3.0)")
        .replace("SUPERFICIE pano", "SUPERFÍCIE")
    )
    s = parse_par(text)
    assert s.duration == 2 and s.surfaces[0].bending == (1, 2, 3)
    assert s.surfaces[0].name == "SUPERFICIE1"
    assert s.surfaces[0].translations[0].start == 0


def test_repeated_translation_blocks():
    text = MINIMAL.replace(
        "    FIM_TRANSL = 1\n",
        "    FIM_TRANSL = 1\n    TRANSLACAO (-2 0 0)\n    INI_TRANSL = 3\n    FIM_TRANSL = 4\n",
    )
    moves = parse_par(text).surfaces[0].translations
    assert [(m.start, m.end) for m in moves] == [(0, 1), (3, 4)]
    np.testing.assert_allclose(moves[1].step, [-2, 0, 0])


def test_linear_fixed_point_indices_as_printed_in_the_paper_example():
    paper, cardboard = read_par(example_path("paper")), read_par(example_path("cardboard"))
    assert paper.surfaces[0].fixed == cardboard.surfaces[0].fixed
    assert paper.surfaces[0].fixed[-1] == (6, 9)


@pytest.mark.parametrize("name", list(EXAMPLES))
def test_every_shipped_example_parses(name):
    s = read_par(example_path(name))
    assert s.time_step == 0.001 and s.surfaces


@pytest.mark.parametrize(
    "edit, line, words",
    [
        (("ATRITO = 0.5", "ATRITOS = 0.5"), 5, "unknown keyword"),
        (("    0 3\n", "    0 4\n"), 19, "outside the 3x4 grid"),
        (("DELTA_t = 0.001\n", ""), None, "DELTA_T"),
        (("MASSA = 0.1", "MASSA = abc"), 13, "expects a number"),
        (("PONTOS_FIXOS = 2", "PONTOS_FIXOS = 3"), 20, "fixed point"),
        (("NUM_SUPERFICIES = 1", "NUM_SUPERFICIES = 2"), 7, "NUM_SUPERFICIES says 2"),
        (("  MALHA (3 4)\n", ""), 15, "MALHA"),
    ],
)
def test_errors_name_file_and_line(edit, line, words):
    with pytest.raises(UserInputError) as info:
        parse_par(MINIMAL.replace(*edit), "bad.PAR")
    message = str(info.value)
    assert "bad.PAR" in message and words in message
    if line is not None:
        assert f"line {line}:" in message


def test_truncated_script_reports_end_of_file():
    with pytest.raises(UserInputError, match="ends where"):
        parse_par(MINIMAL.split("FIM_RESTRICOES")[0], "cut.PAR")


def test_missing_script_file(tmp_path):
    with pytest.raises(UserInputError, match="cannot read"):
        read_par(tmp_path / "none.PAR")
