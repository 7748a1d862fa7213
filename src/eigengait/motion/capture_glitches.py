"""Repair motion-capture glitches: a joint that turns faster than a human joint can.

Optical capture loses or swaps markers now and then, and the solved skeleton then flips a limb for a
few frames and back: CMU's dance 05_14 turns its right thigh at 4 100-6 200°/s for 0.04 s, its dance
05_15 the right thigh and foot at 3 400-5 100°/s for 0.06 s (the foot travels 30 cm per frame and
returns). Tracked, the body follows the flipped leg and falls. Human joints do not turn that fast
outside throwing: a soccer kick's knee extends at 1 500-2 300°/s, its hip at under 1 000°/s, while a
baseball pitch turns the shoulder at up to 7 000-7 500°/s. Over the legs, the hips and the spine of
57 clips (CMU, Bandai Namco, another studio's walk) the fastest joint otherwise turned at 1 100°/s.

A joint whose rotation relative to its parent exceeds MAX_BODY_SPEED_DEG_S (legs, pelvis, spine up
to the torso joint) or MAX_LIMB_SPEED_DEG_S (arms, neck, head, and every joint of a skeleton whose
legs are not found by name) between two frames is glitched over those
frames; such frame pairs less than JOIN_S apart are one glitch, grown by MARGIN_S on each side.
Its local rotation is then replaced by a cubic rotation spline through the good frames within
KEYS_S on each side (held at the last good pose when the glitch reaches the clip's end), so a limb
flipped mid-swing is filled along its swing. Other joints and the root's position are
kept.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation, RotationSpline

from eigengait.motion.bvh import BvhClip, local_transforms
from eigengait.motion.skeleton_names import find_roles

MAX_BODY_SPEED_DEG_S = 3000.0  # above a kick's knee extension (1 500-2 300°/s)
MAX_LIMB_SPEED_DEG_S = 7500.0  # a baseball pitch's shoulder rotation
JOIN_S = 0.05  # s: faster frame pairs closer than this are one glitch
MARGIN_S = 0.025  # s added on each side of a glitch
KEYS_S = 0.05  # s of good frames on each side that the fill passes through


@dataclass(frozen=True)
class Glitch:
    """One repaired glitch: joint name and the clip time span (s) whose rotation was replaced."""

    joint: str
    start_s: float
    end_s: float


def joint_speeds_deg_s(clip: BvhClip) -> np.ndarray:
    """Rotation speed (deg/s) of each joint relative to its parent between consecutive frames
    (F−1, J)."""
    rot, _ = local_transforms(clip)
    relative = np.swapaxes(rot[:-1], -1, -2) @ rot[1:]
    cosine = (np.trace(relative, axis1=-2, axis2=-1) - 1.0) / 2.0
    return np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))) / clip.frame_time


def speed_bounds_deg_s(clip: BvhClip) -> np.ndarray:
    """Per joint (J,): MAX_BODY_SPEED_DEG_S on the legs (the thighs and everything below them) and
    on the trunk (the thighs' and the torso's ancestors, root included), MAX_LIMB_SPEED_DEG_S
    elsewhere."""
    bounds = np.full(len(clip.joints), MAX_LIMB_SPEED_DEG_S)
    roles = find_roles(clip)
    thighs = [clip.joint_index(roles[r]) for r in ("left_thigh", "right_thigh") if r in roles]
    trunk = thighs + ([clip.joint_index(roles["torso"])] if "torso" in roles else [])
    for joint in trunk:
        ancestor = joint
        while ancestor >= 0:
            bounds[ancestor] = MAX_BODY_SPEED_DEG_S
            ancestor = clip.joints[ancestor].parent
    for index, joint in enumerate(clip.joints):
        ancestor = joint.parent
        while ancestor >= 0 and ancestor not in thighs:
            ancestor = clip.joints[ancestor].parent
        if ancestor in thighs:
            bounds[index] = MAX_BODY_SPEED_DEG_S
    return bounds


def _spans(fast: np.ndarray, join: int, margin: int, n_frames: int) -> list[tuple[int, int]]:
    """Frame spans [start, end) to replace, from the fast frame pairs `fast` (F−1,) bool: a pair
    (f, f + 1) marks frame f + 1 bad up to the last fast pair's frame f, pairs within `join` frames
    merged, each span grown by `margin` frames and kept off the first and last frame's anchors."""
    pairs = np.flatnonzero(fast)
    spans: list[list[int]] = []
    for f in pairs:
        if spans and f - spans[-1][1] <= join:
            spans[-1][1] = f
        else:
            spans.append([f, f])
    out = []
    for first, last in spans:
        start, end = max(first + 1 - margin, 1), min(last + 1 + margin, n_frames)
        if out and start <= out[-1][1]:
            out[-1] = (out[-1][0], end)
        else:
            out.append((start, end))
    return out


def _euler_channels(joint_channels: list[str]) -> tuple[str, list[int]]:
    """SciPy intrinsic sequence ('ZXY') of a joint's rotation channels and their positions."""
    seq, cols = "", []
    for k, channel in enumerate(joint_channels):
        if channel.endswith("rotation"):
            seq += channel[0]
            cols.append(k)
    return seq, cols


def repair_glitches(clip: BvhClip, start_frame: int = 0) -> tuple[BvhClip, list[Glitch]]:
    """A copy of `clip` with its glitches (module doc) from `start_frame` on repaired, and the list
    of what was replaced. Frames before `start_frame` (a lead-in) are neither read nor changed."""
    if clip.n_frames - start_frame < 3:
        return clip, []
    tail = BvhClip(clip.joints, clip.frame_time, clip.frames[start_frame:])
    fast = joint_speeds_deg_s(tail) > speed_bounds_deg_s(clip)
    join = max(1, int(round(JOIN_S / clip.frame_time)))
    margin = int(round(MARGIN_S / clip.frame_time))
    frames, glitches = clip.frames.copy(), []
    slices = clip.channel_slices()
    keys = max(2, int(round(KEYS_S / clip.frame_time)))
    for index, joint in enumerate(clip.joints):
        seq, cols = _euler_channels(joint.channels)
        if not fast[:, index].any() or len(seq) != 3:
            continue
        columns = [slices[index].start + k for k in cols]
        for start, end in _spans(fast[:, index], join, margin, tail.n_frames):
            times = np.arange(start, end) + start_frame
            before = np.arange(max(start - keys, 0), start) + start_frame
            after = np.arange(end, min(end + keys, tail.n_frames)) + start_frame
            known = np.concatenate([before, after])
            rotations = Rotation.from_euler(seq, frames[known][:, columns], degrees=True)
            if len(after) == 0:  # a glitch reaching the clip's end
                filled = Rotation.concatenate([rotations[-1]] * len(times))
            else:
                filled = RotationSpline(known, rotations)(times)
            angles = filled.as_euler(seq, degrees=True)
            guide = np.array([np.interp(times, known, frames[known, c]) for c in columns]).T
            frames[times[:, None], columns] = angles + 360.0 * np.round((guide - angles) / 360.0)
            glitches.append(
                Glitch(
                    joint=joint.name,
                    start_s=round(float(times[0] * clip.frame_time), 4),
                    end_s=round(float((times[-1] + 1) * clip.frame_time), 4),
                )
            )
    return BvhClip(clip.joints, clip.frame_time, frames), glitches
