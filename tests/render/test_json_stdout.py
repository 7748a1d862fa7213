"""Every command with --json prints exactly one JSON document on standard output, whatever else it
writes."""

import json
from pathlib import Path

import pytest
from shared_data import MOCAP

WALK = MOCAP / "cmu_02_01_walk.bvh"


def _commands(tmp: Path) -> list[list[str]]:
    return [
        ["characters", "--json"],
        ["modes", "kangaroo", "--json"],
        ["gaits", "--json"],
        [
            "sketch",
            "basic-run",
            "--seconds",
            "0.3",
            "--json",
            "--video",
            tmp / "sketch.gif",
            "--fps",
            "10",
        ],
        [
            "play",
            "humanoid-basic-run",
            "--cycles",
            "1",
            "--plans",
            "8",
            "--json",
            "--video",
            tmp / "play.gif",
            "--fps",
            "10",
            "--bvh",
            tmp / "play.bvh",
        ],
        [
            "track",
            WALK,
            "--json",
            "--video",
            tmp / "track.gif",
            "--bvh",
            tmp / "track.bvh",
            "--fps",
            "5",
        ],
    ]


@pytest.mark.parametrize("index", range(6))
def test_json_commands_print_only_json(eigengait_cli, tmp_path, index):
    args = _commands(tmp_path)[index]
    if WALK in args and not WALK.exists():
        pytest.skip(f"{WALK} is missing")
    run = eigengait_cli(*args)
    assert run.returncode == 0, run.stderr
    json.loads(run.stdout)
    written = [a for a in args if isinstance(a, Path) and a.parent == tmp_path]
    assert all(p.exists() and p.stat().st_size > 0 for p in written)
    # status lines still reach the user, on stderr
    assert all(str(p) in run.stderr for p in written)
