"""Gait-quality figures of a played motion: cadence, stride, flight, duty factors, slip, tilt,
footfall, jumps.

Everything is measured on frames sampled at `fps` in MuJoCo's z-up world (x forward, metres,
seconds); frame i is at t = i / fps. A foot is on the ground by the rule of `sim/contacts.py`
(a contact sphere's bottom within 5 mm of the floor); gaps, then contacts, shorter than `DEBOUNCE_S`
inside the recording are ignored,
so a grazing frame is neither a step nor a flight.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from eigengait.sim.contacts import foot_touching, spheres_touching
from eigengait.sim.recording import RolloutView, frame_rows
from eigengait.sim.root import root_layout

# frames/s at which playback records a gait, and the optimizers measure its slip
PLAYBACK_FPS = 60.0
DEBOUNCE_S = 0.02  # s
SAME_STEP_S = 0.05  # s: touchdowns of different feet this close count as one step
_ROTATION_DOFS = {
    int(mujoco.mjtJoint.mjJNT_FREE): (3, 6),
    int(mujoco.mjtJoint.mjJNT_BALL): (0, 3),
    int(mujoco.mjtJoint.mjJNT_HINGE): (0, 1),
}  # joint type -> its rotation's range in its dofs


@dataclass
class GaitRecording:
    """A played motion sampled at `fps` frames/s (MuJoCo z-up world, x forward, metres, seconds)."""

    fps: float
    period: float  # s, one controller cycle (phase = (t mod period) / period, t = frame / fps)
    # F × nq MuJoCo positions; the root's joints come first (free: pos xyz, quat wxyz; planar: its
    # slides and its pitch hinge)
    qpos: np.ndarray
    com: np.ndarray  # F × 3 whole-body COM (m)
    # foot name -> F × k × 3 world positions of the foot's contact-sphere centres
    foot_points: dict[str, np.ndarray]
    foot_radius: dict[str, float]  # foot name -> contact-sphere radius (m)


def _runs(on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Start and end (exclusive) frame indices of the True runs of a (F,) bool array."""
    edges = np.diff(np.r_[0, on.astype(np.int8), 0])
    return np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)


def _debounce(on: np.ndarray, min_frames: float) -> np.ndarray:
    """Fill gaps shorter than `min_frames`, then drop contacts shorter than it; runs touching either
    end of the recording are kept, their true length being unknown."""
    for value in (False, True):
        starts = np.flatnonzero(np.r_[True, on[1:] != on[:-1]])
        lengths = np.diff(np.r_[starts, len(on)])
        values = on[starts]
        flip = (values == value) & (lengths < min_frames)
        flip[[0, -1]] = False
        on = np.repeat(values ^ flip, lengths)
    return on


def _foot_contact(points: np.ndarray, radius: float, fps: float) -> np.ndarray:
    """(F,) bool: some contact sphere (centres `points`, F × k × 3, m) touches the ground, debounced
    (gaps, then contacts, shorter than `DEBOUNCE_S` inside the recording ignored)."""
    on = foot_touching(points, radius)
    return _debounce(on, DEBOUNCE_S * fps) if len(on) > 2 else on


def foot_contacts(rec: GaitRecording) -> dict[str, np.ndarray]:
    """foot -> (F,) bool: the foot is on the ground (`_foot_contact`)."""
    return {f: _foot_contact(p, rec.foot_radius[f], rec.fps) for f, p in rec.foot_points.items()}


def _stance_slips(points: np.ndarray, radius: float, contact: np.ndarray) -> np.ndarray:
    """Per stance (run of `contact`): the largest horizontal (xy) distance, in m, one sphere centre
    travels between the first and last frames of a run in which it touches throughout. points F × k
    × 3."""
    spheres = spheres_touching(points[..., 2], radius)
    stance_starts, _ = _runs(contact)
    slip = np.zeros(len(stance_starts))
    for k in range(spheres.shape[1]):
        a, b = _runs(spheres[:, k] & contact)
        travel = np.linalg.norm(points[b - 1, k, :2] - points[a, k, :2], axis=1)
        np.maximum.at(slip, np.searchsorted(stance_starts, a, side="right") - 1, travel)
    return slip


def stance_slips(
    foot_points: dict[str, np.ndarray], foot_radius: dict[str, float], fps: float
) -> dict:
    """foot -> (stances,) `_stance_slips` in m: the feet's contact-sphere centres (foot -> F × k
    × 3, world, m) sampled at `fps` frames/s. Their mean per foot is `stance_slip_m` of
    `gait_metrics`."""
    return {
        foot: _stance_slips(
            points, foot_radius[foot], _foot_contact(points, foot_radius[foot], fps)
        )
        for foot, points in foot_points.items()
    }


def rollout_stance_slips(
    view: RolloutView, first: np.ndarray, sensors: np.ndarray, timestep: float
) -> dict:
    """`stance_slips` of a rollout as playback records it: `first` the sensor row before its first
    step, `sensors` one row per physics step of `timestep` s, sampled at `PLAYBACK_FPS`
    (`sim.recording.frame_rows`)."""
    rows = _playback_rows(first, sensors, timestep)
    points = {f: view.foot_points(rows, f) for f in view.foot_radius}
    return stance_slips(points, view.foot_radius, PLAYBACK_FPS)


def _playback_rows(first: np.ndarray, sensors: np.ndarray, timestep: float) -> np.ndarray:
    """A rollout's sensor rows (`first` before its first step, then one per physics step of
    `timestep` s) at the frames playback records, `PLAYBACK_FPS` (`sim.recording.frame_rows`)."""
    return np.vstack([first, sensors])[frame_rows(len(sensors), timestep, PLAYBACK_FPS)]


def rollout_footfalls(
    view: RolloutView,
    first: np.ndarray,
    sensors: np.ndarray,
    timestep: float,
    period: float,
    after_s: float = 0.0,
) -> dict:
    """foot -> `footfall` (touchdown phase in a cycle of `period` s, 0-1; None without touchdown)
    of a rollout as playback records it (`rollout_stance_slips`), counting the touchdowns from
    `after_s` s on."""
    rows = _playback_rows(first, sensors, timestep)
    footfall = {}
    for foot, radius in view.foot_radius.items():
        touchdowns = touchdown_frames(
            _foot_contact(view.foot_points(rows, foot), radius, PLAYBACK_FPS)
        )
        footfall[foot] = _footfall(
            touchdowns[touchdowns >= after_s * PLAYBACK_FPS], PLAYBACK_FPS, period
        )
    return footfall


def phase_distance(a: float, b: float) -> float:
    """Distance (in cycles, 0-0.5) between two cycle phases in [0, 1)."""
    d = abs(a - b) % 1.0
    return min(d, 1.0 - d)


def _swing_clearances(points: np.ndarray, radius: float, contact: np.ndarray) -> np.ndarray:
    """Per swing (a run off the ground that both begins and ends inside the recording): the highest
    the foot's lowest contact sphere bottom rises above the floor, in m. points F × k × 3."""
    bottom = points[..., 2].min(axis=1) - radius
    starts, ends = _runs(~contact)
    inside = (starts > 0) & (ends < len(contact))
    return np.array([bottom[a:b].max() for a, b in zip(starts[inside], ends[inside])])


def touchdown_frames(contact: np.ndarray) -> np.ndarray:
    """Frame indices where a contact begins after a frame without it (rising edges)."""
    starts, _ = _runs(contact)
    return starts[starts > 0]


def _step_count(touchdowns: dict[str, np.ndarray], window: float) -> int:
    """Touchdowns (frame indices per foot) grouped into steps: a step gathers the touchdowns of
    different feet within `window` frames of its first one."""
    steps, first, landed = 0, -math.inf, set()
    for frame, foot in sorted((int(i), f) for f, frames in touchdowns.items() for i in frames):
        if frame - first > window + 1e-9 or foot in landed:
            steps, first, landed = steps + 1, frame, set()
        landed.add(foot)
    return steps


def _footfall(touchdowns: np.ndarray, fps: float, period: float) -> float | None:
    """Circular mean of the touchdowns' cycle phases (t mod period) / period, in [0, 1); None
    without touchdown."""
    if not touchdowns.size:
        return None
    phases = np.mod(touchdowns / fps, period) / period
    return round(circular_mean_turn(phases), 4) % 1.0


def circular_mean_turn(phases) -> float:
    """Circular mean of cycle phases (fractions of a turn), in (−0.5, 0.5]."""
    return float(np.angle(np.mean(np.exp(2j * np.pi * np.asarray(phases))))) / (2 * np.pi)


def _root_tilt_series(model: mujoco.MjModel, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pitch and roll (degrees) per frame: the root's `RootLayout.tilt_deg` (a free root through its
    quaternion, a planar root's hinge about y as pitch and no roll); NaN for a model without
    joints."""
    if not model.njnt:
        return (np.full(len(qpos), np.nan),) * 2
    return root_layout(model, int(model.jnt_bodyid[0])).tilt_deg(qpos)


def _max_root_jump_m(model: mujoco.MjModel, qpos: np.ndarray) -> float:
    """Largest root translation between consecutive frames (m), free or planar root."""
    position = root_layout(model, int(model.jnt_bodyid[0])).position(qpos)
    return float(np.linalg.norm(np.diff(position, axis=0), axis=1).max())


def _rotation_dofs(model: mujoco.MjModel) -> list[np.ndarray]:
    """Velocity indices of each joint's rotation: a free joint's last 3, a ball joint's 3, a
    hinge's 1."""
    out = []
    for kind, adr in zip(model.jnt_type, model.jnt_dofadr):
        if int(kind) in _ROTATION_DOFS:
            a, b = _ROTATION_DOFS[int(kind)]
            out.append(np.arange(adr + a, adr + b))
    return out


def _max_frame_jump_deg(model: mujoco.MjModel, qpos: np.ndarray) -> float:
    """Largest rotation of one joint between consecutive frames (degrees): norm of a ball or free
    joint's rotation vector, |angle| of a hinge, from mj_differentiatePos over one frame."""
    qpos = np.asarray(qpos, dtype=np.float64)
    v = np.zeros((len(qpos) - 1, model.nv))
    for i in range(len(v)):
        mujoco.mj_differentiatePos(model, v[i], 1.0, qpos[i], qpos[i + 1])
    return float(
        np.degrees(
            max((np.linalg.norm(v[:, d], axis=1).max() for d in _rotation_dofs(model)), default=0.0)
        )
    )


def rounded(x) -> float | None:
    """A plain float rounded to 4 decimals, None when undefined or not finite."""
    return round(float(x), 4) if x is not None and np.isfinite(x) else None


def gait_metrics(model: mujoco.MjModel, rec: GaitRecording) -> dict:
    """JSON-ready gait-quality figures of a recording of F ≥ 1 frames (plain floats rounded to 4
    decimals, None where a figure is undefined or not finite).

    Rates use the played time F / fps (each frame stands for 1 / fps s): `cadence_spm` (steps per
    minute; a step is the touchdowns, i.e. contact rising edges, of different feet within
    `SAME_STEP_S` of its first one), `flight_fraction` (share of frames with no foot in contact),
    `duty_factor` per foot. `stride_m` is the COM's forward (x) speed between the first and last
    frames, (x_last − x_first) / ((F − 1) / fps), times the period. `stance_slip_m` per foot is the
    mean over its stances of `_stance_slips`, `stance_slip_max_m` the largest foot value;
    `swing_clearance_m` per foot is the mean over its swings of `_swing_clearances` (how high the
    foot lifts: a shuffle that grazes the floor counts as flight but shows millimetres here);
    `footfall` per foot is `_footfall` of its touchdowns.
    `torso_pitch_deg` and `torso_roll_deg` are [min, max] of `_root_tilt_series` (a planar root: its
    pitch hinge, roll 0). `max_frame_jump_deg` is the largest joint rotation between consecutive
    frames, `max_root_jump_m` the largest root translation (a planar root: its forward and vertical
    slides).
    """
    frames = len(rec.qpos)
    contacts = foot_contacts(rec)
    touchdowns = {f: touchdown_frames(c) for f, c in contacts.items()}
    in_contact = np.any(list(contacts.values()), axis=0) if contacts else np.zeros(frames, bool)
    slips = stance_slips(rec.foot_points, rec.foot_radius, rec.fps)
    slip = {f: rounded(v.mean()) if v.size else None for f, v in slips.items()}
    clearances = {
        f: _swing_clearances(rec.foot_points[f], rec.foot_radius[f], c) for f, c in contacts.items()
    }
    pitch, roll = _root_tilt_series(model, rec.qpos)
    moved = frames > 1
    return {
        "cadence_spm": rounded(
            60.0 * _step_count(touchdowns, SAME_STEP_S * rec.fps) * rec.fps / frames
        ),
        "stride_m": rounded((rec.com[-1, 0] - rec.com[0, 0]) * rec.fps / (frames - 1) * rec.period)
        if moved
        else None,
        "flight_fraction": rounded(1.0 - in_contact.mean()),
        "duty_factor": {f: rounded(c.mean()) for f, c in contacts.items()},
        "stance_slip_m": slip,
        "stance_slip_max_m": max((s for s in slip.values() if s is not None), default=None),
        "swing_clearance_m": {
            f: rounded(c.mean()) if c.size else None for f, c in clearances.items()
        },
        "torso_pitch_deg": [rounded(pitch.min()), rounded(pitch.max())],
        "torso_roll_deg": [rounded(roll.min()), rounded(roll.max())],
        "footfall": {f: _footfall(t, rec.fps, rec.period) for f, t in touchdowns.items()},
        "max_frame_jump_deg": rounded(_max_frame_jump_deg(model, rec.qpos)) if moved else None,
        "max_root_jump_m": rounded(_max_root_jump_m(model, rec.qpos))
        if moved and model.njnt
        else None,
    }
