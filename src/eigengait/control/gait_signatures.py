"""The figures that tell the thesis's experiments apart (§5.3): sway, twist, skips, crouch, stance
width, a raised foot.

Measured on a `GaitRecording` (MuJoCo z-up world, metres, seconds). "Lateral" is the horizontal
direction square to the COM's overall travel from the first frame to the last (world y when it
travels less than `STILL_M`), so a gait that drifts off the x axis is not read as swaying.
Amplitudes are per full cycle: the half range of the signal within the cycle once the straight line
from its start to the next cycle's start is removed (a steady drift or a steady turn is not an
oscillation); the median over the cycles is reported.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.control.gait_metrics import GaitRecording, foot_contacts, rounded, touchdown_frames
from eigengait.sim.root import root_layout

STILL_M = 0.01  # m: below this overall travel the lateral direction is world y


def _lateral_axis(com: np.ndarray) -> np.ndarray:
    """Unit horizontal vector square to the COM's overall travel (world y for a creature that stays
    put)."""
    travel = com[-1, :2] - com[0, :2]
    length = float(np.linalg.norm(travel))
    if length < STILL_M:
        return np.array([0.0, 1.0])
    return np.array([-travel[1], travel[0]]) / length


def cycle_amplitude(signal: np.ndarray, frames_per_cycle: float) -> float | None:
    """Median over full cycles of half the range of `signal` (F,) within a cycle, less the straight
    line from the cycle's first frame to the next cycle's first (a steady drift); None when the
    recording holds no full cycle of at least 3 frames followed by one more frame."""
    halves = []
    for k in range(int(len(signal) // frames_per_cycle) if frames_per_cycle > 0 else 0):
        a, b = int(round(k * frames_per_cycle)), int(round((k + 1) * frames_per_cycle))
        if b - a < 3 or b >= len(signal):
            continue
        residual = signal[a:b] - np.linspace(signal[a], signal[b], b - a + 1)[:-1]
        halves.append(0.5 * (residual.max() - residual.min()))
    return float(np.median(halves)) if halves else None


def _stance_width(
    rec: GaitRecording, lateral: np.ndarray, touchdowns: dict[str, np.ndarray]
) -> float | None:
    """Mean lateral distance (m) between each touchdown point and the previous touchdown point of
    another foot."""
    landed = sorted((int(i), f) for f, frames in touchdowns.items() for i in frames)
    widths, last = [], {}
    for frame, foot in landed:
        point = rec.foot_points[foot][frame, :, :2].mean(axis=0)
        others = [(i, p) for f, (i, p) in last.items() if f != foot]
        if others:
            widths.append(abs(float((point - max(others, key=lambda o: o[0])[1]) @ lateral)))
        last[foot] = (frame, point)
    return float(np.mean(widths)) if widths else None


def gait_signatures(model: mujoco.MjModel, rec: GaitRecording) -> dict:
    """JSON-ready signature figures (rounded to 4 decimals, None where undefined):

    `lateral_com_amplitude_m` (lateral sway of the COM), `yaw_amplitude_deg` (twist of the root
    about the vertical), `touchdowns_per_cycle` per foot (2 for a skip: two hops on each foot),
    `mean_root_height_m` (crouch), `stance_width_m` (`_stance_width`), `min_foot_height_m` per foot
    (the lowest its lowest contact sphere's bottom comes to the floor after the first cycle, which
    launches from q₀ when the recording has more than two: about 0 for a foot that lands, the
    clearance of a foot held up).
    """
    frames_per_cycle = rec.period * rec.fps
    lateral = _lateral_axis(rec.com)
    layout = root_layout(model, int(model.jnt_bodyid[0])) if model.njnt else None
    yaw = np.unwrap(layout.heading(rec.qpos)) if layout is not None else np.zeros(len(rec.qpos))
    contacts = foot_contacts(rec)
    touchdowns = {f: touchdown_frames(c) for f, c in contacts.items()}
    cycles = len(rec.qpos) / frames_per_cycle if frames_per_cycle > 0 else 0.0
    height = (
        layout.position(rec.qpos)[:, 2] if layout is not None else np.full(len(rec.qpos), np.nan)
    )
    yaw_amplitude = cycle_amplitude(yaw, frames_per_cycle)
    steady = slice(int(frames_per_cycle) if len(rec.qpos) > 2 * frames_per_cycle else 0, None)
    return {
        "lateral_com_amplitude_m": rounded(
            cycle_amplitude(rec.com[:, :2] @ lateral, frames_per_cycle)
        ),
        "yaw_amplitude_deg": rounded(
            np.degrees(yaw_amplitude) if yaw_amplitude is not None else None
        ),
        "touchdowns_per_cycle": {
            f: rounded(len(t) / cycles) if cycles else None for f, t in touchdowns.items()
        },
        "mean_root_height_m": rounded(height.mean()),
        "stance_width_m": rounded(_stance_width(rec, lateral, touchdowns)),
        "min_foot_height_m": {
            f: rounded(points[steady, :, 2].min() - rec.foot_radius[f])
            for f, points in rec.foot_points.items()
        },
    }
