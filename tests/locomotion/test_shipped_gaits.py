"""The shipped gaits: named as documented, and they replay what the file says about them."""

import json

import pytest

from eigengait.control.controller import load_controller, system_for, to_parameters
from eigengait.control.library import gait_names, resolve
from eigengait.control.playback import play

REQUIRED = {"humanoid-basic-run", "monster-run", "kangaroo-hop"}


def test_required_gaits_are_shipped(eigengait_cli):
    assert REQUIRED <= set(gait_names())
    listed = json.loads(eigengait_cli("gaits", "--json").stdout)
    assert REQUIRED <= {row["name"] for row in listed}


@pytest.mark.parametrize("name", sorted(gait_names()))
def test_shipped_gait_replays_its_recorded_metrics(name):
    controller = load_controller(resolve("gait", name))
    system = system_for(controller)
    result = play(system, to_parameters(controller, system), cycles=20)
    assert not result.fell and result.cycles_completed == 20                 # with the default snap
    assert result.cycle_violation == pytest.approx(controller.metrics["cycle_violation"], abs=1e-4)
    assert result.cycle_violation < controller.metrics["cycle_tolerance"]
    assert result.mean_speed_mps > 0.2                                    # it goes forward
    free = play(system, to_parameters(controller, system), cycles=20, snap=False)   # as scripts/make_gaits.py
    assert free.cycles_completed == controller.metrics["cycles_without_snap"]


def test_play_json_contract_on_a_shipped_gait(eigengait_cli):
    result = eigengait_cli("play", "humanoid-basic-run", "--cycles", "2", "--json")
    assert result.returncode == 0, result.stderr
    out = json.loads(result.stdout)
    assert out["cycles_completed"] == 2 and out["fell"] is False and out["mean_speed_mps"] > 0.2
