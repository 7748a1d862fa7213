"""Compiled (numba) kernels for the mass–spring model: forces, explicit steps, the spring Jacobian's action.

Each kernel computes exactly what the NumPy reference in :mod:`eigengait.cloth.model`,
:mod:`eigengait.cloth.integrators` and :mod:`eigengait.cloth.stiffness` computes (the tests compare them), but in
one pass over the springs instead of many temporary arrays. Positions in m, velocities in m/s, forces in N,
spring constants in N/m, masses in kg, steps in s. Kernels are compiled on first use and cached on disk.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from eigengait.cloth.strain import limit_strain

#: explicit methods the fused step kernel knows
EULER, SYMPLECTIC = 0, 1
FUSED = {"euler": EULER, "symplectic": SYMPLECTIC}


@nb.njit(cache=True)
def internal_forces(x, springs, rest, k, bend, bend_coef, out):
    """Overwrite ``out`` (N, 3) with the spring + angular-spring forces at ``x``.

    ``bend_coef`` is ``k_c r / 2`` per angular spring (N).
    """
    out[:] = 0.0
    for s in range(springs.shape[0]):
        i, j = springs[s, 0], springs[s, 1]
        d0 = x[j, 0] - x[i, 0]
        d1 = x[j, 1] - x[i, 1]
        d2 = x[j, 2] - x[i, 2]
        length = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        t = k[s] * (length - rest[s]) / max(length, 1e-12)
        out[i, 0] += t * d0
        out[i, 1] += t * d1
        out[i, 2] += t * d2
        out[j, 0] -= t * d0
        out[j, 1] -= t * d1
        out[j, 2] -= t * d2
    for b in range(bend.shape[0]):
        a, c, e = bend[b, 0], bend[b, 1], bend[b, 2]
        a0, a1, a2 = x[a, 0] - x[c, 0], x[a, 1] - x[c, 1], x[a, 2] - x[c, 2]
        b0, b1, b2 = x[e, 0] - x[c, 0], x[e, 1] - x[c, 1], x[e, 2] - x[c, 2]
        wa = bend_coef[b] / max(np.sqrt(a0 * a0 + a1 * a1 + a2 * a2), 1e-12)
        wb = bend_coef[b] / max(np.sqrt(b0 * b0 + b1 * b1 + b2 * b2), 1e-12)
        out[c, 0] += wa * a0 + wb * b0
        out[c, 1] += wa * a1 + wb * b1
        out[c, 2] += wa * a2 + wb * b2


@nb.njit(cache=True)
def explicit_step(x, v, h, method, mass, springs, rest, k, bend, bend_coef, gravity, external, friction, fixed,
                  force):
    """One forward-Euler (``method`` 0) or symplectic-Euler (1) step of every free point, in place.

    Forces include gravity, the external force and FLEX3D's friction ``-min(μ|F|, m|v|/h) v̂``; fixed points are
    left untouched (their prescribed motion is imposed afterwards). ``force`` (N, 3) is scratch space.
    """
    internal_forces(x, springs, rest, k, bend, bend_coef, force)
    inv_h = 1.0 / h
    for i in range(x.shape[0]):
        if fixed[i]:
            continue
        m = mass[i]
        f0 = force[i, 0] + m * gravity[0] + external[0]
        f1 = force[i, 1] + m * gravity[1] + external[1]
        f2 = force[i, 2] + m * gravity[2] + external[2]
        v0, v1, v2 = v[i, 0], v[i, 1], v[i, 2]
        if friction != 0.0:
            speed = np.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
            if speed > 0.0:
                drag = min(friction * np.sqrt(f0 * f0 + f1 * f1 + f2 * f2), m * speed * inv_h) / speed
                f0 -= drag * v0
                f1 -= drag * v1
                f2 -= drag * v2
        if method == EULER:
            x[i, 0] += h * v0
            x[i, 1] += h * v1
            x[i, 2] += h * v2
        step = h / m
        v0 += step * f0
        v1 += step * f1
        v2 += step * f2
        v[i, 0], v[i, 1], v[i, 2] = v0, v1, v2
        if method == SYMPLECTIC:
            x[i, 0] += h * v0
            x[i, 1] += h * v1
            x[i, 2] += h * v2


@nb.njit(cache=True)
def explicit_steps(x, v, steps, h, method, mass, springs, rest, k, bend, bend_coef, gravity, external, friction,
                   fixed, force, strain_springs, strain_rest, strain_weights, strain_bound):
    """``steps`` calls of :func:`explicit_step`, each followed by a strain-limiting sweep when ``strain_bound`` ≥ 0,
    in one compiled loop (for scenes whose fixed points stand still and that have nothing else to resolve per step).
    """
    for _ in range(steps):
        explicit_step(x, v, h, method, mass, springs, rest, k, bend, bend_coef, gravity, external, friction, fixed,
                      force)
        if strain_bound >= 0.0:
            limit_strain(x, v, strain_springs, strain_rest, strain_weights, strain_bound, h)


@nb.njit(cache=True)
def spring_blocks(x, springs, rest, k, clamp, blocks):
    """Fill ``blocks`` (S, 3, 3) with each spring's ``k [d̂d̂ᵀ + α(I - d̂d̂ᵀ)]``, α = 1 - rest/|d| (N/m).

    ``clamp`` drops α < 0 (compressed springs) so that the assembled Jacobian stays negative semi-definite.
    """
    for s in range(springs.shape[0]):
        i, j = springs[s, 0], springs[s, 1]
        d0, d1, d2 = x[j, 0] - x[i, 0], x[j, 1] - x[i, 1], x[j, 2] - x[i, 2]
        length = max(np.sqrt(d0 * d0 + d1 * d1 + d2 * d2), 1e-12)
        alpha = 1.0 - rest[s] / length
        if clamp and alpha < 0.0:
            alpha = 0.0
        ks = k[s]
        for p in range(3):
            up = (d0, d1, d2)[p] / length
            for q in range(3):
                uu = up * (d0, d1, d2)[q] / length
                blocks[s, p, q] = ks * (uu + alpha * ((1.0 if p == q else 0.0) - uu))


@nb.njit(cache=True)
def jacobian_times(v, springs, blocks, bend, bend_quarter, out):
    """``out = K v`` for the spring Jacobian K (3N × 3N, N/m) given by its spring ``blocks``.

    Angular springs add ``-(k_c/4) s sᵀ ⊗ I₃`` on each triple (s = (1, -2, 1)); ``bend_quarter`` is ``k_c/4``.
    ``v`` and ``out`` are (N, 3).
    """
    out[:] = 0.0
    for s in range(springs.shape[0]):
        i, j = springs[s, 0], springs[s, 1]
        for p in range(3):
            acc = 0.0
            for q in range(3):
                acc += blocks[s, p, q] * (v[j, q] - v[i, q])
            out[i, p] += acc
            out[j, p] -= acc
    for b in range(bend.shape[0]):
        a, c, e = bend[b, 0], bend[b, 1], bend[b, 2]
        for q in range(3):
            w = bend_quarter[b] * (v[a, q] - 2.0 * v[c, q] + v[e, q])
            out[a, q] -= w
            out[c, q] += 2.0 * w
            out[e, q] -= w


@nb.njit(cache=True)
def jacobian_diagonal(springs, blocks, bend, bend_quarter, out):
    """Diagonal of K, (N, 3) N/m."""
    out[:] = 0.0
    for s in range(springs.shape[0]):
        i, j = springs[s, 0], springs[s, 1]
        for p in range(3):
            out[i, p] -= blocks[s, p, p]
            out[j, p] -= blocks[s, p, p]
    for b in range(bend.shape[0]):
        for q in range(3):
            out[bend[b, 0], q] -= bend_quarter[b]
            out[bend[b, 1], q] -= 4.0 * bend_quarter[b]
            out[bend[b, 2], q] -= bend_quarter[b]


@nb.njit(cache=True)
def _system_times(z, diag_mass, h2, springs, blocks, bend, bend_quarter, free, out):
    """``out = P (M' - h² K) P z + (I - P) z``: the backward-Euler matrix with fixed points as identity rows."""
    jacobian_times(z, springs, blocks, bend, bend_quarter, out)
    for i in range(z.shape[0]):
        for q in range(3):
            if free[i]:
                out[i, q] = diag_mass[i] * z[i, q] - h2 * out[i, q]
            else:
                out[i, q] = z[i, q]


@nb.njit(cache=True)
def solve_backward_euler(rhs, guess, diag_mass, h2, springs, blocks, bend, bend_quarter, free, rtol, max_iter,
                         scratch):
    """Solve ``(M' - h²K) Δv = rhs`` on the free points by Jacobi-preconditioned conjugate gradients.

    ``diag_mass`` (N,) is m + h·drag (kg); fixed rows are identity, so their ``rhs`` entries are returned as is.
    Starts from ``guess`` (N, 3), overwritten with the solution; returns the iteration count.
    ``scratch`` is (5, N, 3) work space.
    """
    r, z, p, ap, inv_diag = scratch[0], scratch[1], scratch[2], scratch[3], scratch[4]
    jacobian_diagonal(springs, blocks, bend, bend_quarter, inv_diag)
    for i in range(rhs.shape[0]):
        for q in range(3):
            inv_diag[i, q] = 1.0 / (diag_mass[i] - h2 * inv_diag[i, q]) if free[i] else 1.0
    _system_times(guess, diag_mass, h2, springs, blocks, bend, bend_quarter, free, ap)
    r[:] = rhs - ap
    z[:] = r * inv_diag
    p[:] = z
    rz = (r * z).sum()
    target = rtol * rtol * (rhs * rhs).sum()
    iterations = 0
    while (r * r).sum() > target and iterations < max_iter:
        _system_times(p, diag_mass, h2, springs, blocks, bend, bend_quarter, free, ap)
        alpha = rz / (p * ap).sum()
        guess += alpha * p
        r -= alpha * ap
        z[:] = r * inv_diag
        rz_next = (r * z).sum()
        p[:] = z + (rz_next / rz) * p
        rz = rz_next
        iterations += 1
    return iterations
