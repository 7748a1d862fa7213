"""Fabric behaviour: strain limiting, resting contact, floor, the tablecloth drape, and the added
constraints."""

import numpy as np
import pytest

from eigengait.cloth import example_path, read_obt, read_par, script_model
from eigengait.cloth.contact import _ray_triangle
from eigengait.cloth.model import surface_model
from eigengait.cloth.par import SurfaceSpec, parse_par
from eigengait.cloth.simulate import Simulation
from eigengait.cloth.strain import max_strain
from eigengait.errors import UserInputError


def curtain_at_rest(**options):
    model = script_model(read_par(example_path("curtain")))
    sim = Simulation(model, 0.001, "euler", **options)
    sim.advance(12000)
    return model, sim


def test_strain_limited_curtain_stays_within_ten_percent_at_rest():
    model, sim = curtain_at_rest()
    assert np.abs(sim.v).max() < 0.05  # at rest
    assert max_strain(sim.x, model.springs, model.spring_rest) <= 0.10 + 1e-4
    vertical = sim.x[model.surfaces[0].indices].reshape(20, 20, 3)
    length = vertical[-1, :, 2].mean() - vertical[0, :, 2].mean()
    assert -length <= 1.10 * 19 * 1.85 + 1e-6


def test_dissertation_mode_curtain_stretches_like_rubber():
    model, sim = curtain_at_rest(dissertation=True)
    assert max_strain(sim.x, model.springs, model.spring_rest) > 0.3


def test_floor_holds_a_falling_sheet_at_the_contact_gap():
    spec = SurfaceSpec(
        "s",
        5,
        5,
        0.5,
        np.array([0.0, 0.0, 1.0]),
        np.array([0.0, 0.0, 1.0]),
        0.05,
        (30.0,) * 3,
        (0, 0, 0),
    )
    model = surface_model([spec], gravity=(0, 0, -9.81), friction=0.3)
    sim = Simulation(model, 0.002, "symplectic", floor=-0.5)
    sim.advance(1000)
    np.testing.assert_allclose(sim.x[:, 2], -0.5 + sim.thickness, atol=1e-9)


def tablecloth_draped(duration=6.0):
    script = read_par(example_path("tablecloth"))
    model = script_model(script, [read_obt(p) for p in script.obstacles])
    sim = Simulation(model, 0.002, "symplectic")
    sim.advance(round(duration / 0.002))
    return model, sim


def test_tablecloth_rests_on_the_table_and_covers_its_top():
    model, sim = tablecloth_draped()
    table = model.obstacles[0]
    lo, hi = table.vertices.min(axis=0), table.vertices.max(axis=0)
    inside = ((sim.x > lo) & (sim.x < hi)).all(axis=1)
    assert not inside.any()
    top = hi[2]
    on_top = ((sim.x[:, :2] > lo[:2]) & (sim.x[:, :2] < hi[:2])).all(axis=1)
    assert on_top.sum() > 100 and (sim.x[on_top, 2] >= top + sim.thickness - 1e-9).all()
    # Seen from above, every vertex of the table top lies under the cloth (no corner pokes through).
    corners = sim.x[model.triangles]
    for vertex in table.vertices[table.vertices[:, 2] == top]:
        hits = [
            s
            for a, b, c in corners
            for hit, s, _, _ in [_ray_triangle(vertex, np.array([0.0, 0, 1]), a, b, c)]
            if hit and s > 0
        ]
        assert hits, f"table corner {vertex} is not under the cloth"
        # pushed out along the corner's bisector, so less than straight up
        assert min(hits) > 0.5 * sim.thickness


def hanging_pair(**surface):
    top = SurfaceSpec(
        "top",
        3,
        3,
        1.0,
        np.zeros(3),
        np.array([0.0, -1.0, 0.0]),
        0.1,
        (50.0,) * 3,
        (0, 0, 0),
        fixed=[(0, 0), (0, 1), (0, 2)],
    )
    low = SurfaceSpec(
        "low",
        3,
        3,
        1.0,
        np.array([0.0, 0.0, -3.0]),
        np.array([0.0, -1.0, 0.0]),
        0.1,
        (50.0,) * 3,
        (0, 0, 0),
        **surface,
    )
    return [top, low]


def test_target_point_is_fixed_where_it_arrives():
    from eigengait.cloth.par import Target

    goal = np.array([1.0, 0.0, -6.0])
    model = surface_model(
        hanging_pair(targets=[Target(2, 2, goal)]), gravity=(0, 0, -9.81), friction=0.5
    )
    sim = Simulation(model, 0.001, "symplectic", strain_limit=None)
    sim.advance(3000)
    point = model.surfaces[1].start + 8
    assert sim.model.fixed[point] and not model.fixed[point]
    np.testing.assert_allclose(sim.x[point], goal, atol=1e-12)
    np.testing.assert_allclose(sim.v[point], 0.0, atol=1e-12)


def test_attached_surface_hangs_from_the_other():
    from eigengait.cloth.par import Attachment

    held = [Attachment(0, j, "top", (2, j), 0) for j in range(3)]
    model = surface_model(hanging_pair(attachments=held), gravity=(0, 0, -9.81), friction=0.5)
    sim = Simulation(model, 0.001, "symplectic")
    sim.advance(4000)
    a, b = model.links[:, 0], model.links[:, 1]
    np.testing.assert_allclose(sim.x[a], sim.x[b], atol=1e-12)
    # 4 rows of springs, ≤ 10 %
    assert np.abs(sim.v).max() < 0.05 and sim.x[:, 2].min() > -4 * 1.1 - 1e-6


PAR = """DURACAO = 1
QUADROS_SEG = 1
DELTA_t = 0.01
PISO = -3
NUM_SUPERFICIES = 2
SUPERFICIE a
MALHA (3 3)
DENSIDADE = 1
MASSA = 1
CONST_ELASTICIDADE (10 10 10)
RESTRICOES
PONTOS_ALVO = 1
2 2 (4 -2 0)
PONTOS_PRESOS = 1
0 0 b 1 1
FIM_RESTRICOES
FIM_SUPERFICIE
SUPERFICIE b
MALHA (2 2)
DENSIDADE = 1
MASSA = 1
CONST_ELASTICIDADE (10 10 10)
FIM_SUPERFICIE
"""


def test_par_target_attachment_and_floor():
    script = parse_par(PAR)
    surface = script.surfaces[0]
    assert script.floor == -3.0
    assert (surface.targets[0].i, surface.targets[0].j) == (2, 2)
    # y-up (4, -2, 0) -> z-up
    np.testing.assert_allclose(surface.targets[0].position, [4.0, 0.0, -2.0])
    attached = surface.attachments[0]
    assert (attached.i, attached.j, attached.body, attached.point) == (0, 0, "b", (1, 1))
    model = script_model(script)
    assert model.links.tolist() == [[0, 9 + 3]]
    assert model.targets.tolist() == [8]


@pytest.mark.parametrize(
    "edit, words",
    [
        (("0 0 b 1 1", "0 0 c 1 1"), ["line 15", "no surface named 'c'"]),
        (("0 0 b 1 1", "0 0 b 5 1"), ["line 15", "outside surface 'b'"]),
        (("2 2 (4 -2 0)", "7 2 (4 -2 0)"), ["line 13", "outside the 3x3 grid"]),
        (("0 0 b 1 1", "0 0 mesa"), ["line 15", "no obstacle named 'mesa'"]),
    ],
)
def test_constraint_errors_name_the_line(edit, words):
    with pytest.raises(UserInputError) as error:
        script_model(parse_par(PAR.replace(*edit), "scene.PAR"))
    for word in words:
        assert word in str(error.value)


def test_point_attached_to_an_obstacle_sits_on_its_surface():
    from test_model import box
    from eigengait.cloth.par import Attachment

    spec = SurfaceSpec(
        "s",
        3,
        3,
        1.0,
        np.array([0.0, 0.0, 1.5]),
        np.array([0.0, -1.0, 0.0]),
        0.1,
        (50.0,) * 3,
        (0, 0, 0),
        attachments=[Attachment(2, 1, "box", None, 0)],
    )
    model = surface_model([spec], gravity=(0, 0, -9.81), obstacles=[box((-1, -1, -1), (1, 1, 0))])
    point = 2 * 3 + 1
    assert model.fixed[point]
    np.testing.assert_allclose(model.rest_positions[point], [0.0, 0.0, 0.0], atol=1e-12)


def test_run_options_for_fabric(tmp_path):
    from typer.testing import CliRunner

    from eigengait.cli import build_app

    runner, app = CliRunner(), build_app()
    ok = runner.invoke(
        app,
        [
            "cloth",
            "run",
            "tablecloth",
            "-o",
            str(tmp_path / "a"),
            "--duration",
            "0.5",
            "--no-render",
            "--strain-limit",
            "0.05",
            "--thickness",
            "0.2",
            "--floor",
            "0",
        ],
    )
    assert ok.exit_code == 0, ok.output
    assert (
        runner.invoke(
            app,
            [
                "cloth",
                "run",
                "curtain",
                "-o",
                str(tmp_path / "b"),
                "--duration",
                "1",
                "--no-render",
                "--dissertation",
            ],
        ).exit_code
        == 0
    )
    for option, value in (("--strain-limit", "-0.1"), ("--thickness", "0")):
        bad = runner.invoke(
            app,
            ["cloth", "run", "curtain", "-o", str(tmp_path / "c"), "--no-render", option, value],
        )
        assert bad.exit_code == 2 and option in bad.output and "Traceback" not in bad.output
