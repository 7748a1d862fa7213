"""The `cloth` command line: runs, examples, modes, and one-line errors with exit status 2."""

import subprocess
import sys

import pytest
from typer.testing import CliRunner

from eigengait.cli import build_app
from eigengait.cloth.library import EXAMPLES

runner, app = CliRunner(), build_app()


def test_examples_lists_all_six():
    result = runner.invoke(app, ["cloth", "examples"])
    assert result.exit_code == 0
    for name in EXAMPLES:
        assert name in result.output


@pytest.mark.parametrize("name", ["curtain", "paper", "wind", "theatre", "cardboard", "tablecloth"])
def test_every_example_runs_briefly(name, tmp_path):
    result = runner.invoke(
        app, ["cloth", "run", name, "-o", str(tmp_path), "--duration", "1", "--no-render"]
    )
    assert result.exit_code == 0, result.output
    assert not (tmp_path / ".incomplete").exists()
    frames = sorted(p.name for p in tmp_path.glob("*_1.OBT"))
    assert frames and (tmp_path / "obj").is_dir()


def test_run_renders_pngs_and_video(tmp_path):
    result = runner.invoke(
        app,
        [
            "cloth",
            "run",
            "tablecloth",
            "-o",
            str(tmp_path),
            "--duration",
            "1",
            "--integrator",
            "implicit",
            "--time-step",
            "0.01",
            "--video-fps",
            "4",
        ],
    )
    assert result.exit_code == 0, result.output
    assert (tmp_path / "toalha_2.OBT").exists() and (tmp_path / "obj" / "toalha_2.obj").exists()
    assert len(list((tmp_path / "png").glob("*.png"))) == 3
    assert (tmp_path / "tablecloth.mp4").stat().st_size > 1000


def write(tmp_path, text):
    path = tmp_path / "bad.PAR"
    path.write_text(text)
    return path


GOOD = (
    "DURACAO = 1\nQUADROS_SEG = 1\nDELTA_t = 0.01\nNUM_SUPERFICIES = 1\nSUPERFICIE s\n"
    "MALHA (3 3)\nDENSIDADE = 1\nMASSA = 1\nCONST_ELASTICIDADE (10 10 "
    "10)\nRESTRICOES\nPONTOS_FIXOS = 1\n0 0\n"
    "FIM_RESTRICOES\nFIM_SUPERFICIE\n"
)


@pytest.mark.parametrize(
    "text, needle",
    [
        (GOOD.replace("MASSA", "MASA"), "line 8"),
        (GOOD.replace("0 0\n", "5 0\n"), "line 12"),
        (
            GOOD.replace(
                "NUM_SUPERFICIES = 1\n", "OBJETOS_NA_CENA = 1\nmissing.obt\nNUM_SUPERFICIES = 1\n"
            ),
            "missing.obt",
        ),
        (
            GOOD.replace("DELTA_t = 0.01", "DELTA_t = 0.1")
            .replace("DURACAO = 1", "DURACAO = 5")
            .replace("(10 10 10)", "(1e5 1e5 1e5)"),
            "diverged",
        ),
    ],
)
def test_bad_input_exits_2_with_one_line(tmp_path, text, needle):
    out = tmp_path / "out"
    result = runner.invoke(
        app,
        [
            "cloth",
            "run",
            str(write(tmp_path, text)),
            "-o",
            str(out),
            "--no-render",
            "--dissertation",
        ],
    )
    assert result.exit_code == 2
    assert "Traceback" not in result.output
    assert needle in result.output
    assert not list(out.rglob("*.OBT")) if out.exists() else True


def test_blow_up_warns_first_and_leaves_no_frames(tmp_path):
    text = (
        GOOD.replace("DELTA_t = 0.01", "DELTA_t = 0.1")
        .replace("DURACAO = 1", "DURACAO = 5")
        .replace("(10 10 10)", "(1e5 1e5 1e5)")
    )
    result = runner.invoke(
        app,
        [
            "cloth",
            "run",
            str(write(tmp_path, text)),
            "-o",
            str(tmp_path / "o"),
            "--no-render",
            "--dissertation",
        ],
    )
    assert result.exit_code == 2
    assert "warning:" in result.output and "stable step" in result.output
    assert "--integrator implicit" in result.output and "integrator=" not in result.output
    assert "line 3: DELTA_t" in result.output
    assert not list((tmp_path / "o").rglob("*.OBT"))


def test_modes_command_writes_palette(tmp_path):
    result = runner.invoke(
        app, ["cloth", "modes", "12x12", "--palette", str(tmp_path / "m.png"), "--count", "4"]
    )
    assert result.exit_code == 0, result.output
    assert (tmp_path / "m.png").exists() and "Hz" in result.output


def test_unknown_integrator_and_example(tmp_path):
    result = runner.invoke(
        app, ["cloth", "run", "curtain", "-o", str(tmp_path), "--integrator", "verlet"]
    )
    assert result.exit_code == 2 and "verlet" in result.output
    result = runner.invoke(app, ["cloth", "run", "curtian", "-o", str(tmp_path)])
    assert result.exit_code == 2 and "curtain" in result.output


def test_module_is_runnable():
    done = subprocess.run(
        [sys.executable, "-m", "eigengait", "cloth", "examples"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 0 and "tablecloth" in done.stdout
