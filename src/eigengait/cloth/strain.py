"""Strain limiting (Provot 1995): no spring may end a step longer than ``(1 + bound)`` times its
rest length.

After the dynamics step, every spring stretched beyond the bound is shortened back to it by moving
its ends towards each other, in one Gauss–Seidel sweep over the springs (Provot's scheme; what a
sweep leaves is corrected the next step). Velocities receive the same correction divided by the
step, so the projected motion is the one the points carry on with. Compression is not limited.
Positions in m, velocities in m/s, the
bound is a strain (0.1 = 10 %).

Order and weights (:func:`projection_order`): springs are swept outwards from the fixed points
(by hop distance over the spring graph), and of a spring's two ends only the one farther from the
fixed points moves — both, in proportion to their inverse masses, when they are equally far (or the
surface has no fixed point). A hanging sheet then meets its bound in the one sweep, where an
equal-share projection needs hundreds to pass a correction down a long chain.
"""

from __future__ import annotations

import numba as nb
import numpy as np
import scipy.sparse as sp
from scipy.sparse import csgraph

#: default strain bound (10 %), the user-set limit of ``--strain-limit``
DEFAULT_BOUND = 0.10


@nb.njit(cache=True)
def limit_strain(x, v, springs, rest, weights, bound, h):
    """One sweep shortening every spring longer than ``(1 + bound)·rest`` back to it, in place on
    ``x`` (N, 3) and ``v``; returns the largest excess strain it found.

    ``weights`` (S, 2) are the shares (inverse masses, 1/kg, or 0) by which each spring's two ends
    move.
    """
    worst = 0.0
    for s in range(springs.shape[0]):
        i, j = springs[s, 0], springs[s, 1]
        d0, d1, d2 = x[j, 0] - x[i, 0], x[j, 1] - x[i, 1], x[j, 2] - x[i, 2]
        squared = d0 * d0 + d1 * d1 + d2 * d2
        limit = (1.0 + bound) * rest[s]
        if squared <= limit * limit:
            continue
        wi, wj = weights[s, 0], weights[s, 1]
        if wi + wj == 0.0:
            continue
        length = np.sqrt(squared)
        excess = length - limit
        worst = max(worst, excess / rest[s])
        scale = excess / ((wi + wj) * length)
        si, sj = wi * scale, wj * scale
        x[i, 0] += si * d0
        x[i, 1] += si * d1
        x[i, 2] += si * d2
        x[j, 0] -= sj * d0
        x[j, 1] -= sj * d1
        x[j, 2] -= sj * d2
        v[i, 0] += si * d0 / h
        v[i, 1] += si * d1 / h
        v[i, 2] += si * d2 / h
        v[j, 0] -= sj * d0 / h
        v[j, 1] -= sj * d1 / h
        v[j, 2] -= sj * d2 / h
    return worst


def projection_order(
    springs: np.ndarray, mass: np.ndarray, fixed: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(spring order, (S, 2) end weights) for :func:`limit_strain`, from the hop distance to the
    fixed points."""
    n = len(mass)
    depth = np.full(n, np.inf)
    if fixed.any():
        graph = sp.coo_matrix((np.ones(len(springs)), (springs[:, 0], springs[:, 1])), shape=(n, n))
        depth = csgraph.dijkstra(
            graph, directed=False, indices=np.flatnonzero(fixed), unweighted=True, min_only=True
        )
    di, dj = depth[springs[:, 0]], depth[springs[:, 1]]
    order = np.argsort(np.minimum(di, dj), kind="stable")
    inverse = np.where(fixed, 0.0, 1.0 / mass)
    weights = np.stack(
        [
            np.where(di >= dj, inverse[springs[:, 0]], 0.0),
            np.where(dj >= di, inverse[springs[:, 1]], 0.0),
        ],
        axis=1,
    )
    return order, weights[order]


def max_strain(x: np.ndarray, springs: np.ndarray, rest: np.ndarray) -> float:
    """Largest spring strain ``|d|/rest - 1`` at positions ``x`` (NumPy)."""
    return float((np.linalg.norm(x[springs[:, 1]] - x[springs[:, 0]], axis=1) / rest - 1.0).max())
