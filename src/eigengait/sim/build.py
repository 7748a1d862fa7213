"""Which build simulated a recording: a falling gait amplifies rounding, so its figures replay
exactly only on the same MuJoCo and NumPy versions and the same kind of CPU (the vector instructions
MuJoCo and NumPy may use)."""

from __future__ import annotations

import platform
from pathlib import Path

import mujoco
import numpy as np

VECTOR_FLAGS = ("sse4_2", "avx", "avx2", "fma", "avx512f", "avx512dq", "avx512vl", "asimd", "sve")


def _cpu_flags(cpuinfo: Path = Path("/proc/cpuinfo")) -> list[str]:
    """The vector-instruction flags of the first CPU listed in `cpuinfo` (none where the file is
    absent)."""
    try:
        text = cpuinfo.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return []
    for line in text.splitlines():
        if line.split(":")[0].strip() in ("flags", "Features"):
            present = set(line.split(":", 1)[1].split())
            return [f for f in VECTOR_FLAGS if f in present]
    return []


def build_fingerprint() -> dict:
    """MuJoCo and NumPy versions, the machine architecture and its CPU's vector-instruction
    flags."""
    return {
        "mujoco": mujoco.__version__,
        "numpy": np.__version__,
        "machine": platform.machine(),
        "cpu_flags": _cpu_flags(),
    }
