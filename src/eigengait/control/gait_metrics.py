"""Gait-quality figures of a played motion: cadence, stride, flight, duty factors, slip, tilt, footfall, jumps.

Everything is measured on frames sampled at `fps` in MuJoCo's z-up world (x forward, metres, seconds). A foot is
on the ground when one of its contact spheres' bottom (centre z − radius) is within `tolerance` of the floor;
contacts and gaps shorter than `DEBOUNCE_S` are ignored, so a grazing frame is neither a step nor a flight.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

CONTACT_TOLERANCE = 0.005   # m
DEBOUNCE_S = 0.02           # s
SAME_STEP_S = 0.05          # s: touchdowns of different feet this close count as one step


@dataclass
class GaitRecording:
    """A played motion sampled at `fps` frames/s (MuJoCo z-up world, x forward, metres, seconds)."""
    fps: float
    period: float                        # s, one controller cycle (phase = (t mod period) / period)
    qpos: np.ndarray                     # F × nq MuJoCo positions; joint 0 is the root free joint
    com: np.ndarray                      # F × 3 whole-body COM (m)
    foot_points: dict[str, np.ndarray]   # foot -> F × k × 3 world positions of its contact-sphere centres
    foot_radius: dict[str, float]        # foot -> contact-sphere radius (m)


def _debounce(on: np.ndarray, frames: int) -> np.ndarray:
    """Fill gaps shorter than `frames`, then drop contacts shorter than `frames`."""
    out = on.copy()
    for value in (False, True):
        runs = _runs(out == value)
        for a, b in runs:
            if b - a < frames and a > 0 and b < len(out):
                out[a:b] = not value
    return out


def _runs(on: np.ndarray) -> list[tuple[int, int]]:
    """[start, end) index pairs of the True runs."""
    edges = np.diff(np.r_[0, on.astype(int), 0])
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)))


def sphere_contacts(rec: GaitRecording, foot: str, tolerance: float = CONTACT_TOLERANCE) -> np.ndarray:
    """(F × k) bool: each contact sphere of the foot within `tolerance` of the floor."""
    return rec.foot_points[foot][..., 2] - rec.foot_radius[foot] <= tolerance


def foot_contacts(rec: GaitRecording, tolerance: float = CONTACT_TOLERANCE) -> dict[str, np.ndarray]:
    """foot -> (F,) bool: the foot is on the ground (debounced)."""
    frames = max(1, int(round(DEBOUNCE_S * rec.fps)))
    return {f: _debounce(sphere_contacts(rec, f, tolerance).any(axis=1), frames) for f in rec.foot_points}


def root_tilt_deg(quat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pitch (about world y, nose down positive) and roll (about world x, right side down positive), degrees,
    from root quaternions (F × 4, wxyz): pitch = asin(−R₂₀), roll = asin(R₂₁), yaw-independent."""
    w, x, y, z = quat.T
    pitch = np.degrees(np.arcsin(np.clip(-2 * (x * z - w * y), -1, 1)))
    roll = np.degrees(np.arcsin(np.clip(2 * (y * z + w * x), -1, 1)))
    return pitch, roll


def frame_jumps(model: mujoco.MjModel, qpos: np.ndarray) -> tuple[float, float]:
    """Largest joint-angle change between consecutive frames (degrees; ball joints and the root's rotation by the
    norm of their rotation vector) and largest root translation between frames (m)."""
    if len(qpos) < 2:
        return 0.0, 0.0
    v = np.zeros(model.nv)
    angle, root = 0.0, float(np.linalg.norm(np.diff(qpos[:, 0:3], axis=0), axis=1).max())
    groups = []
    for j in range(model.njnt):
        d, kind = int(model.jnt_dofadr[j]), model.jnt_type[j]
        if kind == mujoco.mjtJoint.mjJNT_FREE:
            groups.append(slice(d + 3, d + 6))
        elif kind == mujoco.mjtJoint.mjJNT_BALL:
            groups.append(slice(d, d + 3))
        elif kind == mujoco.mjtJoint.mjJNT_HINGE:
            groups.append(slice(d, d + 1))
    for a, b in zip(qpos[:-1], qpos[1:]):
        mujoco.mj_differentiatePos(model, v, 1.0, a, b)
        angle = max(angle, max(float(np.linalg.norm(v[g])) for g in groups))
    return float(np.degrees(angle)), root


def _stance_slip(rec: GaitRecording, foot: str, contact: np.ndarray) -> list[float]:
    """Per stance: the largest horizontal travel of a sphere between its first and last in-contact frames."""
    spheres = sphere_contacts(rec, foot)
    points = rec.foot_points[foot]
    out = []
    for a, b in _runs(contact):
        travel = 0.0
        for k in range(spheres.shape[1]):
            on = np.flatnonzero(spheres[a:b, k])
            if on.size:
                p0, p1 = points[a + on[0], k, :2], points[a + on[-1], k, :2]
                travel = max(travel, float(np.linalg.norm(p1 - p0)))
        out.append(travel)
    return out


def _circular_mean(phases: np.ndarray) -> float:
    angle = np.angle(np.mean(np.exp(2j * np.pi * phases)))
    return float(np.mod(angle / (2 * np.pi), 1.0))


def _round(x):
    return None if x is None else round(float(x), 4)


def gait_metrics(model: mujoco.MjModel, rec: GaitRecording) -> dict:
    """JSON-ready figures of the played motion (None where a figure is undefined)."""
    F = len(rec.qpos)
    duration = F / rec.fps
    contacts = foot_contacts(rec)
    touchdowns = {f: np.array([a for a, _ in _runs(c) if a > 0]) / rec.fps for f, c in contacts.items()}
    times = np.sort(np.concatenate([t for t in touchdowns.values()])) if touchdowns else np.zeros(0)
    steps = int(np.sum(np.diff(times) > SAME_STEP_S)) + 1 if times.size else 0
    any_contact = np.any(np.stack(list(contacts.values())), axis=0) if contacts else np.zeros(F, bool)
    slips = {f: _stance_slip(rec, f, c) for f, c in contacts.items()}
    slip = {f: _round(np.mean(s)) if s else None for f, s in slips.items()}
    footfall = {f: _round(_circular_mean(np.mod(t, rec.period) / rec.period)) if t.size else None
                for f, t in touchdowns.items()}
    pitch, roll = root_tilt_deg(rec.qpos[:, 3:7])
    jump_deg, jump_m = frame_jumps(model, rec.qpos)
    known = [v for v in slip.values() if v is not None]
    return {
        "cadence_spm": _round(60.0 * steps / duration) if duration > 0 else None,
        "stride_m": _round((rec.com[-1, 0] - rec.com[0, 0]) / ((F - 1) / rec.fps) * rec.period) if F > 1 else None,
        "flight_fraction": _round(1.0 - any_contact.mean()),
        "duty_factor": {f: _round(c.mean()) for f, c in contacts.items()},
        "stance_slip_m": slip,
        "stance_slip_max_m": _round(max(known)) if known else None,
        "torso_pitch_deg": [_round(pitch.min()), _round(pitch.max())],
        "torso_roll_deg": [_round(roll.min()), _round(roll.max())],
        "footfall": footfall,
        "max_frame_jump_deg": _round(jump_deg),
        "max_root_jump_m": _round(jump_m),
    }
