"""Mode numbers and activations ψ: the one place that turns 1-based mode numbers into 0-based
columns and back.

Files, sketches and the optimizer's parameter names number modes from 1 (mode 1 is the lowest); a
basis's columns and a dense ψ array (N·m per mode, one per (foot, phase)) count from 0. A sparse ψ
maps mode number -> value and leaves out the zeros.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from eigengait.errors import UserInputError


def mode_index(m: int) -> int:
    """Column (0-based) of 1-based mode number `m`."""
    return m - 1


def mode_indices(modes: Iterable[int]) -> list[int]:
    """Columns (0-based) of 1-based mode numbers, in their order: a fancy index into a basis's
    columns."""
    return [mode_index(m) for m in modes]


def mode_number(i: int) -> int:
    """1-based mode number of column `i`."""
    return int(i + 1)


def sparse_to_dense(
    sparse: Mapping[int, float], size: int, file: str | Path | None = None, field: str | None = None
) -> np.ndarray:
    """ψ over all `size` modes (zeros elsewhere) from mode number -> ψ; a mode number outside
    1..size is an error naming `file` and `field`."""
    psi = np.zeros(size)
    for m, v in sparse.items():
        if not 1 <= m <= size:
            raise UserInputError(
                f"mode {m} does not exist ({size} modes)",
                file=file,
                field=field,
                fix=f"use mode numbers from 1 to {size} (`eigengait modes CHARACTER` lists them)",
            )
        psi[mode_index(m)] = v
    return psi


def dense_to_sparse(dense: Iterable[float]) -> dict[int, float]:
    """Mode number -> ψ of the non-zero entries of a dense ψ, in mode order."""
    return {mode_number(i): float(v) for i, v in enumerate(dense) if v != 0}


def psi_key(foot: str, phase: str, m: int) -> str:
    """Name of the optimizer's parameter for ψ of mode number `m` of (foot, phase)."""
    return f"psi/{foot}/{phase}/{m}"
