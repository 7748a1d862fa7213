"""Compiled (numba) kernels for the mass–spring model: forces, explicit steps, the spring Jacobian's
action.

Each kernel computes exactly what the NumPy reference in :mod:`eigengait.cloth.model`,
:mod:`eigengait.cloth.integrators` and :mod:`eigengait.cloth.stiffness` computes (the tests compare
them), but in one pass over the springs instead of many temporary arrays. Positions in m, velocities
in m/s, forces in N, spring constants in N/m, masses in kg, steps in s. Kernels are compiled on
first use and cached on disk.
"""

from __future__ import annotations

import numba as nb
import numpy as np

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
def explicit_step(
    x,
    v,
    h,
    method,
    mass,
    springs,
    rest,
    k,
    bend,
    bend_coef,
    gravity,
    external,
    friction,
    fixed,
    force,
):
    """One forward-Euler (``method`` 0) or symplectic-Euler (1) step of every free point, in place.

    Forces include gravity, the external force and FLEX3D's friction ``-min(μ|F|, m|v|/h) v̂``; fixed
    points are left untouched (their prescribed motion is imposed afterwards). ``force`` (N, 3) is
    scratch space.
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
                drag = (
                    min(friction * np.sqrt(f0 * f0 + f1 * f1 + f2 * f2), m * speed * inv_h) / speed
                )
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
def _run_forces(X, runs, rest, k, T, F):
    """Add the forces of the springs of ``runs`` to ``F`` (3, N) N at positions ``X`` (3, N) m;
    ``T`` (3, L) is scratch space for the longest run. Each run is taken as slices so that its loops
    run in SIMD lanes."""
    t0, t1, t2 = T[0], T[1], T[2]
    for run in range(runs.shape[0]):
        s0, a0, b0, count = runs[run, 0], runs[run, 1], runs[run, 2], runs[run, 3]
        xa0, xa1, xa2 = X[0, a0 : a0 + count], X[1, a0 : a0 + count], X[2, a0 : a0 + count]
        xb0, xb1, xb2 = X[0, b0 : b0 + count], X[1, b0 : b0 + count], X[2, b0 : b0 + count]
        rs, ks = rest[s0 : s0 + count], k[s0 : s0 + count]
        for r in range(count):
            d0 = xb0[r] - xa0[r]
            d1 = xb1[r] - xa1[r]
            d2 = xb2[r] - xa2[r]
            length = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            t = ks[r] * (length - rs[r]) / max(length, 1e-12)
            t0[r], t1[r], t2[r] = t * d0, t * d1, t * d2
        for c in range(3):
            fa, fb, tc = F[c, a0 : a0 + count], F[c, b0 : b0 + count], T[c]
            for r in range(count):
                fa[r] += tc[r]
            for r in range(count):
                fb[r] -= tc[r]


@nb.njit(cache=True)
def _bend_forces(X, bend, bend_coef, F):
    """Add the angular springs' forces (``bend_coef`` = k_c r / 2, N) on their middle points to
    ``F`` (3, N)."""
    for b in range(bend.shape[0]):
        a, c, e = bend[b, 0], bend[b, 1], bend[b, 2]
        a0, a1, a2 = X[0, a] - X[0, c], X[1, a] - X[1, c], X[2, a] - X[2, c]
        b0, b1, b2 = X[0, e] - X[0, c], X[1, e] - X[1, c], X[2, e] - X[2, c]
        wa = bend_coef[b] / max(np.sqrt(a0 * a0 + a1 * a1 + a2 * a2), 1e-12)
        wb = bend_coef[b] / max(np.sqrt(b0 * b0 + b1 * b1 + b2 * b2), 1e-12)
        F[0, c] += wa * a0 + wb * b0
        F[1, c] += wa * a1 + wb * b1
        F[2, c] += wa * a2 + wb * b2


@nb.njit(cache=True)
def _integrate(X, V, F, h, method, mass, gravity, external, friction, free):
    """The Euler update of :func:`explicit_step` on (3, N) arrays, branch-free so that it runs in
    SIMD lanes; fixed points keep their state. Zeroes ``F`` for the next step."""
    inv_h = 1.0 / h
    lagged = method == EULER
    g0, g1, g2 = gravity[0], gravity[1], gravity[2]
    e0, e1, e2 = external[0], external[1], external[2]
    x0, x1, x2, v0, v1, v2, f0, f1, f2 = X[0], X[1], X[2], V[0], V[1], V[2], F[0], F[1], F[2]
    for i in range(X.shape[1]):
        m = mass[i]
        a0 = f0[i] + m * g0 + e0
        a1 = f1[i] + m * g1 + e1
        a2 = f2[i] + m * g2 + e2
        u0, u1, u2 = v0[i], v1[i], v2[i]
        speed = np.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
        push, stop = friction * np.sqrt(a0 * a0 + a1 * a1 + a2 * a2), m * speed * inv_h
        drag = (stop if stop < push else push) / speed if speed > 0.0 else 0.0
        step = h / m
        n0 = u0 + step * (a0 - drag * u0)
        n1 = u1 + step * (a1 - drag * u1)
        n2 = u2 + step * (a2 - drag * u2)
        keep = free[i]
        x0[i] += (h * (u0 if lagged else n0)) if keep else 0.0
        x1[i] += (h * (u1 if lagged else n1)) if keep else 0.0
        x2[i] += (h * (u2 if lagged else n2)) if keep else 0.0
        v0[i] = n0 if keep else u0
        v1[i] = n1 if keep else u1
        v2[i] = n2 if keep else u2
        f0[i] = 0.0
        f1[i] = 0.0
        f2[i] = 0.0


@nb.njit(cache=True)
def _overstretched(X, runs, rest, bound, flags):
    """Set ``flags[s]`` to whether spring ``s`` is longer than ``(1 + bound)·rest`` at ``X`` (3, N)
    m."""
    for run in range(runs.shape[0]):
        s0, a0, b0, count = runs[run, 0], runs[run, 1], runs[run, 2], runs[run, 3]
        xa0, xa1, xa2 = X[0, a0 : a0 + count], X[1, a0 : a0 + count], X[2, a0 : a0 + count]
        xb0, xb1, xb2 = X[0, b0 : b0 + count], X[1, b0 : b0 + count], X[2, b0 : b0 + count]
        rs, out = rest[s0 : s0 + count], flags[s0 : s0 + count]
        for r in range(count):
            d0 = xb0[r] - xa0[r]
            d1 = xb1[r] - xa1[r]
            d2 = xb2[r] - xa2[r]
            limit = (1.0 + bound) * rs[r]
            out[r] = d0 * d0 + d1 * d1 + d2 * d2 > limit * limit


@nb.njit(cache=True)
def _sweep(X, V, springs, rest, weights, bound, h, flags, touch_start, touching):
    """The strain-limiting sweep of :func:`~eigengait.cloth.strain.limit_strain` on (3, N) arrays,
    visiting only the flagged springs: a spring is flagged when it was overstretched before the
    sweep or when an earlier spring of the sweep moved one of its ends
    (``touching[touch_start[p]:touch_start[p + 1]]``: the springs at point p)."""
    for s in range(springs.shape[0]):
        if not flags[s]:
            continue
        i, j = springs[s, 0], springs[s, 1]
        d0, d1, d2 = X[0, j] - X[0, i], X[1, j] - X[1, i], X[2, j] - X[2, i]
        squared = d0 * d0 + d1 * d1 + d2 * d2
        limit = (1.0 + bound) * rest[s]
        wi, wj = weights[s, 0], weights[s, 1]
        if squared <= limit * limit or wi + wj == 0.0:
            continue
        length = np.sqrt(squared)
        scale = (length - limit) / ((wi + wj) * length)
        for end, sign, w in ((i, 1.0, wi), (j, -1.0, wj)):
            if w == 0.0:
                continue
            shift = sign * w * scale
            X[0, end] += shift * d0
            X[1, end] += shift * d1
            X[2, end] += shift * d2
            V[0, end] += shift * d0 / h
            V[1, end] += shift * d1 / h
            V[2, end] += shift * d2 / h
            for q in range(touch_start[end], touch_start[end + 1]):
                if touching[q] > s:
                    flags[touching[q]] = True


@nb.njit(cache=True)
def explicit_steps(
    x,
    v,
    steps,
    h,
    method,
    mass,
    springs,
    rest,
    k,
    weights,
    bend,
    bend_coef,
    gravity,
    external,
    friction,
    free,
    bound,
    runs,
    touch_start,
    touching,
):
    """``steps`` forward- (``method`` 0) or symplectic-Euler (1) steps, each followed by a
    strain-limiting sweep when ``bound`` ≥ 0, in one compiled loop, in place on ``x`` (N, 3) m and
    ``v`` m/s.

    The springs (``springs``, ``rest``, ``k``, ``weights``) come in the sweep order of
    :func:`~eigengait.cloth.strain.projection_order`, described by :class:`SpringRuns`. Gives the
    result of :func:`explicit_step` followed by :func:`~eigengait.cloth.strain.limit_strain`, up to
    the order in which the spring forces are summed.
    """
    X, V = x.T.copy(), v.T.copy()
    F = np.zeros_like(X)
    T = np.empty((3, max(runs[:, 3].max(), 1) if runs.shape[0] else 1))
    flags = np.zeros(springs.shape[0], np.bool_)
    for _ in range(steps):
        _run_forces(X, runs, rest, k, T, F)
        _bend_forces(X, bend, bend_coef, F)
        _integrate(X, V, F, h, method, mass, gravity, external, friction, free)
        if bound >= 0.0:
            _overstretched(X, runs, rest, bound, flags)
            _sweep(X, V, springs, rest, weights, bound, h, flags, touch_start, touching)
    x[:] = X.T
    v[:] = V.T


class SpringRuns:
    """Springs in sweep order cut into runs of consecutive point pairs (a+r, b+r), r < count, so
    that the compiled loops over them run in SIMD lanes; plus, for each point, the sweep positions
    of the springs at it."""

    def __init__(self, springs: np.ndarray, size: int):
        first = (
            np.r_[True, (np.diff(springs[:, 0]) != 1) | (np.diff(springs[:, 1]) != 1)]
            if len(springs)
            else np.zeros(0, bool)
        )
        starts = np.flatnonzero(first)
        counts = np.diff(np.r_[starts, len(springs)])
        self.runs = np.stack(
            [starts, springs[starts, 0], springs[starts, 1], counts], axis=1
        ).astype(np.int64)
        ends = springs.ravel()
        order = np.argsort(ends, kind="stable")
        self.touching = (order // 2).astype(np.int64)
        self.touch_start = np.searchsorted(ends[order], np.arange(size + 1)).astype(np.int64)


@nb.njit(cache=True)
def spring_blocks(x, springs, rest, k, clamp, blocks):
    """Fill ``blocks`` (S, 3, 3) with each spring's ``k [d̂d̂ᵀ + α(I - d̂d̂ᵀ)]``, α = 1 - rest/|d|
    (N/m).

    ``clamp`` drops α < 0 (compressed springs) so that the assembled Jacobian stays negative
    semi-definite.
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

    Angular springs add ``-(k_c/4) s sᵀ ⊗ I₃`` on each triple (s = (1, -2, 1)); ``bend_quarter`` is
    ``k_c/4``. ``v`` and ``out`` are (N, 3).
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
    """``out = P (M' - h² K) P z + (I - P) z``: the backward-Euler matrix with fixed points as
    identity rows."""
    jacobian_times(z, springs, blocks, bend, bend_quarter, out)
    for i in range(z.shape[0]):
        for q in range(3):
            if free[i]:
                out[i, q] = diag_mass[i] * z[i, q] - h2 * out[i, q]
            else:
                out[i, q] = z[i, q]


@nb.njit(cache=True)
def solve_backward_euler(
    rhs, guess, diag_mass, h2, springs, blocks, bend, bend_quarter, free, rtol, max_iter, scratch
):
    """Solve ``(M' - h²K) Δv = rhs`` on the free points by Jacobi-preconditioned conjugate
    gradients.

    ``diag_mass`` (N,) is m + h·drag (kg); fixed rows are identity, so their ``rhs`` entries are
    returned as is. Starts from ``guess`` (N, 3), overwritten with the solution; returns the
    iteration count. ``scratch`` is (5, N, 3) work space.
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
