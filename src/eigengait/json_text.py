"""JSON text that every parser accepts: NaN and infinities become null, NumPy numbers plain
numbers."""

from __future__ import annotations

import json
import math

import numpy as np


def finite(value):
    """`value` with every non-finite float replaced by None, recursively (dicts, lists, tuples,
    NumPy)."""
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    if isinstance(value, np.ndarray):
        return finite(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    return value


def dumps(value, **kwargs) -> str:
    """`json.dumps` of `finite(value)`; never writes NaN or Infinity."""
    return json.dumps(finite(value), allow_nan=False, **kwargs)
