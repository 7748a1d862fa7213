"""Outputs as the user gets them: --force replaces a file, writes are atomic, MuJoCo's log stays out
of the folder.

Refusals (an existing file without --force, bad output paths) are in the hostile-input corpus.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import mujoco
import numpy as np
import pytest

from eigengait.render.video import write_video
from test_hostile_inputs import run_cli

REPLACED = {
    "modes-save": ("m.npz", ["modes", "humanoid", "--save", "{out}"]),
    "character-export": ("h.xml", ["character", "export", "humanoid", "-o", "{out}"]),
    "animate-bvh": (
        "a.bvh",
        ["animate", "humanoid", "--mix", "1:1", "--seconds", "0.2", "--bvh", "{out}"],
    ),
    "play-bvh": ("p.bvh", ["play", "dog-trot", "--cycles", "1", "--bvh", "{out}"]),
}


@pytest.mark.parametrize("name, args", REPLACED.values(), ids=REPLACED.keys())
def test_force_replaces_an_existing_output(name, args, tmp_path, capsys, monkeypatch):
    out = tmp_path / name
    out.write_text("old")
    code, err = run_cli(capsys, monkeypatch, [*(a.format(out=out) for a in args), "--force"])
    assert code == 0, err
    assert out.read_bytes() != b"old" and out.stat().st_size > 100
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]  # no temporary file left


def test_a_kill_during_a_video_write_leaves_no_file_under_the_final_name(tmp_path):
    out = tmp_path / "out.mp4"
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "eigengait",
            "animate",
            "humanoid",
            "--mix",
            "2:1",
            "--seconds",
            "30",
            "--width",
            "64",
            "--height",
            "64",
            "--video",
            str(out),
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        deadline = time.monotonic() + 120
        while not list(tmp_path.glob(".out.mp4.*.part.mp4")):
            assert not out.exists(), "the video is written under its final name"
            assert proc.poll() is None and time.monotonic() < deadline, (
                "no temporary video appeared"
            )
            time.sleep(0.05)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.kill()
        proc.wait()
    time.sleep(0.5)  # the orphaned encoder, if any, finishes the temporary file, not the output
    assert not out.exists()


def _frames_then_failure():
    yield np.zeros((16, 16, 3), np.uint8)
    raise RuntimeError("rendering failed")


@pytest.mark.parametrize("name", ["v.mp4", "v.gif"])
def test_a_failed_video_write_leaves_the_old_file_and_no_temporary(name, tmp_path):
    out = tmp_path / name
    out.write_text("old")
    with pytest.raises(RuntimeError):
        write_video(_frames_then_failure(), out, fps=10)
    assert out.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


def test_mujoco_warnings_go_to_stderr_not_to_a_log_in_the_folder(tmp_path, capfd, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, err = run_cli(capfd, monkeypatch, ["characters", "--json"])
    assert code == 0, err
    model = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><body><freejoint/><geom size='.1'/></body></worldbody></mujoco>"
    )
    data = mujoco.MjData(model)
    data.qvel[:] = 1e20
    mujoco.mj_step(model, data)
    assert "Nan, Inf or huge value" in capfd.readouterr().err
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
