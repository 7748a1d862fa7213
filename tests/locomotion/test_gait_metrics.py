"""Gait-quality figures against hand-built motions whose cadence, flight, slip, footfall, tilt and
jumps are known."""

import json

import mujoco
import numpy as np
import pytest

from eigengait.control.gait_metrics import GaitRecording, foot_contacts, gait_metrics

XML = """<mujoco><worldbody><body name="root"><freejoint/><geom type="box" size=".1 .1 .1"/>
  <body name="a" pos="0 0 -.2"><joint name="ball" type="ball"/><geom type="box" size=".05 .05 .05"/></body>
  <body name="b" pos=".2 0 0"><joint name="hinge" type="hinge" axis="0 1 0"/><geom type="box" size=".05 .05 .05"/>
  </body></body></worldbody></mujoco>"""  # noqa: E501
FPS, PERIOD, R = 100.0, 0.8, 0.02
CYCLE = int(PERIOD * FPS)  # 80 frames
CYCLES = 4


@pytest.fixture(scope="module")
def model():
    return mujoco.MjModel.from_xml_string(XML)


def still_pose(model, frames):
    qpos = np.tile(model.qpos0, (frames, 1))
    qpos[:, 2] = 1.0
    return qpos


def stance(first, last, lag=0):
    """(F,) bool: on the ground from cycle frame `first` to `last` (inclusive) of every cycle, `lag`
    frames late."""
    k = np.mod(np.arange(CYCLES * CYCLE) - lag, CYCLE)
    return (k >= first) & (k <= last)


def foot(on, slide=(0.0, 0.0)):
    """F × 2 × 3 heel and toe centres: resting on the floor when `on`, 5 cm up otherwise; the toe
    slides `slide` (x, y in m) steadily over each stance, the heel stays put."""
    pts = np.zeros((len(on), 2, 3))
    pts[:, :, 2] = np.where(on, R, R + 0.05)[:, None]
    progress = np.zeros(len(on))
    (starts,) = np.nonzero(np.diff(np.r_[0, on.astype(int)]) == 1)
    (ends,) = np.nonzero(np.diff(np.r_[on.astype(int), 0]) == -1)
    for a, b in zip(starts, ends):
        progress[a : b + 1] = np.linspace(0.0, 1.0, b - a + 1)
    pts[:, 1, :2] = progress[:, None] * np.array(slide)
    return pts


def axis_quat(axis, deg):
    """wxyz quaternion of a turn of `deg` degrees about `axis`."""
    q = np.zeros(4)
    mujoco.mju_axisAngle2Quat(q, np.array(axis, float) / np.linalg.norm(axis), np.radians(deg))
    return q


def recording(model, feet, fps=FPS):
    frames = len(next(iter(feet.values())))
    t = np.arange(frames) / fps
    com = np.stack([1.5 * t, np.zeros(frames), np.ones(frames)], axis=1)  # 1.5 m/s forward
    return GaitRecording(
        fps=fps,
        period=PERIOD,
        qpos=still_pose(model, frames),
        com=com,
        foot_points=feet,
        foot_radius={f: R for f in feet},
    )


def biped(model):
    """Left foot down over phases [0.1, 0.4), right over [0.6, 0.9): 0.16 s of flight between
    stances, flight 0.4 of the time. The left toe slides 2 cm (1.2 cm forward, 1.6 cm sideways)
    during each stance."""
    return recording(
        model, {"left": foot(stance(8, 31), slide=(0.012, 0.016)), "right": foot(stance(48, 71))}
    )


def test_biped_cadence_flight_duty_footfall_slip_and_stride(model):
    m = gait_metrics(model, biped(model))
    assert m["cadence_spm"] == pytest.approx(150.0)  # 8 touchdowns in 3.2 s
    assert m["flight_fraction"] == pytest.approx(0.4)
    assert m["duty_factor"] == pytest.approx({"left": 0.3, "right": 0.3})
    assert m["footfall"] == pytest.approx({"left": 0.1, "right": 0.6})
    assert m["stance_slip_m"] == pytest.approx({"left": 0.02, "right": 0.0})
    assert m["stance_slip_max_m"] == pytest.approx(0.02)
    assert m["swing_clearance_m"] == pytest.approx({"left": 0.05, "right": 0.05})
    assert m["stride_m"] == pytest.approx(1.5 * PERIOD)
    assert m["torso_pitch_deg"] == m["torso_roll_deg"] == [0.0, 0.0]
    assert m["max_frame_jump_deg"] == m["max_root_jump_m"] == 0.0


@pytest.mark.parametrize("lag, cadence", [(0, 150.0), (2, 150.0), (10, 300.0)])
def test_trot_pairs_landing_within_the_window_count_as_one_step(model, lag, cadence):
    """Diagonal pairs land at phases 0.1 and 0.6, the second foot of a pair `lag` frames
    (lag / 100 s) later: 0.02 s apart is one step, 0.1 s apart two."""
    feet = {
        "lf": foot(stance(8, 31)),
        "rh": foot(stance(8, 31, lag)),
        "rf": foot(stance(48, 71)),
        "lh": foot(stance(48, 71, lag)),
    }
    assert gait_metrics(model, recording(model, feet))["cadence_spm"] == pytest.approx(cadence)


def test_contacts_ignore_a_grazing_frame_and_bridge_a_one_frame_gap(model):
    """At 60 frames/s one frame lasts 1/60 s < 0.02 s: too short either as a contact or as a gap."""
    on = np.array([0, 0, 1, 0, 0, 1, 1, 1, 0, 1, 1, 1, 1, 0, 0], bool)
    feet = {"f": np.zeros((len(on), 1, 3))}
    # bottom 4 mm up: within the 5 mm tolerance
    feet["f"][:, 0, 2] = np.where(on, R + 0.004, R + 0.05)
    expected = np.array([0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0], bool)
    np.testing.assert_array_equal(foot_contacts(recording(model, feet, fps=60.0))["f"], expected)


def test_slip_counts_only_travel_while_a_sphere_touches(model):
    """The heel holds the foot down for frames 5–24; the toe touches 5–9, is carried 5 cm forward in
    the air, then touches again 15–24 and slides 1 cm: the slip is 1 cm, not the toe's 6 cm from
    first to last touch."""
    frames = 30
    pts = np.zeros((frames, 2, 3))
    pts[:, :, 2] = R + 0.05
    pts[5:25, 0, 2] = R
    pts[5:10, 1, 2] = pts[15:25, 1, 2] = R
    pts[10:, 1, 0] = 0.05 + np.r_[np.zeros(5), np.linspace(0.0, 0.01, 10), np.full(5, 0.01)]
    m = gait_metrics(model, recording(model, {"f": pts}))
    assert m["stance_slip_m"]["f"] == pytest.approx(0.01)


def test_frame_jumps_take_the_largest_joint_rotation_and_root_translation(model):
    qpos = still_pose(model, 10)
    ball, hinge = (model.jnt_qposadr[model.joint(n).id] for n in ("ball", "hinge"))
    qpos[6:, ball : ball + 4] = axis_quat([1, 1, 0], 20)  # the ball joint turns 20° in one frame
    qpos[3:, hinge] = np.radians(-8)  # the hinge turns 8° in one frame
    qpos[8:, 0:2] += [0.06, 0.08]  # the root jumps 10 cm
    rec = GaitRecording(
        fps=FPS,
        period=PERIOD,
        qpos=qpos,
        com=np.zeros((10, 3)),
        foot_points={"f": np.full((10, 1, 3), 1.0)},
        foot_radius={"f": R},
    )
    m = gait_metrics(model, rec)
    assert m["max_frame_jump_deg"] == pytest.approx(20.0)
    assert m["max_root_jump_m"] == pytest.approx(0.1)

    qpos[4:, hinge] = np.radians(27)  # a 35° hinge jump now dominates
    assert gait_metrics(model, rec)["max_frame_jump_deg"] == pytest.approx(35.0)
    qpos[5:, 3:7] = axis_quat([0, 0, 1], 40)  # the root turns 40° about z in one frame
    assert gait_metrics(model, rec)["max_frame_jump_deg"] == pytest.approx(40.0)


def test_torso_pitch_and_roll_ignore_the_heading(model):
    """Heading 40°, roll 7°, pitch ramping −5° → 12° (intrinsic z-y-x): [min, max] pitch and roll
    come back."""
    frames = 18
    qpos = still_pose(model, frames)
    for i, pitch in enumerate(np.linspace(-5, 12, frames)):
        yaw_pitch = np.zeros(4)
        mujoco.mju_mulQuat(yaw_pitch, axis_quat([0, 0, 1], 40), axis_quat([0, 1, 0], pitch))
        mujoco.mju_mulQuat(qpos[i, 3:7], yaw_pitch, axis_quat([1, 0, 0], 7))
    nose_down = np.zeros(9)
    mujoco.mju_quat2Mat(nose_down, qpos[-1, 3:7])
    assert nose_down[6] < 0  # positive pitch: the body x axis points below the horizon
    rec = GaitRecording(
        fps=FPS,
        period=PERIOD,
        qpos=qpos,
        com=np.zeros((frames, 3)),
        foot_points={"f": np.full((frames, 1, 3), 1.0)},
        foot_radius={"f": R},
    )
    m = gait_metrics(model, rec)
    assert m["torso_pitch_deg"] == pytest.approx([-5.0, 12.0])
    assert m["torso_roll_deg"] == pytest.approx([7.0, 7.0])


def test_a_foot_that_never_lands_gives_nulls_and_valid_json(model):
    rec = biped(model)
    rec.foot_points["spare"] = np.full((CYCLES * CYCLE, 2, 3), 1.0)
    rec.foot_radius["spare"] = R
    m = gait_metrics(model, rec)
    assert m["footfall"]["spare"] is None and m["stance_slip_m"]["spare"] is None
    assert m["duty_factor"]["spare"] == 0.0 and m["stance_slip_max_m"] == pytest.approx(0.02)
    json.dumps(m, allow_nan=False)

    airborne = recording(model, {"f": np.full((20, 1, 3), 1.0)})
    airborne.com[-1, 0] = np.nan  # a diverged simulation: no figure may be NaN
    m = gait_metrics(model, airborne)
    assert m["cadence_spm"] == 0.0 and m["flight_fraction"] == 1.0
    assert m["footfall"] == {"f": None} and m["stance_slip_max_m"] is None and m["stride_m"] is None
    json.dumps(m, allow_nan=False)


PLANAR = """<mujoco><worldbody><body name="torso">
  <joint name="rootx" type="slide" axis="1 0 0"/><joint name="rootz" type="slide" axis="0 0 1"/>
  <joint name="rooty" type="hinge" axis="0 1 0"/><geom type="box" size=".1 .1 .1"/>
  <body name="leg" pos="0 0 -.2"><joint name="hip" type="hinge" axis="0 1 0"/><geom type="box" size=".05 .05 .05"/>
  </body></body></worldbody></mujoco>"""  # noqa: E501


def test_a_planar_root_reports_its_pitch_and_its_jumps():
    model = mujoco.MjModel.from_xml_string(PLANAR)
    frames = 60
    qpos = np.zeros((frames, model.nq))
    qpos[:, 0] = np.arange(frames) * 0.01  # 1 cm per frame forward
    qpos[30, 0] += 0.05  # one 5 cm jump forward (and back)
    qpos[:, 1] = 1.0
    qpos[:, 2] = np.radians(np.linspace(-10, 20, frames))  # pitch about +y: nose down positive
    rec = GaitRecording(
        fps=FPS,
        period=PERIOD,
        qpos=qpos,
        com=np.zeros((frames, 3)),
        foot_points={"f": foot(np.ones(frames, bool))},
        foot_radius={"f": R},
    )
    m = gait_metrics(model, rec)
    assert m["torso_pitch_deg"] == pytest.approx([-10, 20], abs=1e-3)
    assert m["torso_roll_deg"] == [0.0, 0.0]
    assert m["max_root_jump_m"] == pytest.approx(0.06, abs=1e-4)


def test_a_shuffle_counts_as_flight_but_shows_its_millimetre_clearance(model):
    on = stance(8, 31)
    feet = {"f": foot(on)}
    feet["f"][~on, :, 2] = R + 0.008  # lifts 8 mm: off the ground by the 5 mm rule
    m = gait_metrics(model, recording(model, feet))
    assert m["flight_fraction"] == pytest.approx(0.7)
    assert m["swing_clearance_m"] == pytest.approx({"f": 0.008})
