"""The build fingerprint that tells whether a recorded simulation can replay exactly here."""

import mujoco
import numpy as np

from eigengait.sim.build import _cpu_flags, build_fingerprint


def test_cpu_flags_keep_the_vector_instructions_of_the_first_cpu(tmp_path):
    cpuinfo = tmp_path / "cpuinfo"
    cpuinfo.write_text(
        "processor\t: 0\nflags\t\t: fpu sse4_2 avx avx2 fma\n\nprocessor\t: 1\nflags\t\t: avx512f\n"
    )
    assert _cpu_flags(cpuinfo) == ["sse4_2", "avx", "avx2", "fma"]
    arm = tmp_path / "arm"
    arm.write_text("processor\t: 0\nFeatures\t: fp asimd evtstrm\n")
    assert _cpu_flags(arm) == ["asimd"]
    assert _cpu_flags(tmp_path / "absent") == []


def test_fingerprint_names_the_versions_that_simulate():
    here = build_fingerprint()
    assert here["mujoco"] == mujoco.__version__ and here["numpy"] == np.__version__
    assert here == build_fingerprint()
