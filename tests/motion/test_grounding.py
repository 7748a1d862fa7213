"""Grounding: the capture floor's drift and a hovering supporting foot are removed, a flight keeps
its height."""

import numpy as np
import pytest

from eigengait.motion.grounding import FLIGHT_M, HOVER_M, floor_offset

FRAME_TIME = 0.01


def _lows(frames: int, drift: float) -> np.ndarray:
    """Lowest foot point (m) on a floor that rises linearly by `drift` over the clip."""
    return np.linspace(0.0, drift, frames)


def test_a_drifting_floor_is_followed():
    lows = _lows(400, 0.06)
    grounded = lows - floor_offset(lows, FRAME_TIME)
    assert np.abs(grounded[50:-50]).max() < 0.002  # within the ends, where the 1-s window is full


def test_a_hovering_foot_is_put_down_and_a_flight_keeps_its_height():
    lows = _lows(400, 0.0)
    hover = slice(100, 160)
    lows[hover] += HOVER_M * 0.8  # the supporting foot 2.4 cm up for 0.6 s
    flight = slice(250, 290)
    lows[flight] += 0.25  # both feet 25 cm up: a jump
    grounded = lows - floor_offset(lows, FRAME_TIME)
    assert np.abs(grounded[110:150]).max() < 0.003
    assert grounded[flight].min() > 0.25 - 0.01 and FLIGHT_M < 0.25


@pytest.mark.parametrize("height", [0.04, 0.06])
def test_between_hover_and_flight_the_correction_fades(height):
    lows = _lows(400, 0.0)
    lows[150:250] += height
    kept = (lows - floor_offset(lows, FRAME_TIME))[200]
    weight = (FLIGHT_M - height) / (FLIGHT_M - HOVER_M)
    assert kept == pytest.approx(height * (1 - weight), abs=0.002)
