"""6D spatial algebra, angular part first: twists (ω; v) and wrenches (τ; f)."""

from __future__ import annotations

import numpy as np

from eigengait.geometry import skew


def adjoint(R: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Ad of T = (R, t): maps a twist in the moving frame to the reference frame, [[R, 0],
    [[t]R, R]]."""
    Ad = np.zeros((6, 6))
    Ad[:3, :3] = R
    Ad[3:, 3:] = R
    Ad[3:, :3] = skew(t) @ R
    return Ad


def relative_adjoint(
    R_a: np.ndarray, p_a: np.ndarray, R_b: np.ndarray, p_b: np.ndarray
) -> np.ndarray:
    """Ad(a←b): twist in frame b -> same twist in frame a, frames given by world rotation and
    origin."""
    R = R_a.T @ R_b
    t = R_a.T @ (p_b - p_a)
    return adjoint(R, t)


def spatial_inertia(mass: float, inertia: np.ndarray) -> np.ndarray:
    """blockdiag(I_c, m I₃) at the COM, in the body's inertial frame."""
    M = np.zeros((6, 6))
    M[:3, :3] = np.diag(inertia) if np.ndim(inertia) == 1 else inertia
    M[3:, 3:] = mass * np.eye(3)
    return M
