"""The runnable examples in examples/ run as a user runs them, and what they print is right."""

from __future__ import annotations

import csv
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
from shared_data import DM_CONTROL

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
WALKER = DM_CONTROL / "suite" / "walker.xml"


def run_example(name: str, *args: str) -> str:
    proc = subprocess.run(
        [sys.executable, str(EXAMPLES / name), *args], capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


def numbers(pattern: str, text: str) -> list[float]:
    return [float(v) for v in re.findall(pattern, text)]


def test_modes_example_prints_what_the_modes_command_computes():
    out = run_example("modes_of_your_model.py", str(WALKER), "--count", "4")
    printed = numbers(r"mode +\d+: +([\d.]+) Hz", out)
    cli = subprocess.run(
        [sys.executable, "-m", "eigengait", "modes", str(WALKER), "--stiffness", "auto", "--json"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert cli.returncode == 0, cli.stderr
    expected = json.loads(cli.stdout)["frequencies_hz"][:4]
    assert np.allclose(printed, expected, atol=1e-3) and printed == sorted(printed)


def test_cloth_example_hangs_the_curtain_within_its_strain_limit():
    out = run_example("cloth_script.py", "curtain", "--seconds", "1")
    strains = numbers(r"strain +([\d.]+) %", out)
    heights = numbers(r"z = +([-\d.]+) m", out)
    # stretched, but limited
    assert len(strains) == 2 and max(strains) <= 10.0 + 1e-6 and strains[-1] > 1.0
    assert heights[1] < heights[0]  # gravity pulls it down


def test_track_example_holds_the_walk():
    out = run_example("track_a_clip.py")
    tracked, total = map(float, re.search(r"tracked ([\d.]+) of ([\d.]+) s", out).groups())
    assert "fell: False" in out and abs(tracked - total) < 0.02


def test_sketch_example_optimizes_within_its_budget_and_plays(tmp_path):
    out = run_example(
        "sketch_to_gait.py", "kangaroo", "--evaluations", "40", "--output", str(tmp_path / "run")
    )
    evaluations = numbers(r"^(\d+) evaluations", out)
    # both stages counted: each stops after the generation that spends its share, so the whole
    # run spends the budget and overshoots it by less than one generation
    logs = [
        list(csv.DictReader(open(tmp_path / "run" / stage / "log.csv")))
        for stage in ("open-loop", ".")
    ]
    generation = int(logs[0][0]["evaluations"])
    assert evaluations == [sum(int(rows[-1]["evaluations"]) for rows in logs)]
    assert 40 <= evaluations[0] < 40 + generation
    assert (tmp_path / "run" / "best_controller.json").is_file() and "played" in out
