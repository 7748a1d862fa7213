"""The root translation's scale is fitted to the legs: a path k times too long is found to need
1/k."""

import numpy as np
import pytest

from eigengait.motion.root_scale import MIN_TRAVEL_M, leg_consistent_factor

FRAME_TIME = 0.01


def _foot_x(t: np.ndarray, delay: float) -> tuple[np.ndarray, np.ndarray]:
    """A foot that stands still for half of each second at x = k + 0.25 + delay and swings to the
    next spot at 2 m/s in the other half; returns its x (m) and whether it supports."""
    local = t - delay
    k, phase = np.floor(local), local - np.floor(local)
    supports = phase < 0.5
    x = np.where(supports, k + 0.25, k + 0.25 + 2.0 * (phase - 0.5)) + delay
    return x, supports


def _walk(stretch: float, frames: int = 300) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """A root moving at 1 m/s along x whose two feet alternately stand still (the legs carry the
    body 1 m/s); the root path is then stretched by `stretch`, as a mis-scaled clip's would be, with
    the feet's offsets from the root (fixed by the joint rotations) kept."""
    t = np.arange(frames) * FRAME_TIME
    root = np.stack([t, np.zeros_like(t), np.full_like(t, 0.9)], axis=1)
    offsets = {}
    for name, delay in (("left", 0.0), ("right", 0.5)):
        x, supports = _foot_x(t, delay)
        centre = np.stack([x, np.zeros_like(t), np.where(supports, 0.0, 0.1)], axis=1)
        offsets[name] = (
            np.stack([centre + [0.09, 0, 0], centre - [0.09, 0, 0]], axis=1) - root[:, None]
        )
    stretched = root * [stretch, 1, 1]
    return stretched, {f: stretched[:, None] + o for f, o in offsets.items()}


@pytest.mark.parametrize("stretch", [1.5, 1.0, 0.8])
def test_the_factor_undoes_a_stretched_root_path(stretch):
    root, soles = _walk(stretch)
    assert leg_consistent_factor(root, soles, FRAME_TIME) == pytest.approx(1.0 / stretch, rel=0.02)


def test_a_clip_that_does_not_travel_keeps_its_scale():
    root, soles = _walk(1.5, frames=int(MIN_TRAVEL_M / 1.5 / FRAME_TIME))
    assert leg_consistent_factor(root, soles, FRAME_TIME) == 1.0
