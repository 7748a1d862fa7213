import sys

import pytest
import typer
from typer.testing import CliRunner

import eigengait.cli
from eigengait.cli.animate import register
from eigengait.errors import UserInputError


@pytest.fixture(scope="module")
def app():
    app = typer.Typer()
    register(app)
    return app


def exit_status(app, monkeypatch, *args) -> int:
    """Run the commands through eigengait's real entry point, which turns bad input into
    status 2."""
    monkeypatch.setattr(eigengait.cli, "build_app", lambda: app)
    monkeypatch.setattr(sys, "argv", ["eigengait", *map(str, args)])
    try:
        eigengait.cli.main()
    except SystemExit as exit_:
        return exit_.code
    return 0


def test_animate_writes_bvh_and_gif(app, tmp_path):
    bvh, gif = tmp_path / "mix.bvh", tmp_path / "mix.gif"
    result = CliRunner().invoke(
        app,
        [
            "animate",
            "humanoid",
            "--mix",
            "2:1,11:0.5@90",
            "--seconds",
            "0.2",
            "--fps",
            "10",
            "--bvh",
            str(bvh),
            "--video",
            str(gif),
            "--width",
            "64",
            "--height",
            "48",
            "--base-hz",
            "0.5",
        ],
    )
    assert result.exit_code == 0, result.output
    assert bvh.read_text().startswith("HIERARCHY") and gif.stat().st_size > 0
    assert "loops every 1.000 s" in result.output


def test_bad_mode_number_exits_with_status_2(app, tmp_path, monkeypatch, capsys):
    out = tmp_path / "x.bvh"
    assert exit_status(app, monkeypatch, "animate", "humanoid", "--mix", "99:1", "--bvh", out) == 2
    assert "mode 99" in capsys.readouterr().err and not out.exists()
    result = CliRunner().invoke(app, ["animate", "humanoid", "--mix", "99:1", "--bvh", str(out)])
    assert isinstance(result.exception, UserInputError)


def test_existing_output_is_kept_unless_forced(app, tmp_path, monkeypatch, capsys):
    out = tmp_path / "palette.png"
    out.write_bytes(b"keep me")
    args = ["palette", "snake", "--modes", "2", "--tile", "48", "-o", out]
    assert exit_status(app, monkeypatch, *args) == 2
    assert "--force" in capsys.readouterr().err and out.read_bytes() == b"keep me"
    assert exit_status(app, monkeypatch, *args, "--force") == 0
    assert out.read_bytes().startswith(b"\x89PNG")


@pytest.mark.parametrize(
    "args",
    [
        ["animate", "humanoid", "--mix", "1:1"],  # nothing to write
        ["animate", "humanoid", "--mix", "1:1", "--video", "out.avi"],
        ["animate", "humanoid", "--mix", "1:one", "--bvh", "out.bvh"],
        ["palette", "humanoid", "--modes", "40", "-o", "p.png"],
        ["palette", "snake", "--phase", "sideways", "-o", "p.png"],
    ],
)
def test_bad_input_exits_with_status_2(app, tmp_path, monkeypatch, args):
    monkeypatch.chdir(tmp_path)
    assert exit_status(app, monkeypatch, *args) == 2
    assert list(tmp_path.iterdir()) == []
