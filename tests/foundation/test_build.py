"""The build fingerprint that tells whether a recorded simulation can replay exactly here."""

import mujoco
import numpy as np

from eigengait.sim.build import _cpu_fields, _cpu_flags, _cpu_name, build_fingerprint


def test_cpu_flags_and_model_are_the_first_cpus(tmp_path):
    cpuinfo = tmp_path / "cpuinfo"
    cpuinfo.write_text(
        "processor\t: 0\nvendor_id\t: AuthenticAMD\ncpu family\t: 25\nmodel\t\t: 17\n"
        "model name\t: AMD EPYC\n"
        "flags\t\t: fpu sse4_2 avx avx2 fma\n\n"
        "processor\t: 1\nmodel name\t: other\nflags\t\t: avx512f\n"
    )
    fields = _cpu_fields(cpuinfo)
    assert _cpu_flags(fields) == ["sse4_2", "avx", "avx2", "fma"]
    # two generations of "AMD EPYC" are told apart by their family and model numbers
    assert _cpu_name(fields) == "AuthenticAMD AMD EPYC cpu family 25 model 17"
    arm = tmp_path / "arm"
    arm.write_text(
        "processor\t: 0\nFeatures\t: fp asimd evtstrm\nCPU implementer\t: 0x41\nCPU part\t: 0xd0c\n"
    )
    assert _cpu_flags(_cpu_fields(arm)) == ["asimd"]
    assert _cpu_name(_cpu_fields(arm)) == "CPU implementer 0x41 CPU part 0xd0c"
    assert _cpu_fields(tmp_path / "absent") == {} and _cpu_flags({}) == []


def test_fingerprint_names_the_versions_that_simulate():
    here = build_fingerprint()
    assert here["mujoco"] == mujoco.__version__ and here["numpy"] == np.__version__
    assert here == build_fingerprint()
