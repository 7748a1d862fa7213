"""The whole pipeline through the CLI on users' models: planar walker and the CMU humanoid
(56 hinges).

Budgets are tiny (16 evaluations): these check that every command accepts the model, not that the
gait walks."""

import json

import pytest
from shared_data import DM_CONTROL

MODELS = DM_CONTROL


@pytest.mark.parametrize("model", ["suite/walker.xml", "suite/humanoid_CMU.xml"])
def test_modes_palette_sketch_optimize_play(tmp_path, eigengait_cli, model):
    sketch = tmp_path / "gait.yaml"
    r = eigengait_cli("sketch", "new", MODELS / model, "--stiffness", "auto", "-o", sketch)
    assert r.returncode == 0, r.stderr
    side = next(tmp_path.glob("*.eigengait.yaml"))
    r = eigengait_cli("modes", side, "--phase", "ground", "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["rigid_modes"] == (1 if "walker" in model else 3)
    r = eigengait_cli("sketch", sketch, "--seconds", "0.3", "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["max_joint_rotation_deg"] > 0
    r = eigengait_cli("palette", side, "-o", tmp_path / "p.png", "--modes", "2", "--tile", "64")
    assert r.returncode == 0, r.stderr
    run = tmp_path / "run"
    r = eigengait_cli(
        "optimize",
        sketch,
        "-o",
        run,
        "--max-evaluations",
        "16",
        "--popsize",
        "8",
        "--workers",
        "1",
        "--max-outer",
        "1",
        "--inner-generations",
        "2",
    )
    assert r.returncode == 0, r.stderr
    # rendering 56 bodies takes ~10 s
    video = ["--video", tmp_path / "v.gif"] if "walker" in model else []
    # lookahead on the planar walker only (56 dofs are slow), with a third of the default plans
    planner = ["--plans", "32"] if "walker" in model else ["--no-lookahead"]
    r = eigengait_cli(
        "play",
        run / "best_controller.json",
        "--cycles",
        "1",
        "--json",
        "--bvh",
        tmp_path / "m.bvh",
        *video,
        *planner,
    )
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout.splitlines()[0])["character"] == str(side.resolve())
    assert json.loads(r.stdout.splitlines()[0])["lookahead"] is ("--plans" in planner)
    assert (tmp_path / "m.bvh").exists() and all(
        p.stat().st_size > 0 for p in tmp_path.glob("v.gif")
    )
