"""The generalized eigenproblem K φ = λ M φ, optionally restricted to the null space of
constraints."""

from __future__ import annotations

import numpy as np
from scipy.linalg import eigh, null_space

# an eigenvalue below this fraction of the largest is a rigid-body (zero) mode
RIGID_TOLERANCE = 1e-8


def constrained_modes(K: np.ndarray, M: np.ndarray, G: np.ndarray | None = None):
    """Solve K φ = λ M φ subject to G φ = 0.

    Returns (eigenvalues λ ascending, shapes φ as columns with φᵀ M φ = 1, number of rigid modes
    dropped). Only the non-rigid modes are returned.
    """
    N = np.eye(K.shape[0]) if G is None or G.size == 0 else null_space(G)
    Kr = N.T @ K @ N
    Mr = N.T @ M @ N
    lam, x = eigh((Kr + Kr.T) / 2, (Mr + Mr.T) / 2)
    rigid = lam < RIGID_TOLERANCE * max(abs(lam).max(), 1e-300)
    shapes = N @ x[:, ~rigid]
    return lam[~rigid], shapes, int(rigid.sum())


def frequencies_hz(eigenvalues: np.ndarray) -> np.ndarray:
    """f = √λ / 2π (Hz)."""
    return np.sqrt(np.clip(eigenvalues, 0, None)) / (2 * np.pi)
