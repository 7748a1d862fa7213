"""Skip a clip's lead-in: the frames before its motion starts.

Many exports begin with a synthetic pose (the T-pose of CMU's frame 0) and some blend from it into
the motion over a few frames (the Daz-skeleton CMU files: about 20° per frame at 120 frames/s for
four frames). Started there, a reference begins with joint speeds of thousands of degrees per second
that no controller can follow. The lead-in ends at the first frame whose largest bone rotation to
the next frame is within `LEAD_IN_FACTOR` times the clip's median; at most `LEAD_IN_MAX_S` of the
clip is skipped, so a clip that starts in fast motion keeps its start.
"""

from __future__ import annotations

import numpy as np

from eigengait.motion.bvh import BvhClip, global_transforms

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
