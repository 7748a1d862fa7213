"""Hostile input at the command line: every case exits with status 2 and one message, never a
traceback.

One parametrized test per kind of input (option values, character files, sketches and controllers,
cloth scripts, output paths, run folders). Each case builds its files in a temporary folder and runs
`main()` in process, as the `eigengait` command does.
"""

from __future__ import annotations

import json
import pickle
import sys

import pytest

from eigengait.cli import main
from eigengait.cloth.library import example_path
from eigengait.control.library import resolve
from shared_data import MOCAP

LATIN1 = "name: caf\xe9\n".encode("latin-1")


def run_cli(capsys, monkeypatch, args) -> tuple[int, str]:
    monkeypatch.setattr(sys, "argv", ["eigengait", *map(str, args)])
    with pytest.raises(SystemExit) as stop:
        main()
    return stop.value.code, capsys.readouterr().err


def assert_clean_refusal(code: int, err: str) -> None:
    assert code == 2, err
    assert "Traceback" not in err and err.strip()
    assert "No such option" not in err, err  # refused for the value under test, not a mistyped case
    assert len([line for line in err.lower().splitlines() if line.startswith("error")]) == 1, err


OPTION_VALUES = {
    "cycles-not-a-number": ["play", "basic-run", "--cycles", "abc"],
    "random-sketch-procedure-three": [
        "sketch",
        "new",
        "humanoid",
        "--random",
        "1",
        "--procedure",
        "3",
        "-o",
        "{tmp}/s.yaml",
    ],
    "random-sketch-seed-negative": [
        "sketch",
        "new",
        "humanoid",
        "--random",
        "-1",
        "-o",
        "{tmp}/s.yaml",
    ],
    "demo-harden-minutes-negative": ["demo", "--output", "{tmp}/demo", "--harden-minutes", "-1"],
    "harden-copies-zero": ["harden", "kangaroo-hop", "-o", "{tmp}/run", "--copies", "0"],
    "harden-impulse-nan": ["harden", "kangaroo-hop", "-o", "{tmp}/run", "--push-impulse", "nan"],
    "harden-horizon-two": ["harden", "kangaroo-hop", "-o", "{tmp}/run", "--horizon", "2"],
    "harden-event-no-sketch": ["harden", "kangaroo-hop", "-o", "{tmp}/run", "--event"],
    "harden-pairs-no-sketch": ["harden", "kangaroo-hop", "-o", "{tmp}/run", "--paired-feet"],
    "harden-tilt-negative": ["harden", "kangaroo-hop", "-o", "{tmp}/run", "--max-tilt", "-5"],
    "port-out-of-range": ["studio", "--port", "99999"],
    "port-zero": ["studio", "--port", "0"],
    "host-unknown": ["studio", "--host", "nosuch.invalid"],
    "unknown-command": ["nosuch"],
    "unknown-character": ["modes", "no-such-creature"],
    "unknown-phase": ["modes", "humanoid", "--phase", "sideways"],
    "relax-nan": ["modes", "humanoid", "--relax", "left_thigh=nan,0,0"],
    "unknown-gait": ["play", "no-such-gait"],
    "unknown-cloth-example": ["cloth", "run", "no-such-example", "-o", "{tmp}/out"],
    "unknown-method": ["optimize", "basic-run", "-o", "{tmp}/run", "--method", "magic"],
    "evaluations-zero": ["optimize", "basic-run", "-o", "{tmp}/run", "--max-evaluations", "0"],
    "minutes-negative": ["optimize", "basic-run", "-o", "{tmp}/run", "--max-minutes", "-1"],
    "workers-negative": ["optimize", "basic-run", "-o", "{tmp}/run", "--workers", "-2"],
    "tolerance-nan": ["optimize", "basic-run", "-o", "{tmp}/run", "--cycle-tolerance", "nan"],
    "palette-angle-nan": ["palette", "humanoid", "--angle", "nan", "-o", "{tmp}/p.png"],
    "animate-seconds-nan": [
        "animate",
        "humanoid",
        "--mix",
        "2:1",
        "--seconds",
        "nan",
        "--bvh",
        "{tmp}/a.bvh",
    ],
    "cloth-time-step-negative": ["cloth", "run", "curtain", "-o", "{tmp}/out", "--time-step", "-1"],
    "fps-a-billion": [
        "play",
        "kangaroo-hop",
        "--cycles",
        "1",
        "--bvh",
        "{tmp}/x.bvh",
        "--fps",
        "1e9",
    ],
    "popsize-a-hundred-million": [
        "optimize",
        "basic-run",
        "-o",
        "{tmp}/run",
        "--popsize",
        "100000000",
    ],
    "palette-tile-100000": ["palette", "humanoid", "--tile", "100000", "-o", "{tmp}/p.png"],
    "track-start-frame-negative": ["track", "{mocap}/cmu_02_01_walk.bvh", "--start-frame", "-5"],
    "track-foot-radius-negative": ["track", "{mocap}/cmu_02_01_walk.bvh", "--foot-radius", "-0.1"],
    "track-push-malformed": ["track", "{mocap}/cmu_02_01_walk.bvh", "--push", "150"],
    "balance-unknown-character": ["balance", "no-such-creature"],
    "balance-unknown-pose": ["balance", "walker", "--pose", "crouched"],
    "balance-duration-negative": ["balance", "walker", "--duration", "-1"],
    "balance-duration-nan": ["balance", "walker", "--duration", "nan"],
    "balance-push-malformed": ["balance", "walker", "--push", "350at1"],
    "balance-push-negative-time": ["balance", "walker", "--push", "350@-1"],
    "balance-push-after-the-end": ["balance", "walker", "--push", "350@5", "--duration", "1"],
    "balance-robustness-above-one": ["balance", "walker", "--robustness", "1.5"],
    "balance-robustness-negative": ["balance", "walker", "--robustness", "-0.1"],
    "balance-foot-friction-zero": ["balance", "walker", "--foot-friction", "0"],
    "balance-foot-height-inf": ["balance", "walker", "--foot-height", "inf"],
    "balance-video-suffix": ["balance", "walker", "--video", "{tmp}/out.txt"],
    "cloth-floor-nan": ["cloth", "run", "curtain", "-o", "{tmp}/out", "--floor", "nan"],
    "cloth-duration-nan": ["cloth", "run", "curtain", "-o", "{tmp}/out", "--duration", "nan"],
    "cloth-restitution-nan": ["cloth", "run", "curtain", "-o", "{tmp}/out", "--restitution", "nan"],
}


@pytest.mark.parametrize("args", OPTION_VALUES.values(), ids=OPTION_VALUES.keys())
def test_bad_option_values(args, tmp_path, capsys, monkeypatch):
    assert_clean_refusal(
        *run_cli(capsys, monkeypatch, [a.format(tmp=tmp_path, mocap=MOCAP) for a in args])
    )
    assert not (tmp_path / "run").exists()  # refused before any work started


def test_a_script_error_never_echoes_another_files_lines(tmp_path, capsys, monkeypatch):
    secret = tmp_path / "secret.txt"
    secret.write_text("root:x:0:0:root:/root:/bin/bash\n")
    code, err = run_cli(capsys, monkeypatch, ["cloth", "run", secret, "-o", tmp_path / "out"])
    assert_clean_refusal(code, err)
    assert "root:" not in err and "/bin/bash" not in err


def _deep_bvh(depth: int = 5000) -> bytes:
    """A hierarchy nested `depth` joints deep (a recursive parser overflows Python's stack)."""
    channels = "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    head = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\n" + channels
    joints = "".join(
        f"JOINT j{i}\n{{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n"
        for i in range(depth)
    )
    tail = (
        "}\n" * (depth + 1)
        + "MOTION\nFrames: 1\nFrame Time: 0.01\n"
        + " ".join(["0"] * (6 + 3 * depth))
        + "\n"
    )
    return (head + joints + tail).encode()


def _short_state_controller() -> bytes:
    data = json.loads(resolve("gait", "kangaroo-hop").read_text())
    data["initial_qpos"] = data["initial_qpos"][:-1]
    return json.dumps(data).encode()


def _unknown_foot_controller() -> bytes:
    data = json.loads(resolve("gait", "kangaroo-hop").read_text())
    data["feet"] = ["paw"]
    return json.dumps(data).encode()


def _shipped_text(kind: str, name: str) -> str:
    path = example_path(name) if kind == "cloth" else resolve(kind, name)
    return path.read_text(encoding="utf-8")


FILES = {
    "par-4000-grid": (
        "big.PAR",
        _shipped_text("cloth", "curtain").replace("MALHA (20 20)", "MALHA (4000 4000)").encode(),
        ["cloth", "run", "{file}", "-o", "{tmp}/out"],
    ),
    "sketch-unknown-foot": (
        "s.yaml",
        _shipped_text("sketch", "basic-run")
        .replace("character: humanoid", "character: humanoid\nfeet: [hoof]")
        .encode(),
        ["sketch", "{file}"],
    ),
    "bvh-5000-deep": ("deep.bvh", _deep_bvh(), ["track", "{file}", "--json"]),
    "controller-unknown-foot": (
        "c.json",
        _unknown_foot_controller(),
        ["play", "{file}", "--cycles", "1"],
    ),
    "controller-short-state": (
        "c.json",
        _short_state_controller(),
        ["play", "{file}", "--cycles", "1"],
    ),
    "mjcf-garbage": ("bad.xml", b"<mujoco><worldbody><body", ["modes", "{file}"]),
    "mjcf-empty": ("empty.xml", b"", ["modes", "{file}"]),
    "mjcf-missing": (None, None, ["modes", "{tmp}/missing.xml"]),
    "sketch-not-yaml": ("s.yaml", b"{ [ unclosed", ["sketch", "{file}"]),
    "sketch-latin1": ("s.yaml", LATIN1, ["sketch", "{file}"]),
    "sketch-a-list": ("s.yaml", b"- 1\n- 2\n", ["sketch", "{file}"]),
    "controller-not-json": ("c.json", b"{ not json", ["play", "{file}"]),
    "controller-latin1": ("c.json", LATIN1, ["play", "{file}"]),
    "controller-empty-object": ("c.json", b"{}", ["play", "{file}"]),
    "par-garbage": (
        "X.PAR",
        b"root:x:0:0:secret\n\x00\x01",
        ["cloth", "run", "{file}", "-o", "{tmp}/out"],
    ),
    "par-empty": ("X.PAR", b"", ["cloth", "run", "{file}", "-o", "{tmp}/out"]),
    "bvh-garbage": ("m.bvh", b"HIERARCHY\nROOT\n{", ["track", "{file}", "--json"]),
}


@pytest.mark.parametrize("name, content, args", FILES.values(), ids=FILES.keys())
def test_bad_files(name, content, args, tmp_path, capsys, monkeypatch):
    file = tmp_path / (name or "unused")
    if content is not None:
        file.write_bytes(content)
    argv = [a.format(file=file, tmp=tmp_path) for a in args]
    code, err = run_cli(capsys, monkeypatch, argv)
    assert_clean_refusal(code, err)
    if content is not None:
        assert name in err  # the message blames the file at fault, not the character's model


def _pickled_checkpoint(run):
    (run / "checkpoint.pkl").write_bytes(pickle.dumps({"not": "trusted"}))


def _garbage_checkpoint(run):
    (run / "checkpoint.npz").write_bytes(b"garbage")


def _damaged_settings(run):
    (run / "checkpoint.npz").write_bytes(b"garbage")
    (run / "settings.json").write_text("{")


def _empty_folder(run):
    pass


RUN_FOLDERS = {
    "pickled-checkpoint": _pickled_checkpoint,
    "garbage-checkpoint": _garbage_checkpoint,
    "damaged-settings": _damaged_settings,
    "nothing-to-resume": _empty_folder,
}


@pytest.mark.parametrize("damage", RUN_FOLDERS.values(), ids=RUN_FOLDERS.keys())
def test_damaged_run_folders_on_resume(damage, tmp_path, capsys, monkeypatch):
    run = tmp_path / "run"
    run.mkdir()
    damage(run)
    before = sorted(p.name for p in run.iterdir())
    assert_clean_refusal(
        *run_cli(capsys, monkeypatch, ["optimize", "basic-run", "-o", run, "--resume"])
    )
    assert sorted(p.name for p in run.iterdir()) == before


OUTPUT_PATHS = {
    "export-below-a-file": ["character", "export", "humanoid", "-o", "{tmp}/file.txt/h.xml"],
    "export-onto-a-folder": ["character", "export", "humanoid", "-o", "{tmp}"],
    "optimize-into-a-file": ["optimize", "basic-run", "-o", "{tmp}/file.txt"],
    "export-existing-without-force": ["character", "export", "humanoid", "-o", "{tmp}/file.txt"],
    "export-unwritable": ["character", "export", "humanoid", "-o", "/proc/eigengait-h.xml"],
    "palette-unwritable": ["palette", "humanoid", "-o", "/proc/eigengait-p.png"],
    "optimize-unwritable": ["optimize", "basic-run", "-o", "/proc/eigengait-run"],
    "save-below-a-file": ["modes", "humanoid", "--save", "{tmp}/file.txt/m.npz"],
    "save-without-npz": ["modes", "humanoid", "--save", "{tmp}/old"],
    "video-onto-a-folder-with-force": [
        "play",
        "dog-trot",
        "--video",
        "{tmp}/folder.mp4",
        "--force",
    ],
    "demo-into-a-file": ["demo", "--output", "{tmp}/file.txt"],
    "force-and-resume": ["optimize", "basic-run", "-o", "{tmp}/run", "--force", "--resume"],
}
KEPT = ("file.txt", "old.npz", "old.png", "old.mp4", "old.gif", "old.bvh", "old.yaml")


def _outputs_to_keep(tmp_path):
    for name in KEPT:
        (tmp_path / name).write_text("keep me")
    (tmp_path / "folder.mp4").mkdir()


def _assert_kept(tmp_path):
    assert all((tmp_path / name).read_text() == "keep me" for name in KEPT)
    assert not list(tmp_path.glob(".*.part.*")), "a temporary file was left behind"


@pytest.mark.parametrize("args", OUTPUT_PATHS.values(), ids=OUTPUT_PATHS.keys())
def test_bad_output_paths(args, tmp_path, capsys, monkeypatch):
    _outputs_to_keep(tmp_path)
    assert_clean_refusal(*run_cli(capsys, monkeypatch, [a.format(tmp=tmp_path) for a in args]))
    _assert_kept(tmp_path)


EXISTING_OUTPUTS = {
    "modes-save": ["modes", "humanoid", "--save", "{tmp}/old.npz"],
    "palette": ["palette", "humanoid", "-o", "{tmp}/old.png"],
    "animate-video": ["animate", "humanoid", "--mix", "1:1", "--video", "{tmp}/old.gif"],
    "animate-bvh": ["animate", "humanoid", "--mix", "1:1", "--bvh", "{tmp}/old.bvh"],
    "sketch-video": ["sketch", "basic-run", "--video", "{tmp}/old.mp4"],
    "play-video": ["play", "dog-trot", "--video", "{tmp}/old.mp4"],
    "play-bvh": ["play", "dog-trot", "--bvh", "{tmp}/old.bvh"],
    "track-video": ["track", "{tmp}/old.bvh", "--video", "{tmp}/old.mp4"],
    "track-bvh": ["track", "{tmp}/old.bvh", "--bvh", "{tmp}/old.bvh"],
    "character-export": ["character", "export", "humanoid", "-o", "{tmp}/file.txt"],
    "character-inspect": ["character", "inspect", "humanoid", "-o", "{tmp}/old.yaml"],
    "sketch-new": ["sketch", "new", "humanoid", "-o", "{tmp}/old.yaml"],
}


@pytest.mark.parametrize("args", EXISTING_OUTPUTS.values(), ids=EXISTING_OUTPUTS.keys())
def test_existing_outputs_need_force(args, tmp_path, capsys, monkeypatch):
    _outputs_to_keep(tmp_path)
    code, err = run_cli(capsys, monkeypatch, [a.format(tmp=tmp_path) for a in args])
    assert_clean_refusal(code, err)
    assert "exists" in err and "--force" in err, err
    _assert_kept(tmp_path)


def _unfinished_run(run):
    (run / "checkpoint.npz").write_bytes(b"state")
    (run / "status.json").write_text('{"finished": false}')


def _finished_run(run):
    (run / "best_controller.json").write_text("{}")
    (run / "status.json").write_text('{"finished": true}')


def _unfinished_first_stage(run):
    (run / "open-loop").mkdir()
    _unfinished_run(run / "open-loop")


EARLIER_RUNS = {
    "unfinished": (_unfinished_run, "--resume"),
    "finished": (_finished_run, "--force"),
    "unfinished-first-stage": (_unfinished_first_stage, "--resume"),
}


@pytest.mark.parametrize("earlier, fix", EARLIER_RUNS.values(), ids=EARLIER_RUNS.keys())
def test_a_new_run_over_an_earlier_one_is_refused(earlier, fix, tmp_path, capsys, monkeypatch):
    run = tmp_path / "run"
    run.mkdir()
    earlier(run)
    before = {p: p.read_bytes() for p in run.rglob("*") if p.is_file()}
    code, err = run_cli(capsys, monkeypatch, ["optimize", "basic-run", "-o", run])
    assert_clean_refusal(code, err)
    assert fix in err and "--force" in err, err
    assert {p: p.read_bytes() for p in run.rglob("*") if p.is_file()} == before
