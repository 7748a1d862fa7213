"""`eigengait track` through typer's runner and as a process with the CLI's error handling."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import typer
from scipy.spatial.transform import Rotation
from typer.testing import CliRunner

from eigengait.cli.track import register
from eigengait.motion.bvh import local_transforms, read_bvh, write_bvh
from eigengait.motion.flat_feet import FLAT_TILT_WARN_DEG
from shared_data import DM_CONTROL, MOCAP, clip_start

WALK = str(MOCAP / "cmu_02_01_walk.bvh")
DAZ_WALK = str(MOCAP / "cmu_07_06_walk_daz.bvh")
RUN = str(MOCAP / "cmu_16_36_run_daz.bvh")
MAIN = (
    "import sys, typer; from eigengait.cli.track import register; from eigengait.errors import "
    "UserInputError\n"
    "app = typer.Typer(); register(app); app.command('noop')(lambda: None)\n"
    "try:\n    app(standalone_mode=False)\n"
    "except UserInputError as err:\n    print('error:', err, file=sys.stderr); sys.exit(2)\n"
)


def _walk_start(tmp_path, frames: int) -> Path:
    """The 02_01 walk's first `frames` frames as a clip of its own."""
    return clip_start(Path(WALK), frames, tmp_path / "short.bvh")


def _app():
    app = typer.Typer()
    register(app)
    app.command("noop")(lambda: None)
    return app


def test_json_reports_the_required_fields(tmp_path):
    short = _walk_start(tmp_path, 40)
    out_bvh = tmp_path / "out.bvh"
    result = CliRunner().invoke(
        _app(),
        [
            "track",
            str(short),
            "--robustness",
            "1",
            "--json",
            "--bvh",
            str(out_bvh),
            "--bvh-units",
            "cm",
        ],
    )
    assert result.exit_code == 0, result.output
    out = json.loads(result.stdout)  # status lines ("BVH: …") go to standard error
    assert {"duration_s", "fell", "joint_rms_deg", "com_error_m", "artificial_torque"} <= set(out)
    assert out["duration_s"] > 0.25 and out["fell"] is False and out["fall_time_s"] is None
    assert 0.0 <= out["foot_skate_m"] < 0.5 and out["bvh_units"] == "cm"
    assert out["recoveries"] == 0 and out["recovery_simulations"] == 0  # nothing fell
    assert out_bvh.read_text().startswith("HIERARCHY")


def test_the_whole_body_controller_is_chosen_from_the_command_line(tmp_path):
    short = _walk_start(tmp_path, 60)
    result = CliRunner().invoke(
        _app(), ["track", str(short), "--controller", "qp", "--robustness", "0.5", "--json"]
    )
    assert result.exit_code == 0, result.output
    out = json.loads(result.stdout)
    assert out["controller"] == "qp" and out["fell"] is False and out["duration_s"] > 0.45
    assert out["joint_rms_deg"] < 3.0 and out["artificial_torque"] > 0.0


def test_kinematic_json_reports_the_reference_feet_and_the_source_conventions():
    result = CliRunner().invoke(
        _app(), ["track", DAZ_WALK, "--kinematic", "--clean-feet", "--json"]
    )
    assert result.exit_code == 0, result.output
    out = json.loads(result.output)
    assert out["kinematic"] is True and out["feet_cleaned"] is True
    # the T-pose and the blend out of it (frames 0-3) are skipped; the reference starts at its
    # first supported frame (a foot within the contact band)
    assert out["first_frame"] == 4
    assert out["source"]["unit"] == "cm" and out["source"]["up_axis"] == "+y"
    assert out["foot_skate_m"] < 0.35 * out["raw"]["foot_skate_m"]
    # a held foot up to 5.2 mm into the floor (the IK's pull toward the retargeted legs, leg_ik)
    assert out["stances"] >= 1 and out["floor_penetration_m"] < 0.01
    raw = json.loads(
        CliRunner()
        .invoke(_app(), ["track", DAZ_WALK, "--kinematic", "--raw-feet", "--json"])
        .output
    )
    # the raw reference starts on its own first supported frame (4), as the cleaned one does
    assert raw["feet_cleaned"] is False and raw["first_frame"] == 4
    assert raw["foot_skate_m"] == pytest.approx(out["raw"]["foot_skate_m"], rel=0.01)
    # the root translation fitted to the legs: the Daz exports travel about 1.6 times too far
    # (measured 0.62)
    assert 0.5 < out["root_scale_factor"] < 0.75 and out["retarget_scale_m_per_unit"] < 0.01
    assert out["capture_glitches"] == []


def test_kinematic_reports_a_flipped_thigh_it_repaired(tmp_path):
    # The Daz walk with its right thigh turned 160° about its axis for 5 frames (a capture glitch).
    clip = read_bvh(DAZ_WALK)
    thigh = clip.joint_index("rThigh")
    yaw = clip.channel_slices()[thigh].start + clip.joints[thigh].channels.index("Yrotation")
    clip.frames[200:205, yaw] += 160.0
    glitched = tmp_path / "glitched.bvh"
    write_bvh(clip, glitched)
    result = CliRunner().invoke(_app(), ["track", str(glitched), "--kinematic", "--json"])
    assert result.exit_code == 0, result.output
    (glitch,) = json.loads(result.output)["capture_glitches"]
    assert glitch["joint"] == "rThigh"
    assert glitch["start_s"] <= 200 * clip.frame_time and glitch["end_s"] >= 205 * clip.frame_time
    text = CliRunner().invoke(_app(), ["track", str(glitched), "--kinematic"]).output
    assert "capture glitch repaired: rThigh" in text


def _run(*args):
    return subprocess.run(
        [sys.executable, "-c", MAIN, "track", *args], capture_output=True, text=True, timeout=120
    )


def test_bad_inputs_exit_with_status_2(tmp_path):
    proc = _run(WALK, "--robustness", "1.5")
    assert proc.returncode == 2 and "robustness" in proc.stderr
    truncated = tmp_path / "cut.bvh"
    truncated.write_text("\n".join(Path(WALK).read_text().splitlines()[:150]) + "\n")
    proc = _run(str(truncated))
    assert proc.returncode == 2 and "line" in proc.stderr and "cut.bvh" in proc.stderr
    proc = _run(WALK, "--push", "lots")
    assert proc.returncode == 2 and "FORCE@TIME" in proc.stderr
    proc = _run(WALK, "--controller", "pid")
    assert proc.returncode == 2 and "controller" in proc.stderr and "qp" in proc.stderr
    proc = _run(WALK, "--recoveries", "-1")
    assert proc.returncode == 2 and "recoveries" in proc.stderr
    proc = _run(WALK, "--kinematic", "--levelling", "sideways")
    assert proc.returncode == 2 and "levelling" in proc.stderr and "flat" in proc.stderr


def test_a_users_model_is_mapped_by_its_body_names():
    """dm_control's humanoid.xml: no joint stiffness (the tracker switches springs off, so it
    needs none) and the built-in humanoid's name but not its joints; its bodies' names
    (`right_thigh`, `left_lower_arm`) give the mapping. A model whose bodies name no legs (the
    quadruped) gets one error asking for a mapping file, a planar one one naming its root."""
    proc = _run(
        WALK, "--character", str(DM_CONTROL / "suite" / "humanoid.xml"), "--kinematic", "--json"
    )
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout.splitlines()[-1])
    assert out["duration_s"] == pytest.approx(2.85, abs=0.01) and out["stances"] >= 4
    # its free root is the chest: the cleanup holds a foot with that leg's joints alone (through
    # the spine it moved the other foot too, and the cleaned feet slid 53 cm per stance)
    assert out["foot_skate_m"] < 0.02 < out["raw"]["foot_skate_m"]
    proc = _run(WALK, "--character", str(DM_CONTROL / "suite" / "quadruped.xml"), "--kinematic")
    assert proc.returncode == 2 and "stiffness" not in proc.stderr
    assert "no leg bodies found by name" in proc.stderr and "mapping file" in proc.stderr
    # a planar model (slides and a hinge at its root) cannot follow a 3D clip: said at once
    proc = _run(WALK, "--character", str(DM_CONTROL / "suite" / "walker.xml"), "--kinematic")
    assert proc.returncode == 2 and "free-floating root" in proc.stderr
    assert "walker.xml" in proc.stderr and "<freejoint/>" in proc.stderr


def test_a_fall_searched_past_is_reported(tmp_path):
    # The walk's first 0.8 s shoved with 5 000 N at 0.1 s falls at 0.28 s (3 000 N: at 0.71 s);
    # one recovery is searched (every rewind reaches the clip's start: 8 samples), and the output
    # says so.
    short = _walk_start(tmp_path, 100)
    args = ["track", str(short), "--push", "5000@0.1", "--recoveries", "1"]
    out = json.loads(CliRunner().invoke(_app(), [*args, "--json"]).stdout)
    assert out["fell"] is True and out["recoveries"] == 0 and out["recovery_simulations"] == 8
    text = CliRunner().invoke(_app(), args).output
    assert "recovery: 0 fall(s) searched past, 8 simulations" in text


def test_kinematic_warns_of_a_foot_standing_off_level_where_the_clip_is_flat(tmp_path):
    # The CMU run's left foot twisted 40° about its own ankle-to-toe bone in every frame: its toe
    # stays where it was, and so do the frames in which the clip's foot stands flat, but the foot
    # rolls, and a run has no still stance for the levelling to correct it on.
    clip = read_bvh(RUN)
    foot = clip.joint_index("lFoot")
    bone = clip.joints[foot].end_site / np.linalg.norm(clip.joints[foot].end_site)
    twisted = (
        local_transforms(clip)[0][:, foot] @ Rotation.from_rotvec(np.radians(40) * bone).as_matrix()
    )
    channels = clip.joints[foot].channels
    order = "".join(c[0] for c in channels if c.endswith("rotation"))
    cols = clip.channel_slices()[foot]
    clip.frames[:, cols] = Rotation.from_matrix(twisted).as_euler(order, degrees=True)
    rolled = tmp_path / "rolled.bvh"
    write_bvh(clip, rolled)
    before = json.loads(CliRunner().invoke(_app(), ["track", RUN, "--kinematic", "--json"]).output)
    after = json.loads(
        CliRunner().invoke(_app(), ["track", str(rolled), "--kinematic", "--json"]).output
    )
    # measured 7.5° before; the twist about a bone pointing down at the toes tilts the foot by less
    # than 40°
    assert before["flat_foot_tilt_deg"]["left"] < FLAT_TILT_WARN_DEG
    assert after["flat_foot_tilt_deg"]["left"] > FLAT_TILT_WARN_DEG + 5.0
    assert after["flat_foot_tilt_deg"]["right"] == pytest.approx(
        before["flat_foot_tilt_deg"]["right"], abs=0.5
    )
    text = CliRunner().invoke(_app(), ["track", str(rolled), "--kinematic"]).output
    assert "warning: the left foot stands" in text and "warning: the right foot" not in text
    assert "warning" not in CliRunner().invoke(_app(), ["track", RUN, "--kinematic"]).output
    # levelled on the clip's flat frames instead, the twisted foot stands as level as the other
    flat = CliRunner().invoke(
        _app(), ["track", str(rolled), "--kinematic", "--levelling", "flat", "--json"]
    )
    levelled = json.loads(flat.output)
    assert levelled["levelling"] == "flat" and after["levelling"] == "still"
    assert levelled["flat_foot_tilt_deg"]["left"] < 5.0
