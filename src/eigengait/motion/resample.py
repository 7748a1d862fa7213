"""Resample a qpos trajectory by time, for videos and BVH at an exact frame rate.

Simulations record states at their own step (0.5 ms by default) or at a stride of it, which rarely
divides a requested frame period exactly (1/60 s is 33⅓ steps). Rounding the stride changes the
frame rate (60.606 frames/s instead of 60); here every output frame is the pose at its exact time
instead, interpolated between the two recorded samples around it: linearly for positions and hinge
angles, by normalized linear interpolation on the shorter arc for the quaternions of free and ball
joints. Times are in seconds.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.errors import UserInputError


def quaternion_addresses(model: mujoco.MjModel) -> np.ndarray:
    """qpos index of the first component of every quaternion (free-joint orientations and ball
    joints)."""
    addresses = []
    for j in range(model.njnt):
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE:
            addresses.append(model.jnt_qposadr[j] + 3)
        elif model.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL:
            addresses.append(model.jnt_qposadr[j])
    return np.array(addresses, dtype=int)


MAX_FPS = 1000  # frames per second of a video or BVH


def frame_times(duration_s: float, fps: float, speed: float = 1.0) -> np.ndarray:
    """Simulated times (s) of the frames of a video at `fps` that shows `duration_s` of motion at
    `speed`.

    Frame k shows simulated time k·speed/fps: speed 1 plays in real time, 0.5 in slow motion, 2
    twice as fast.
    """
    if not 0 < fps <= MAX_FPS:
        raise UserInputError(
            f"frame rate {fps} is out of range",
            field="fps",
            fix=f"use e.g. fps=30 (at most {MAX_FPS})",
        )
    if not 0.01 <= speed <= 100:
        raise UserInputError(
            f"playback speed {speed} is out of range",
            field="speed",
            fix="use 1 for real time, 0.5 for slow motion",
        )
    count = int(np.floor(duration_s * fps / speed + 1e-9)) + 1
    return np.arange(count) * (speed / fps)


def resample(
    model: mujoco.MjModel, qpos: np.ndarray, times: np.ndarray, new_times: np.ndarray
) -> np.ndarray:
    """Poses (len(new_times) × nq) at `new_times`, interpolated from `qpos` (T × nq) recorded at
    `times`.

    `times` must increase; requested times outside [times[0], times[-1]] take the nearest end pose.
    """
    qpos, times, new_times = (
        np.atleast_2d(qpos),
        np.asarray(times, float),
        np.asarray(new_times, float),
    )
    if len(times) != len(qpos):
        raise ValueError(f"{len(qpos)} poses but {len(times)} times")
    if len(qpos) == 1:
        return np.repeat(qpos, len(new_times), axis=0)
    clipped = np.clip(new_times, times[0], times[-1])
    upper = np.clip(np.searchsorted(times, clipped, side="right"), 1, len(times) - 1)
    lower = upper - 1
    weight = ((clipped - times[lower]) / (times[upper] - times[lower]))[:, None]
    out = (1 - weight) * qpos[lower] + weight * qpos[upper]
    for adr in quaternion_addresses(model):
        q0, q1 = qpos[lower, adr : adr + 4], qpos[upper, adr : adr + 4]
        q1 = np.where(np.sum(q0 * q1, axis=1, keepdims=True) < 0, -q1, q1)
        quat = (1 - weight) * q0 + weight * q1
        out[:, adr : adr + 4] = quat / np.linalg.norm(quat, axis=1, keepdims=True)
    return out


def at_frame_rate(
    model: mujoco.MjModel, qpos: np.ndarray, source_fps: float, fps: float, speed: float = 1.0
) -> np.ndarray:
    """Poses of a trajectory recorded at `source_fps` (sample i at time i/source_fps) for frames at
    exactly `fps`, each frame `speed`/`fps` simulated seconds after the previous one (see
    `frame_times`)."""
    times = np.arange(len(qpos)) / source_fps
    return resample(model, qpos, times, frame_times(times[-1], fps, speed))
