"""Which build simulated a recording: a falling gait amplifies rounding, so its figures replay
exactly only on the same MuJoCo and NumPy versions and the same kind of CPU: the vector
instructions MuJoCo and NumPy may use, and the CPU's make, model and generation (family and model
numbers: the name alone, "AMD EPYC", covers several), by which NumPy's OpenBLAS picks its kernels
(docs/locomotion.md, "Survival is chaotic"). The mode bases no longer depend on that rounding
(modal/eigen.py); the simulation of a falling gait still does."""

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


# the /proc/cpuinfo fields that name a CPU: x86's make, name and generation, Arm's designer, part
CPU_NAME_FIELDS = ("vendor_id", "model name", "cpu family", "model", "CPU implementer", "CPU part")


def _cpu_name(fields: dict[str, str]) -> str:
    """The CPU's make, model and generation from its `fields`, e.g. "AuthenticAMD AMD EPYC cpu
    family 25 model 17"."""
    named = {"cpu family", "model", "CPU implementer", "CPU part"}
    return " ".join(
        f"{key} {fields[key]}" if key in named else fields[key]
        for key in CPU_NAME_FIELDS
        if fields.get(key)
    )


def build_fingerprint() -> dict:
    """MuJoCo and NumPy versions, the machine architecture, its CPU's vector-instruction flags and
    its make, model and generation."""
    fields = _cpu_fields()
    return {
        "mujoco": mujoco.__version__,
        "numpy": np.__version__,
        "machine": platform.machine(),
        "cpu_flags": _cpu_flags(fields),
        "cpu": _cpu_name(fields),
    }
