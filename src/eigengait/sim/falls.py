"""The one rule for "the creature has fallen", shared by the gait runner, the optimizer and the
balance tracker.

A creature has fallen when its centre of mass is below `COM_DROP` of its reference height (the
standing COM height for a gait, the tracked clip's COM height for the tracker), when its root turns
upside down (the root's up axis points below the horizon), or when a body other than the feet lies
on the floor (the tracker's contacts). Over recorded rollouts (`fallen`, `failed_steps`), a state
that is not finite counts as a fall too, and a blow-up (`sim/stepping.py`) as a failure.
"""

from __future__ import annotations

import numpy as np

from eigengait.sim.recording import RolloutView
from eigengait.sim.stepping import blown_up_steps

COM_DROP = 0.5  # share of the reference COM height below which the creature has fallen
# any state entry beyond this reads as non-finite: unlike MAX_SPEED it also bounds positions/act
STATE_LIMIT = 1e6


def has_fallen(com_z, reference_z, up_z=1.0, body_on_floor=False):
    """Elementwise: COM height (m) below COM_DROP × `reference_z` (m), root up axis z (−1…1) below
    0, or a body other than the feet on the floor."""
    return (
        (np.asarray(com_z) < COM_DROP * np.asarray(reference_z))
        | (np.asarray(up_z) < 0)
        | np.asarray(body_on_floor)
    )


def fallen(
    view: RolloutView, states: np.ndarray, sensors: np.ndarray, standing_com: float
) -> np.ndarray:
    """Per row of recorded states and sensors (…): fallen by `has_fallen` against the standing COM
    height (m), or a state entry that is not finite or beyond `STATE_LIMIT`."""
    physics = view.physics(states)
    finite = np.isfinite(physics).all(axis=-1) & (np.abs(physics) < STATE_LIMIT).all(axis=-1)
    return has_fallen(view.com(sensors)[..., 2], standing_com, view.up_z(states)) | ~finite


def failed_steps(
    view: RolloutView,
    states: np.ndarray,
    sensors: np.ndarray,
    clock_before: np.ndarray,
    standing_com: float,
    dt: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A rollout chunk's failures per row and step (rows × steps): fallen or blown up; blown up
    alone; and the chunk's qvel (rows × steps × nv) that `blown_up_dof` reads. `clock_before`
    (rows × 1): each row's time (s) before the chunk's first step, so a clock that restarts is
    caught as a blow-up; `dt`: the timestep (s)."""
    qvel = view.qvel(states)
    blown = blown_up_steps(qvel, np.concatenate([clock_before, view.time(states)], axis=-1), dt)
    return fallen(view, states, sensors, standing_com) | blown, blown, qvel
