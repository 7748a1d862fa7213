"""The generalized eigenproblem K φ = λ M φ, optionally restricted to the null space of
constraints, and the one basis of each eigenspace that rounding cannot change."""

from __future__ import annotations

import numpy as np
from scipy.linalg import eigh, null_space

# an eigenvalue below this fraction of the largest is a rigid-body (zero) mode
RIGID_TOLERANCE = 1e-8
# eigenvalues closer than this share of the larger are one eigenspace (a character's twin limbs:
# the dog's front and rear legs swing alike); LAPACK's vectors in it are any rotation that the
# last bits of the matrices decide, so `canonical_eigenspaces` fixes one
DEGENERATE_GAP = 1e-8


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


def degenerate_blocks(eigenvalues: np.ndarray) -> list[slice]:
    """Runs of two or more ascending eigenvalues each within DEGENERATE_GAP of the next."""
    lam = np.asarray(eigenvalues, float)
    close = np.diff(lam) <= DEGENERATE_GAP * np.maximum(abs(lam[1:]), 1e-300)
    blocks, start = [], None
    for i, joined in enumerate(close):
        if joined and start is None:
            start = i
        if not joined and start is not None:
            blocks.append(slice(start, i + 1))
            start = None
    if start is not None:
        blocks.append(slice(start, len(lam)))
    return blocks


def canonical_eigenspaces(eigenvalues: np.ndarray, shapes: np.ndarray) -> np.ndarray:
    """The shapes with each degenerate block rotated to the basis that diagonalizes Xᵀ D X, D =
    diag(1, 2, …, n) over the coordinates, in ascending order of it.

    The rotation is orthogonal, so φᵀ M φ = 1 and the eigenvalues hold; the basis depends on the
    eigenspace only, not on which vectors of it the solver returned (signs are fixed later)."""
    out = np.array(shapes, float)
    weights = np.arange(1, out.shape[0] + 1, dtype=float)
    for block in degenerate_blocks(eigenvalues):
        X = out[:, block]
        gram = X.T @ (weights[:, None] * X)
        _, rotation = np.linalg.eigh((gram + gram.T) / 2)
        out[:, block] = X @ rotation
    return out
