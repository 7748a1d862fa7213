"""The force Jacobian ``K = ∂F/∂x`` (3N × 3N, sparse, N/m) of a :class:`ClothModel`'s springs.

Spring i–j with unit direction d̂, length l and rest r contributes the block
``K_s = k [d̂d̂ᵀ + (1 - r/l)(I - d̂d̂ᵀ)]`` with ``∂F_i/∂x_j = K_s`` and ``∂F_i/∂x_i = -K_s``; the second
term is the geometric (tension) stiffness. For implicit steps it is clamped at zero for compressed
springs so that K stays negative semi-definite (Baraff & Witkin 1998); for vibration modes it is
kept exact.

Angular springs enter through the symmetric Hessian of the energy ``(k_c/8)|x_a - 2x_c + x_b|²``
whose force on the centre equals FLEX3D's angular spring at small angles: ``-(k_c/4) s sᵀ ⊗ I₃``
with ``s = (1, -2, 1)``. The sparsity pattern is computed once; each assembly only scatters new
values into it.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from eigengait.cloth.model import ClothModel

_BEND_S = np.array([1.0, -2.0, 1.0])


class StiffnessAssembler:
    """Assembles K for one model; call :meth:`matrix` with positions (N, 3)."""

    def __init__(self, model: ClothModel):
        self.model = model
        n3 = 3 * model.size
        i, j = model.springs[:, 0], model.springs[:, 1]
        # Spring blocks (i,i), (i,j), (j,i), (j,j), each 3x3, in that order.
        node_r = np.stack([i, i, j, j], axis=1)
        node_c = np.stack([i, j, i, j], axis=1)
        a, b = np.meshgrid(np.arange(3), np.arange(3), indexing="ij")
        rows = (3 * node_r[:, :, None, None] + a).ravel()
        cols = (3 * node_c[:, :, None, None] + b).ravel()
        self._spring_sign = np.array([-1.0, 1.0, 1.0, -1.0])
        # Angular-spring Hessian: node pairs (p, q) of each triple, diagonal in the axis.
        tri = model.bend
        pr = np.repeat(tri, 3, axis=1)
        pc = np.tile(tri, (1, 3))
        bend_rows = (3 * pr[:, :, None] + np.arange(3)).ravel()
        bend_cols = (3 * pc[:, :, None] + np.arange(3)).ravel()
        self._bend_values = (
            -(model.bend_k / 4.0)[:, None, None]
            * np.outer(_BEND_S, _BEND_S).ravel()[None, :, None]
            * np.ones(3)
        ).ravel()
        all_rows = np.r_[rows, bend_rows]
        all_cols = np.r_[cols, bend_cols]
        keys = all_rows.astype(np.int64) * n3 + all_cols
        unique, self._slot = np.unique(keys, return_inverse=True)
        self._indices = (unique % n3).astype(np.int32)
        self._indptr = np.searchsorted(unique // n3, np.arange(n3 + 1)).astype(np.int32)
        self._shape = (n3, n3)
        self._n_spring_entries = rows.size

    def matrix(self, x: np.ndarray, *, clamp: bool) -> sp.csr_matrix:
        """K at positions ``x``; ``clamp`` drops the tension term of compressed springs."""
        m = self.model
        d = x[m.springs[:, 1]] - x[m.springs[:, 0]]
        length = np.maximum(np.linalg.norm(d, axis=1), 1e-12)
        u = d / length[:, None]
        alpha = 1.0 - m.spring_rest / length
        if clamp:
            alpha = np.maximum(alpha, 0.0)
        outer = u[:, :, None] * u[:, None, :]
        block = m.spring_k[:, None, None] * (outer + alpha[:, None, None] * (np.eye(3) - outer))
        spring_values = (self._spring_sign[None, :, None, None] * block[:, None, :, :]).ravel()
        values = np.bincount(
            self._slot,
            weights=np.r_[spring_values, self._bend_values],
            minlength=len(self._indices),
        )
        return sp.csr_matrix((values, self._indices, self._indptr), shape=self._shape)
