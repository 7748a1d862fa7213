"""Reference quantities from a kinematic replay of a pose sequence on the simulated character's own
model.

For every frame: qpos is set, ``mj_forward`` gives the COM, every body's world orientation and each
foot's sole centre and height, qvel comes from central differences (``mj_differentiatePos``)
smoothed by a moving average over SMOOTHING_S (mocap is noisy), and ``mj_subtreeVel`` gives the
COM velocity and the angular momentum about the COM; their rates (the COM acceleration and dL/dt,
the momentum feed-forward) are central differences of those, smoothed the same way. All vectors
are in world axes, SI units.
A foot is in reference contact when its lowest contact point is within ``CONTACT_HEIGHT`` of the
floor; the support point is the mean of the contacting feet's toe/heel midpoints, held through
flight phases.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from eigengait.control.balance.planting import transition_windows
from eigengait.sim.world import World

CONTACT_HEIGHT = 0.05  # m
# s: the moving average's width (5 frames of a 120 Hz CMU clip); a 30 Hz clip smoothed over 5 of its
# frames lost its accelerations (a Bandai Namco walk tracked 1.5 s behind its momentum, and fell)
SMOOTHING_S = 5 / 120


@dataclass
class Reference:
    """Per-frame reference of a motion at a fixed frame time (s); arrays have one row per frame."""

    frame_time: float
    qpos: np.ndarray  # (F, nq)
    qvel: np.ndarray  # (F, nv)
    com: np.ndarray  # (F, 3) m
    com_vel: np.ndarray  # (F, 3) m/s
    angular_momentum: np.ndarray  # (F, 3) kg·m²/s about the COM
    support: np.ndarray  # (F, 2) m, horizontal support point
    foot_contact: np.ndarray  # (F, n_feet) bool, feet in the order of world.foot_spheres
    mass: float
    com_acc: np.ndarray | None = None  # (F, 3) m/s²
    angular_momentum_rate: np.ndarray | None = None  # (F, 3) N·m
    body_quat: np.ndarray | None = None  # (F, nbody, 4) world orientation of every body
    # (F, n_feet, 2) m, horizontal centre of each foot's contact spheres
    foot_points: np.ndarray | None = None
    foot_height: np.ndarray | None = None  # (F, n_feet) m, height of each foot's lowest sole point
    # (F, n_feet) 1.0 where a foot is down near its touchdown or lift-off (`planting`), else 0.0
    foot_transition: np.ndarray | None = None
    # (F, n_feet, 2) m/s, horizontal velocity of each foot's sole centre (`foot_points`' rate)
    foot_velocity: np.ndarray | None = None

    def __post_init__(self):
        if self.com_acc is None:
            self.com_acc = _rate(self.com_vel, self.frame_time)
        if self.angular_momentum_rate is None:
            self.angular_momentum_rate = _rate(self.angular_momentum, self.frame_time)
        if self.foot_transition is None and self.foot_height is not None:
            windows = transition_windows(self.foot_height, self.frame_time)
            self.foot_transition = windows.astype(float)
        if self.foot_velocity is None and self.foot_points is not None:
            self.foot_velocity = _rate(self.foot_points, self.frame_time)

    @property
    def n_frames(self) -> int:
        return len(self.qpos)

    @property
    def duration(self) -> float:
        return (self.n_frames - 1) * self.frame_time

    def frame_at(self, t: float) -> tuple[int, int, float]:
        """Bracketing frames and blend weight of time t (s), clamped to the clip."""
        x = np.clip(t / self.frame_time, 0.0, self.n_frames - 1.0)
        i = min(int(x), self.n_frames - 2)
        return i, i + 1, x - i


def _smoothing_frames(frame_time: float) -> int:
    """Odd moving-average width (frames) closest to SMOOTHING_S."""
    return 2 * int(round((SMOOTHING_S / frame_time - 1) / 2)) + 1


def _smooth(values: np.ndarray, width: int) -> np.ndarray:
    if len(values) < width:
        return values
    pad = width // 2
    padded = np.concatenate([np.repeat(values[:1], pad, 0), values, np.repeat(values[-1:], pad, 0)])
    kernel = np.ones(width) / width
    return np.apply_along_axis(lambda c: np.convolve(c, kernel, mode="valid"), 0, padded)


def _rate(values: np.ndarray, frame_time: float) -> np.ndarray:
    """Smoothed central-difference time derivative of per-frame values."""
    if len(values) < 2:
        return np.zeros_like(values)
    return _smooth(np.gradient(values, frame_time, axis=0), _smoothing_frames(frame_time))


def foot_points(world: World, data: mujoco.MjData) -> dict[str, np.ndarray]:
    """World positions (k, 3) of each foot's contact spheres."""
    return {foot: data.geom_xpos[geoms] for foot, geoms in world.foot_spheres.items()}


def kinematic_replay(world: World, qpos: np.ndarray, frame_time: float) -> Reference:
    """Replay poses (F, nq) kinematically and record the reference quantities."""
    model = world.model
    data = mujoco.MjData(model)
    n = len(qpos)
    qvel = np.zeros((n, model.nv))
    for i in range(n):
        a, b = max(i - 1, 0), min(i + 1, n - 1)
        mujoco.mj_differentiatePos(model, qvel[i], (b - a) * frame_time, qpos[a], qpos[b])
    qvel = _smooth(qvel, _smoothing_frames(frame_time))
    root = world.root_body
    feet = list(world.foot_spheres)
    com, com_vel, ang = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3))
    body_quat = np.zeros((n, model.nbody, 4))
    centres, heights = np.zeros((n, len(feet), 2)), np.zeros((n, len(feet)))
    contact = np.zeros((n, len(feet)), bool)
    support = np.full((n, 2), np.nan)
    for i in range(n):
        data.qpos[:], data.qvel[:] = qpos[i], qvel[i]
        mujoco.mj_forward(model, data)
        mujoco.mj_subtreeVel(model, data)
        com[i], com_vel[i], ang[i] = (
            data.subtree_com[root],
            data.subtree_linvel[root],
            data.subtree_angmom[root],
        )
        body_quat[i] = data.xquat
        points = foot_points(world, data)
        low = [points[f][:, 2].min() - world.foot_radius(f) for f in feet]
        centres[i] = [points[f][:, :2].mean(axis=0) for f in feet]
        heights[i] = low
        contact[i] = np.array(low) < CONTACT_HEIGHT
        if contact[i].any():
            support[i] = np.mean(
                [points[f][:, :2].mean(axis=0) for f, c in zip(feet, contact[i]) if c], axis=0
            )
    support = _hold(support, com[:, :2])
    return Reference(
        frame_time=frame_time,
        qpos=qpos,
        qvel=qvel,
        com=com,
        com_vel=com_vel,
        angular_momentum=ang,
        support=support,
        foot_contact=contact,
        mass=float(model.body_subtreemass[root]),
        body_quat=body_quat,
        foot_points=centres,
        foot_height=heights,
    )


def _hold(support: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    """Fill flight frames with the last support point (the COM projection before the first
    contact)."""
    out = support.copy()
    last = fallback[0]
    for i in range(len(out)):
        if np.isnan(out[i, 0]):
            out[i] = last
        last = out[i]
    return out
