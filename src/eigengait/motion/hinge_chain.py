"""Angles of a body's chain of hinge joints that turn it closest to a wanted rotation.

A body on several hinges (a hip as hip_x, hip_z, hip_y; dm_control's humanoids) turns relative to
its parent frame by R(θ) = Π_i exp(θ_i [a_i]×), the hinges applied in the model's order, each axis
a_i in the body frame (MuJoCo's composition). Given wanted relative rotations (F, 3, 3), the angles
are found per frame by damped Gauss-Newton on the rotation error log(R(θ)ᵀ R_wanted), starting from
zero: exact for three independent axes away from gimbal lock, the least-squares turn for fewer.

Joint ranges, when given, bound the angles. Each angle is first moved by whole turns nearest its
range: Gauss-Newton from zero may end several turns away, where clamping would then throw the
body off (the CMU humanoid's humerus came out at −377°, clamped to −90°). If the angles of any
frame still leave the ranges, every frame is solved again by projected Gauss-Newton (each step
clipped into the ranges, a hinge held at a bound it is pushed past) from its clipped angles, from
the ranges' middle and from 2^k angle sets across them: the nearest turn the ranges allow, where
clamping each angle is not. Of each frame's solutions, the sequence that is both near and
continuous is kept (Viterbi, a change between frames charged JUMP_WEIGHT per rad²), so that
solutions of nearly equal error (near gimbal lock) are not crossed frame by frame.
"""

from __future__ import annotations

import numpy as np

from eigengait.geometry import mat_to_quat, quat_exp, quat_log, quat_to_mat

ITERATIONS = 30
DAMPING = 1e-6  # on the normal equations, for axes that line up (gimbal lock)
JUMP_WEIGHT = 1.0  # per rad² of change between frames, against the squared rotation error (rad²)


def hinge_angles(
    wanted: np.ndarray, axes: np.ndarray, ranges: np.ndarray | None = None
) -> np.ndarray:
    """Angles (F, k) in rad of the hinges with unit `axes` (k, 3; body frame, in the model's
    order) whose composed turn is nearest each wanted rotation (F, 3, 3), within `ranges` (k, 2;
    rad, ±inf for a free hinge) if given."""
    wanted = np.asarray(wanted, float)
    axes = np.asarray(axes, float)
    theta = _gauss_newton(wanted, axes, np.zeros((len(wanted), len(axes))))
    if ranges is None:
        return theta
    low, high = np.asarray(ranges, float).T
    theta = _into_ranges(theta, low, high)
    if np.all((theta >= low) & (theta <= high)):
        return theta
    starts = np.concatenate([np.clip(theta, low, high)[None], _spread(low, high, len(theta))])
    every = np.tile(wanted, (len(starts), 1, 1))
    solved = _gauss_newton(every, axes, starts.reshape(-1, len(axes)), (low, high))
    cost = np.sum(_error(solved, every, axes) ** 2, axis=1).reshape(len(starts), len(theta))
    return _smoothest_path(np.swapaxes(solved.reshape(*starts.shape), 0, 1), cost.T)


def _smoothest_path(candidates: np.ndarray, costs: np.ndarray) -> np.ndarray:
    """(F, k): one candidate angle set per frame (of `candidates`, F × S × k, with their `costs`,
    F × S) minimizing Σ cost + JUMP_WEIGHT Σ |θ_f − θ_f−1|² (Viterbi): a bound that several
    nearly equal solutions meet is not crossed from one to the other and back frame by frame."""
    total = costs[0].copy()
    back = np.zeros(costs.shape, int)
    for f in range(1, len(costs)):
        jump = np.sum((candidates[f][:, None] - candidates[f - 1][None]) ** 2, axis=-1)
        step = total[None] + JUMP_WEIGHT * jump  # (S now, S before)
        back[f] = step.argmin(axis=1)
        total = costs[f] + step.min(axis=1)
    path = np.zeros(len(costs), int)
    path[-1] = total.argmin()
    for f in range(len(costs) - 1, 0, -1):
        path[f - 1] = back[f, path[f]]
    return candidates[np.arange(len(costs)), path]


def _into_ranges(theta: np.ndarray, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """Each angle moved by whole turns (the same rotation) to the one nearest its range's middle
    (0 for a free hinge)."""
    middle = np.where(np.isfinite(low + high), (low + high) / 2, 0.0)
    return theta - 2 * np.pi * np.round((theta - middle) / (2 * np.pi))


def _spread(low: np.ndarray, high: np.ndarray, frames: int) -> np.ndarray:
    """(2^k + 1, frames, k) starting angles: the middle of the ranges and the 2^k corners of the
    box at a quarter and three quarters of each range (±π/2 for a free hinge)."""
    low, high = np.maximum(low, -np.pi), np.minimum(high, np.pi)
    levels = [lo + (hi - lo) * np.array([0.25, 0.75]) for lo, hi in zip(low, high)]
    grid = np.stack(np.meshgrid(*levels, indexing="ij"), axis=-1).reshape(-1, len(low))
    grid = np.concatenate([(low + high)[None] / 2, grid])
    return np.repeat(grid[:, None], frames, axis=1)


def _error(theta: np.ndarray, wanted: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """(F, 3) rotation error log(R(θ)ᵀ R_wanted) (rad, end frame)."""
    chain = np.broadcast_to(np.eye(3), wanted.shape).copy()
    for i in range(len(axes)):
        chain = chain @ quat_to_mat(quat_exp(theta[:, [i]] * axes[i]))
    return quat_log(mat_to_quat(np.swapaxes(chain, -1, -2) @ wanted))


def _gauss_newton(
    wanted: np.ndarray,
    axes: np.ndarray,
    theta: np.ndarray,
    bounds: tuple[np.ndarray, np.ndarray] | None = None,
) -> np.ndarray:
    """Angles (F, k) from `theta` minimizing |log(R(θ)ᵀ R_wanted)|², each step clipped into
    `bounds` (low, high) if given."""
    k = len(axes)
    for _ in range(ITERATIONS):
        turns = [quat_to_mat(quat_exp(theta[:, [i]] * axes[i])) for i in range(k)]
        after = np.broadcast_to(np.eye(3), wanted.shape).copy()  # Π_{j>i} R_j, built backward
        columns = [None] * k
        for i in reversed(range(k)):
            columns[i] = np.einsum("fji,j->fi", after, axes[i])  # a_i in the end frame
            after = turns[i] @ after
        chain = after  # Π_i R_i
        error = quat_log(mat_to_quat(np.swapaxes(chain, -1, -2) @ wanted))  # (F, 3), end frame
        jac = np.stack(columns, axis=-1)  # (F, 3, k)
        gradient = np.einsum("fik,fi->fk", jac, error)  # the angles' descent direction
        if bounds is not None:  # a hinge at a bound that the error pushes past it stays there
            held = ((theta <= bounds[0]) & (gradient < 0)) | ((theta >= bounds[1]) & (gradient > 0))
            jac = jac * ~held[:, None, :]
            gradient = gradient * ~held
        normal = np.swapaxes(jac, -1, -2) @ jac + DAMPING * np.eye(k)
        step = np.linalg.solve(normal, gradient[..., None])[..., 0]
        moved = theta + step if bounds is None else np.clip(theta + step, *bounds)
        change, theta = np.abs(moved - theta).max(), moved
        if change < 1e-10:
            break
    return theta
