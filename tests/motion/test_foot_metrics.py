"""Stance detection, skate, penetration and clearance on a hand-built two-point foot with known
stances and slide."""

import numpy as np
import pytest

from eigengait.motion.foot_cleanup import foot_corrections
from eigengait.motion.foot_metrics import foot_report, stance_skate, stances

DT = 0.01  # s


def _foot():
    """Heel and toe sole points (130, 2, 3): stance 0–49 (still, ending on a heel-to-toe roll),
    swing 50–79 (0.5 m forward, 0.10 m high, touching 2 frames mid-way), stance 80–129 sliding 6 cm
    forward, 5 mm into the floor."""
    heel = np.zeros((130, 3))
    heel[40:50, 2] = np.linspace(0.005, 0.05, 10)  # heel lifts, toe stays put: a roll, no skate
    swing = np.sin(np.linspace(0, np.pi, 32))[1:-1]
    heel[50:80, 0] = np.linspace(0.0, 0.5, 30)
    heel[50:80, 2] = 0.05 + 0.05 * swing
    heel[64:66, 2] = 0.01  # a 2-frame scuff: too short for a stance
    heel[80:, 0] = 0.5 + np.linspace(0.0, 0.06, 50)
    heel[80:, 2] = -0.005
    toe = heel + [0.18, 0.0, 0.0]
    toe[40:50] = toe[39]
    return np.stack([heel, toe], axis=1)


def test_stances_are_found_and_short_touches_ignored():
    low = _foot()[..., 2].min(axis=1)
    assert stances(low, DT) == [(0, 50), (80, 130)]
    assert stances(low, DT, min_stance_s=0.0) == [(0, 50), (64, 66), (80, 130)]


def test_skate_counts_slide_not_roll():
    points = _foot()
    assert stance_skate(points, 0, 50) == pytest.approx(0.0, abs=1e-12)
    assert stance_skate(points, 80, 130) == pytest.approx(0.06, abs=1e-9)
    report = foot_report({"left": points}, DT)
    assert report.stances == 2
    assert report.foot_skate_m == pytest.approx(0.03, abs=1e-9)
    assert report.floor_penetration_m == pytest.approx(0.005)
    assert report.ground_clearance_m == pytest.approx(0.10, abs=2e-3)


def test_cleanup_plan_holds_the_sliding_stance_and_lifts_the_scuff():
    points = _foot()
    correction, holds = foot_corrections(points, DT)
    start, end = holds[-1]
    assert start <= 85 and end >= 125
    cleaned = points + correction[:, None, :]
    report = foot_report({"left": cleaned}, DT)
    assert report.foot_skate_m < 0.002  # was 0.03
    assert report.floor_penetration_m < 1e-9  # was 0.005
    assert cleaned[64:66, :, 2].min() > 0.02  # the scuff is lifted off the floor
    np.testing.assert_allclose(correction[55:60], 0.0)  # mid-swing far from contact is untouched


def test_a_bounce_inside_a_stance_is_one_stance_and_its_displacement_counts():
    # A still heel-and-toe foot that rises to 3 cm for 0.03 s (shorter than BOUNCE_S) and lands
    # 4 cm further on: one stance whose skate is the 4 cm, not two stances of no skate.
    points = np.zeros((60, 2, 3))
    points[:, 1, 0] = 0.18
    points[20:23, :, 2] = 0.03
    points[23:, :, 0] += 0.04
    low = points[..., 2].min(axis=1)
    assert stances(low, DT) == [(0, 60)]
    assert stances(low, DT, bounce_s=0.0) == [(0, 20), (23, 60)]
    report = foot_report({"left": points}, DT)
    assert report.stances == 1
    assert report.foot_skate_m == pytest.approx(0.04, abs=1e-9)
    assert report.ground_clearance_m is None  # a bounce is no swing


def test_a_lift_as_long_as_a_step_is_not_a_bounce():
    points = np.zeros((60, 2, 3))
    points[20:26, :, 2] = 0.03  # 0.06 s off the floor: longer than BOUNCE_S
    low = points[..., 2].min(axis=1)
    assert stances(low, DT) == [(0, 20), (26, 60)]


def test_the_worst_stance_is_reported_beside_the_mean():
    points = _foot()
    report = foot_report({"left": points, "right": points + [0.0, 0.3, 0.0]}, DT)
    assert report.stances == 4
    assert report.foot_skate_m == pytest.approx(0.03, abs=1e-9)
    assert report.foot_skate_max_m == pytest.approx(0.06, abs=1e-9)
    assert report.summary()["foot_skate_max_m"] == pytest.approx(0.06)
