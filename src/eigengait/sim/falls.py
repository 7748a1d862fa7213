"""The one rule for "the creature has fallen", shared by the gait runner, the optimizer and the balance tracker.

A creature has fallen when its centre of mass is below `COM_DROP` of its reference height (the standing COM
height for a gait, the tracked clip's COM height for the tracker), when its root turns upside down (the root's up
axis points below the horizon), or when a body other than the feet lies on the floor (the tracker's contacts).
"""

from __future__ import annotations

import numpy as np

COM_DROP = 0.5  # share of the reference COM height below which the creature has fallen


def has_fallen(com_z, reference_z, up_z=1.0, body_on_floor=False):
    """Elementwise: COM height (m) below COM_DROP × `reference_z` (m), root up axis z (−1…1) below 0, or a body
    other than the feet on the floor."""
    return (np.asarray(com_z) < COM_DROP * np.asarray(reference_z)) | (np.asarray(up_z) < 0) | np.asarray(body_on_floor)
