"""Skip a clip's lead-in: the frames before its motion starts.

Many exports begin with a synthetic pose (the T-pose of CMU's frame 0) and some blend from it into
the motion over a few frames (the Daz-skeleton CMU files: about 20° per frame at 120 frames/s for
four frames). Started there, a reference begins with joint speeds of thousands of degrees per second
that no controller can follow. The lead-in ends at the first frame whose largest bone rotation to
the next frame is within `LEAD_IN_FACTOR` times the clip's median; at most `LEAD_IN_MAX_S` of the
clip is skipped, so a clip that starts in fast motion keeps its start.

The retargeted reference then starts at its first supported pose (`first_supported_pose`): a clip
cut just before a heel strike, the other foot leaving the floor, has no foot on the floor for its
first tenths of a second once the feet are cleaned (the leaving foot is lifted as a swing), and a
simulation started there drops onto the floor. Measured on the CMU walk 08_08 (Daz skeleton, not
in the test corpus): started 0.2 s before its first supported pose, the tracked body fell 10 cm
onto its landing leg and toppled forward at 1.6 s; started on it, it is tracked whole.
"""

from __future__ import annotations

import numpy as np

from eigengait.motion.bvh import BvhClip, global_transforms
from eigengait.motion.foot_metrics import CONTACT_M

LEAD_IN_FACTOR = 4.0  # × the clip's median largest bone rotation per frame
LEAD_IN_MAX_S = 0.1  # s, the longest lead-in skipped


def largest_bone_turns_deg(clip: BvhClip, start_frame: int = 0) -> np.ndarray:
    """Largest rotation (degrees) of any bone, in the file's world axes, from each frame to the next
    (F−1,)."""
    rot, _ = global_transforms(clip)
    rot = rot[start_frame:]
    relative = np.swapaxes(rot[:-1], -1, -2) @ rot[1:]
    cosine = (np.trace(relative, axis1=-2, axis2=-1) - 1.0) / 2.0
    return np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))).max(axis=1)


def first_frame_after_lead_in(clip: BvhClip, start_frame: int) -> int:
    """The first frame at or after `start_frame` where the clip's own motion has begun; a start
    frame outside the clip is returned as it is, for `retarget` to refuse with its error."""
    if not 0 <= start_frame < clip.n_frames - 1:
        return start_frame
    turns = largest_bone_turns_deg(clip, start_frame)
    if turns.size < 2:
        return start_frame
    calm = np.flatnonzero(turns <= LEAD_IN_FACTOR * np.median(turns))
    longest = int(LEAD_IN_MAX_S / clip.frame_time)
    skip = int(calm[0]) if calm.size else 0
    return start_frame + (skip if skip <= longest else 0)


def first_supported_pose(soles: dict[str, np.ndarray]) -> int:
    """Index of the first pose in which some foot's lowest sole point is within CONTACT_M of the
    floor, from the sole points per foot (F, k, 3; world, m, floor at z = 0); 0 when none is."""
    lows = np.min([points[..., 2].min(axis=1) for points in soles.values()], axis=0)
    supported = np.flatnonzero(lows <= CONTACT_M)
    return int(supported[0]) if supported.size else 0
