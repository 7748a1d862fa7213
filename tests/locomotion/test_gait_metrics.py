"""Gait-quality figures against hand-built motions whose cadence, flight, slip, footfall and jumps are known."""

import json

import mujoco
import numpy as np
import pytest

from eigengait.control.gait_metrics import GaitRecording, foot_contacts, gait_metrics

XML = """<mujoco><worldbody><body name="root"><freejoint/><geom type="box" size=".1 .1 .1"/>
  <body name="a" pos="0 0 -.2"><joint name="ball" type="ball"/><geom type="box" size=".05 .05 .05"/></body>
  <body name="b" pos=".2 0 0"><joint name="hinge" type="hinge" axis="0 1 0"/><geom type="box" size=".05 .05 .05"/>
  </body></body></worldbody></mujoco>"""
FPS, PERIOD, R = 100.0, 0.8, 0.02


@pytest.fixture(scope="module")
def model():
    return mujoco.MjModel.from_xml_string(XML)


def still_pose(model, frames):
    qpos = np.tile(model.qpos0, (frames, 1))
    qpos[:, 2] = 1.0
    return qpos


def biped(model, cycles=4, slip=0.0):
    """Left on the ground in [0.1, 0.4) of each cycle, right in [0.5, 0.8); flight 0.2 of the time. The left
    foot slides `slip` m forward during each stance. COM moves 1.5 m/s."""
    F = int(cycles * PERIOD * FPS)
    t = np.arange(F) / FPS
    phase = np.mod(t, PERIOD) / PERIOD
    left_on = (phase >= 0.1 / 0.8) & (phase < 0.4 / 0.8)
    right_on = (phase >= 0.5 / 0.8) & (phase < 0.8 / 0.8)
    feet = {}
    for name, on, start in (("left", left_on, 0.1 / 0.8), ("right", right_on, 0.5 / 0.8)):
        pts = np.zeros((F, 2, 3))
        pts[:, :, 2] = np.where(on, R, R + 0.05)[:, None]
        progress = np.clip((phase - start) / (0.3 / 0.8), 0, 1)
        pts[:, :, 0] = (slip * progress if name == "left" else 0.0)[..., None] if name == "left" else 0.0
        feet[name] = pts
    com = np.stack([1.5 * t, 0 * t, 0 * t + 1.0], axis=1)
    return GaitRecording(fps=FPS, period=PERIOD, qpos=still_pose(model, F), com=com, foot_points=feet,
                         foot_radius={"left": R, "right": R})


def test_biped_cadence_flight_duty_footfall_and_slip(model):
    rec = biped(model, slip=0.02)
    m = gait_metrics(model, rec)
    assert m["cadence_spm"] == pytest.approx(60 * 8 / (4 * PERIOD))    # 8 touchdowns in 3.2 s
    assert m["flight_fraction"] == pytest.approx(0.25, abs=0.02)      # 0.0–0.1 and 0.4–0.5 of 0.8 s
    assert m["duty_factor"]["left"] == pytest.approx(0.375, abs=0.02)
    assert m["footfall"]["left"] == pytest.approx(0.125, abs=0.02)
    assert m["footfall"]["right"] == pytest.approx(0.625, abs=0.02)
    assert m["stance_slip_m"]["left"] == pytest.approx(0.02, abs=0.002)
    assert m["stance_slip_m"]["right"] == pytest.approx(0.0, abs=1e-9)
    assert m["stride_m"] == pytest.approx(1.5 * PERIOD, rel=1e-3)


def test_trot_pairs_landing_together_count_once(model):
    rec = biped(model)
    shifted = rec.foot_points["left"].copy()
    lag = 2                                            # 0.02 s later
    shifted[lag:] = rec.foot_points["left"][:-lag]
    rec.foot_points["partner"] = shifted
    rec.foot_radius["partner"] = R
    alone = gait_metrics(model, biped(model))["cadence_spm"]
    assert gait_metrics(model, rec)["cadence_spm"] == pytest.approx(alone)


def test_contacts_ignore_a_single_grazing_frame(model):
    rec = biped(model)
    rec.foot_points["right"][5, :, 2] = R            # one frame touching in the middle of a flight
    on = foot_contacts(rec)["right"]
    assert not on[5]


def test_frame_jumps_and_root_tilt(model):
    qpos = still_pose(model, 10)
    ball = model.jnt_qposadr[model.joint("ball").id]
    q = np.zeros(4)
    mujoco.mju_axisAngle2Quat(q, np.array([1.0, 0, 0]), np.radians(20))
    qpos[6:, ball:ball + 4] = q                     # the ball joint turns 20° in one frame
    qpos[8:, 0] += 0.1                              # the root jumps 10 cm
    mujoco.mju_axisAngle2Quat(q, np.array([0, 1.0, 0]), np.radians(12))
    qpos[:, 3:7] = q                                # pitched 12° nose down throughout
    rec = GaitRecording(fps=FPS, period=PERIOD, qpos=qpos, com=np.zeros((10, 3)),
                        foot_points={"f": np.full((10, 1, 3), 1.0)}, foot_radius={"f": R})
    m = gait_metrics(model, rec)
    assert m["max_frame_jump_deg"] == pytest.approx(20.0, abs=1e-6)
    assert m["max_root_jump_m"] == pytest.approx(0.1, abs=1e-9)
    assert m["torso_pitch_deg"] == pytest.approx([12.0, 12.0], abs=1e-6)
    assert m["torso_roll_deg"] == pytest.approx([0.0, 0.0], abs=1e-6)


def test_a_foot_that_never_lands_gives_nulls_and_valid_json(model):
    m = gait_metrics(model, GaitRecording(fps=FPS, period=PERIOD, qpos=still_pose(model, 20),
                                          com=np.zeros((20, 3)), foot_points={"f": np.full((20, 1, 3), 1.0)},
                                          foot_radius={"f": R}))
    assert m["footfall"]["f"] is None and m["stance_slip_m"]["f"] is None and m["flight_fraction"] == 1.0
    json.dumps(m, allow_nan=False)
