"""Run outputs and pictures: real-time video, the floor, smooth shading, whole-set replacement of
frames."""

import json

import imageio_ffmpeg
import numpy as np
import pytest
from typer.testing import CliRunner

from eigengait.cloth import example_path, read_obt, read_par, script_model
from eigengait.cli import build_app
from eigengait.cloth.render import smooth_quads, vertex_normals
from eigengait.cloth.simulate import run_samples, video_steps

runner, app = CliRunner(), build_app()

SHEET = (
    "DURACAO = 2\nQUADROS_SEG = 2\nDELTA_t = 0.01\nNUM_SUPERFICIES = 1\nSUPERFICIE s\nMALHA (4 4)\n"
    "DENSIDADE = 1\nMASSA = 0.1\nCONST_ELASTICIDADE (10 10 10)\nRESTRICOES\nPONTOS_FIXOS = 2\n0 "
    "0\n0 3\n"
    "FIM_RESTRICOES\nFIM_SUPERFICIE\n"
)


def run(tmp_path, out, *args):
    script = tmp_path / "sheet.PAR"
    script.write_text(SHEET)
    return runner.invoke(
        app, ["cloth", "run", str(script), "-o", str(out), "--integrator", "symplectic", *args]
    )


def test_video_plays_in_real_time(tmp_path):
    result = run(tmp_path, tmp_path / "o", "--duration", "0.5", "--video-fps", "20")
    assert result.exit_code == 0, result.output
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(tmp_path / "o" / "sheet.mp4"))
    assert frames == 0.5 * 20 + 1  # t = 0, 1/20, …, 0.5 s; the script itself writes only 2 frames
    video = json.loads((tmp_path / "o" / "run.json").read_text())["video"]
    assert (
        video["fps"] == 20
        and video["frames"] == frames
        and video["duration_s"] == pytest.approx(11 / 20)
    )
    assert len(list((tmp_path / "o" / "png").glob("*.png"))) == 2


@pytest.mark.parametrize("h, fps", [(0.001, 30), (0.01, 24), (0.1, 30)])
def test_video_frames_sample_the_nearest_step(h, fps):
    steps = video_steps(h, 2.0, fps)
    assert len(steps) == 2 * fps + 1
    np.testing.assert_allclose(steps * h, np.arange(len(steps)) / fps, atol=h / 2 + 1e-12)


def test_tablecloth_floor_holds_the_corners_above_it():
    script = read_par(example_path("tablecloth"))
    assert script.floor == 0.0  # the table's base
    model = script_model(script, [read_obt(p) for p in script.obstacles])
    steps = np.arange(0, 3001, 250)  # 6 s at h = 2 ms
    lowest = {}
    for floor in (script.floor, None):
        frames = run_samples(
            model, steps, time_step=0.002, integrator="symplectic", floor=floor, warn=False
        )
        lowest[floor] = [f.positions[:, 2].min() for f in frames]
    assert min(lowest[None]) < -1.0  # without it the corners hang below the base
    assert min(lowest[0.0]) >= -1e-9
    assert lowest[0.0][-1] == pytest.approx(0.1, abs=1e-6)  # resting on it at the contact gap


def grid(rows, cols, surface):
    u, v = np.meshgrid(np.linspace(0, 1, rows), np.linspace(0, 1, cols), indexing="ij")
    points = surface(u.ravel(), v.ravel())
    r, c = np.meshgrid(np.arange(rows - 1), np.arange(cols - 1), indexing="ij")
    base = r.ravel() * cols + c.ravel()
    quads = np.stack([base, base + cols, base + cols + 1, base + 1], axis=1)
    return points, quads, np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])


def test_vertex_normals_of_a_flat_sheet_are_the_plane_normal():
    normal = np.array([1.0, 2.0, 2.0]) / 3
    a = np.array([2.0, -1.0, 0.0]) / np.sqrt(5)
    b = np.cross(normal, a)
    jitter = np.random.default_rng(0).uniform(-0.02, 0.02, (2, 36))
    points, _, triangles = grid(
        6, 6, lambda u, v: np.outer(u + jitter[0], a) + np.outer(v + jitter[1], b)
    )
    np.testing.assert_allclose(np.abs(vertex_normals(points, triangles) @ normal), 1.0, atol=1e-12)


def test_vertex_normals_of_a_cylinder_are_radial():
    rows, cols = 9, 13
    points, quads, triangles = grid(
        rows, cols, lambda u, v: np.c_[2 * u, np.cos(2 * v), np.sin(2 * v)]
    )
    normals = vertex_normals(points, triangles).reshape(rows, cols, 3)[1:-1, 1:-1]
    radial = points.reshape(rows, cols, 3)[1:-1, 1:-1] * [0, 1, 1]
    cosine = np.abs((normals * radial).sum(axis=2)) / np.linalg.norm(radial, axis=2)
    assert cosine.min() > 0.9999


def test_smooth_shading_varies_less_between_neighbours_than_flat():
    rows, cols = 5, 9
    points, quads, triangles = grid(
        rows, cols, lambda u, v: np.c_[2 * u, np.cos(2.5 * v), np.sin(2.5 * v)]
    )
    pieces, rgba = smooth_quads(
        points, vertex_normals(points, triangles), quads, (1.0, 1.0, 1.0), pieces=3
    )
    assert pieces.shape == (len(quads) * 9, 4, 3) and rgba.shape == (len(quads) * 9, 4)
    smooth = (
        rgba[:, 0]
        .reshape(rows - 1, cols - 1, 3, 3)
        .transpose(0, 2, 1, 3)
        .reshape(3 * (rows - 1), -1)
    )
    _, flat = smooth_quads(
        points, vertex_normals(points, triangles), quads, (1.0, 1.0, 1.0), pieces=1
    )
    flat = flat[:, 0].reshape(rows - 1, cols - 1)
    # across the curved direction: the largest jump between neighbouring pieces is much smaller when
    # smooth
    assert np.abs(np.diff(smooth, axis=1)).max() < 0.5 * np.abs(np.diff(flat, axis=1)).max()


def test_a_second_run_replaces_the_whole_frame_set(tmp_path):
    out = tmp_path / "o"
    assert run(tmp_path, out, "--duration", "2", "--video-fps", "2").exit_code == 0
    assert len(list(out.glob("s_*.OBT"))) == 5
    again = run(tmp_path, out, "--duration", "0.5", "--video-fps", "2")
    assert again.exit_code == 2 and str(out) in again.output and "--force" in again.output
    assert len(list(out.glob("s_*.OBT"))) == 5  # left untouched
    forced = run(tmp_path, out, "--duration", "0.5", "--video-fps", "2", "--force")
    assert forced.exit_code == 0, forced.output
    assert sorted(p.name for p in out.glob("s_*.OBT")) == ["s_0.OBT", "s_1.OBT"]
    assert sorted(p.name for p in (out / "obj").iterdir()) == ["s_0.obj", "s_1.obj"]
    assert sorted(p.name for p in (out / "png").iterdir()) == ["frame_0000.png", "frame_0001.png"]
    assert json.loads((out / "run.json").read_text())["duration_s"] == 0.5
    # no staging or old set left
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o", "sheet.PAR"]


def test_a_folder_of_other_files_is_never_replaced(tmp_path):
    out = tmp_path / "o"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    result = run(tmp_path, out, "--duration", "0.5", "--no-render", "--force")
    assert result.exit_code == 2 and "not a frame set" in result.output
    assert [p.name for p in out.iterdir()] == ["notes.txt"]
