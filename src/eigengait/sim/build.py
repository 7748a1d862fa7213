"""Which build simulated a recording: a falling gait amplifies rounding, so its figures replay
exactly only on the same MuJoCo and NumPy versions and the same kind of CPU: the vector
instructions MuJoCo and NumPy may use, and the CPU's make and model, by which NumPy's OpenBLAS
picks its kernels (the shipped gaits recorded on one AVX-512 machine replay differently on an AMD
EPYC with the same instructions: the dog trot falls in its tenth cycle there)."""

from __future__ import annotations

import platform
from pathlib import Path

import mujoco
import numpy as np

VECTOR_FLAGS = ("sse4_2", "avx", "avx2", "fma", "avx512f", "avx512dq", "avx512vl", "asimd", "sve")


def _cpu_fields(cpuinfo: Path = Path("/proc/cpuinfo")) -> dict[str, str]:
    """The first CPU's fields in `cpuinfo` (none where the file is absent)."""
    try:
        text = cpuinfo.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return {}
    fields: dict[str, str] = {}
    for line in text.splitlines():
        if not line.strip():
            break
        key, _, value = line.partition(":")
        fields[key.strip()] = value.strip()
    return fields


def _cpu_flags(fields: dict[str, str]) -> list[str]:
    """The vector-instruction flags among a CPU's `fields`."""
    present = set((fields.get("flags") or fields.get("Features") or "").split())
    return [f for f in VECTOR_FLAGS if f in present]


def build_fingerprint() -> dict:
    """MuJoCo and NumPy versions, the machine architecture, its CPU's vector-instruction flags and
    its make and model."""
    fields = _cpu_fields()
    return {
        "mujoco": mujoco.__version__,
        "numpy": np.__version__,
        "machine": platform.machine(),
        "cpu_flags": _cpu_flags(fields),
        "cpu": " ".join(v for v in (fields.get("vendor_id"), fields.get("model name")) if v),
    }
