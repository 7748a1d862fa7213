"""The push-off windows before a reference's flights (`takeoff.py`), where the QP tracks the COM's
vertical motion harder."""

import numpy as np

from eigengait.control.balance import wbc
from eigengait.control.balance.double_support import CONTACT_M
from eigengait.control.balance.takeoff import TAKEOFF_COM_GAIN, takeoff_windows
from eigengait.motion.tracking import run_track
from shared_data import MOCAP


def test_the_window_covers_the_push_off_before_each_flight_and_nothing_else():
    # 100 frames at 0.01 s, two feet: a run with flights at frames 40-49 and 80-89 (both feet up),
    # single stances in between, and one foot lifted alone at frames 10-19 (a walk's swing)
    heights = np.zeros((100, 2))
    heights[10:20, 1] = 0.1
    heights[40:50] = heights[80:90] = 0.1
    windows = takeoff_windows(heights, 0.01, window_s=0.05)
    np.testing.assert_array_equal(np.flatnonzero(windows), [*range(35, 40), *range(75, 80)])


def test_a_clip_without_flight_has_no_window_and_a_foot_on_the_floor_line_is_down():
    heights = np.full((50, 2), CONTACT_M)  # both feet exactly at the contact height: down
    heights[20:30, 0] = 0.2
    assert not takeoff_windows(heights, 1 / 120).any()


def test_a_flight_that_starts_the_clip_has_no_push_off_to_weight():
    heights = np.zeros((30, 2))
    heights[:10] = 0.3  # the clip starts in the air
    assert not takeoff_windows(heights, 0.01).any()


def test_tracking_the_runs_take_offs_harder_keeps_its_flights_near_the_reference(monkeypatch):
    # measured (CMU 16_36 run, robustness 0.5): COM error 3.3 cm with the take-off weighting, 4.7 cm
    # without, the body flying higher than the reference after each push-off
    errors = {}
    for gain in (1.0, TAKEOFF_COM_GAIN):
        monkeypatch.setattr(wbc, "TAKEOFF_COM_GAIN", gain)
        _, _, result = run_track(
            MOCAP / "cmu_16_36_run_daz.bvh",
            "walker",
            0.5,
            push=None,
            mapping=None,
            start_frame=1,
            tolerance=0.0,
        )
        assert not result.fell
        errors[gain] = result.com_error_m
    assert errors[TAKEOFF_COM_GAIN] < 0.8 * errors[1.0]
    assert errors[TAKEOFF_COM_GAIN] < 0.05  # the COM target
