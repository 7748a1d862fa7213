"""Signature figures of the thesis's experiments against hand-built motions with a known sway,
twist, skip count, stance width and raised foot."""

import mujoco
import numpy as np
import pytest

from eigengait.control.gait_metrics import GaitRecording
from eigengait.control.gait_signatures import cycle_amplitude, gait_signatures

XML = """<mujoco><worldbody><body name="root"><freejoint/><geom type="box" size=".1 .1 .1"/></body>
  </worldbody></mujoco>"""
FPS, PERIOD, R = 100.0, 0.8, 0.02
CYCLE = int(PERIOD * FPS)
CYCLES = 5
FRAMES = CYCLES * CYCLE


@pytest.fixture(scope="module")
def model():
    return mujoco.MjModel.from_xml_string(XML)


def foot(down_phases, y, lift=0.05):
    """F × 1 × 3 contact-sphere centre at lateral position y: on the floor for cycle phases in any
    of the `down_phases` [a, b) intervals, `lift` m up otherwise."""
    phase = np.mod(np.arange(FRAMES), CYCLE) / CYCLE
    down = np.any([(phase >= a) & (phase < b) for a, b in down_phases], axis=0)
    pts = np.zeros((FRAMES, 1, 3))
    pts[:, 0, 1] = y
    pts[:, 0, 2] = np.where(down, R, R + lift)
    return pts


def record(model, feet, heading_deg=0.0, sway=0.0, yaw_deg=0.0, height=0.9):
    """The COM walks 1.5 m/s along `heading_deg`, swaying `sway` m square to it at the cycle's
    frequency; the root twists ±`yaw_deg` about the vertical at the same frequency, on top of the
    heading."""
    t = np.arange(FRAMES) / FPS
    h = np.radians(heading_deg)
    forward, side = np.array([np.cos(h), np.sin(h)]), np.array([-np.sin(h), np.cos(h)])
    wave = np.sin(2 * np.pi * t / PERIOD)
    com = np.zeros((FRAMES, 3))
    com[:, :2] = 1.5 * t[:, None] * forward + sway * wave[:, None] * side
    com[:, 2] = height
    qpos = np.tile(model.qpos0, (FRAMES, 1))
    qpos[:, 2] = height
    yaw = h + np.radians(yaw_deg) * wave
    qpos[:, 3], qpos[:, 6] = np.cos(yaw / 2), np.sin(yaw / 2)
    return GaitRecording(FPS, PERIOD, qpos, com, feet, {f: R for f in feet})


def biped():
    return {"left": foot([(0.1, 0.4)], 0.1), "right": foot([(0.6, 0.9)], -0.1)}


@pytest.mark.parametrize("heading", [0.0, 35.0])
def test_sway_and_twist_are_read_square_to_the_travel_whatever_the_heading(model, heading):
    s = gait_signatures(model, record(model, biped(), heading_deg=heading, sway=0.04, yaw_deg=12.0))
    assert s["lateral_com_amplitude_m"] == pytest.approx(0.04, rel=0.02)
    assert s["yaw_amplitude_deg"] == pytest.approx(12.0, rel=0.02)


def test_a_straight_run_has_no_sway_and_no_twist(model):
    s = gait_signatures(model, record(model, biped(), heading_deg=20.0))
    assert s["lateral_com_amplitude_m"] == pytest.approx(0.0, abs=1e-9)
    assert s["yaw_amplitude_deg"] == pytest.approx(0.0, abs=1e-9)


def test_a_steady_drift_is_not_an_oscillation():
    t = np.arange(FRAMES) / FPS
    assert cycle_amplitude(0.3 * t, CYCLE) == pytest.approx(0.0, abs=1e-12)
    assert cycle_amplitude(0.3 * t + 0.02 * np.sin(2 * np.pi * t / PERIOD), CYCLE) == pytest.approx(
        0.02, rel=0.05
    )
    assert cycle_amplitude(t[: CYCLE - 1], CYCLE) is None  # not one full cycle


def test_a_skip_lands_twice_on_each_foot_every_cycle(model):
    skip = {
        "left": foot([(0.05, 0.15), (0.3, 0.4)], 0.1),
        "right": foot([(0.55, 0.65), (0.8, 0.9)], -0.1),
    }
    s = gait_signatures(model, record(model, skip))
    # every stance start is a touchdown but the very first frame's (it is not seen landing)
    assert s["touchdowns_per_cycle"] == pytest.approx({"left": 2.0, "right": 2.0})
    assert gait_signatures(model, record(model, biped()))["touchdowns_per_cycle"] == pytest.approx(
        {"left": 1.0, "right": 1.0}
    )


def test_stance_width_is_the_lateral_gap_between_alternate_footfalls(model):
    narrow = gait_signatures(model, record(model, biped()))["stance_width_m"]
    apart = {"left": foot([(0.1, 0.4)], 0.25), "right": foot([(0.6, 0.9)], -0.25)}
    assert narrow == pytest.approx(0.2)
    assert gait_signatures(model, record(model, apart))["stance_width_m"] == pytest.approx(0.5)


def test_a_raised_foot_shows_its_clearance_and_the_crouch_its_height(model):
    hop = {"left": foot([(0.2, 0.6)], 0.1), "right": foot([], -0.1, lift=0.3)}
    s = gait_signatures(model, record(model, hop, height=0.7))
    assert s["min_foot_height_m"] == pytest.approx({"left": 0.0, "right": 0.3})
    assert s["mean_root_height_m"] == pytest.approx(0.7)
    assert s["stance_width_m"] is None  # one landing foot: no alternate footfalls
