"""Stable-step estimates for the explicit integrators, and the warning issued before a run that
would blow up.

The highest natural frequency is bounded by Gershgorin's theorem on M⁻¹K:
``ω_max² ≤ max_i (2 Σ k_springs(i) + 2 Σ k_c(i)) / m_i`` (rad²/s²). Then

* symplectic Euler is stable for ``h ω_max < 2``, RK4 for ``h ω_max < 2.785``;
* forward Euler amplifies a mode of frequency ω with damping ratio ζ by ``√(1 - 2hζω + h²ω²)`` per
  step. FLEX3D's friction behaves like ``ζ ≈ μ/π`` (it removes ``4μ`` of an oscillator's energy per
  cycle), so the amplitude grows over a run of T seconds by ``(1 - 2hζω + h²ω²)^(T/2h)``. The
  estimate is the largest h for which that growth stays below :data:`GROWTH_LIMIT` at ω_max.
* backward Euler has no limit.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from eigengait.cloth.model import ClothModel

GROWTH_LIMIT = 10.0
_LIMITS = {"symplectic": 2.0, "rk4": 2.785}


class StepSizeWarning(UserWarning):
    """The time step is beyond the estimated stability limit of the chosen integrator."""


def max_frequency(model: ClothModel) -> float:
    """Upper bound on the highest natural frequency ω_max (rad/s) of the free points."""
    row = np.zeros(model.size)
    np.add.at(row, model.springs.ravel(), np.repeat(2.0 * model.spring_k, 2))
    np.add.at(
        row,
        model.bend.ravel(),
        np.repeat(model.bend_k, 3) * np.tile([1.0, 2.0, 1.0], len(model.bend_k)),
    )
    free = model.free if model.free.any() else np.ones(model.size, bool)
    return float(np.sqrt((row[free] / model.mass[free]).max()))


def euler_growth(h: float, omega: float, damping_ratio: float, duration: float) -> float:
    """Amplitude growth factor of forward Euler over ``duration`` s for one damped mode."""
    per_step = 1.0 - 2.0 * h * damping_ratio * omega + (h * omega) ** 2
    return math.exp(min(0.5 * duration / h * math.log(max(per_step, 1e-300)), 700.0))


def stable_step(model: ClothModel, integrator: str, duration: float) -> float:
    """Largest step (s) the estimate considers stable for ``integrator`` over a run of ``duration``
    s."""
    if integrator == "implicit":
        return math.inf
    omega = max_frequency(model)
    if integrator in _LIMITS:
        return _LIMITS[integrator] / omega
    zeta = model.friction / math.pi
    lo, hi = 0.0, 2.0 / omega + 2.0 * zeta / omega
    if euler_growth(hi, omega, zeta, duration) <= GROWTH_LIMIT:
        return hi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (
            (mid, hi)
            if mid > 0 and euler_growth(mid, omega, zeta, duration) <= GROWTH_LIMIT
            else (lo, mid)
        )
    return lo


def check_step(model: ClothModel, integrator: str, h: float, duration: float) -> float:
    """Warn with :class:`StepSizeWarning` when ``h`` exceeds :func:`stable_step`; returns the
    estimate."""
    limit = stable_step(model, integrator, duration)
    if h > limit:
        warnings.warn(
            f"DELTA_t = {h:g} s is above the estimated stable step {limit:.3g} s for the "
            f"'{integrator}' integrator (ω_max ≈ {max_frequency(model):.3g} rad/s); the run will "
            "likely blow up. Use a smaller DELTA_t or integrator='implicit'.",
            StepSizeWarning,
            stacklevel=2,
        )
    return limit
