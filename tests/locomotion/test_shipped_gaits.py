"""The shipped gaits: named as documented, and played with physics only they do what their files
record."""

import json

import numpy as np
import pytest

from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_parameters
from eigengait.control.library import gait_names, resolve
from eigengait.control.playback import play
from eigengait.sim.build import build_fingerprint

REQUIRED = {"humanoid-basic-run", "monster-run", "kangaroo-hop", "dog-trot"}
REPLAYED = (
    "cycles_completed",
    "fell",
    "mean_speed_mps",
    "flight_fraction",
    "max_frame_jump_deg",
    "stance_slip_max_m",
    "cadence_spm",
)


def test_required_gaits_are_shipped(eigengait_cli):
    assert REQUIRED <= set(gait_names())
    listed = json.loads(eigengait_cli("gaits", "--json").stdout)
    assert REQUIRED <= {row["name"] for row in listed}


# scripts/make_gaits.py's prefix for the figures played without lookahead
WITHOUT = "without_lookahead_"


@pytest.mark.parametrize("name", sorted(gait_names()))
def test_shipped_gait_replays_its_recorded_metrics_without_reset(name):
    """20 cycles of physics only, feedback included and lookahead off, as scripts/make_gaits.py
    measured them (the same with lookahead is `benchmarks/bench_lookahead.py`: ~1 min per gait). A
    falling gait amplifies rounding, so the figures replay exactly only on the build that recorded
    them (`measured_on`); on any build, a replay of the first cycles is deterministic."""
    controller = load_controller(resolve("gait", name))
    system = gait_system(controller)
    params = to_parameters(controller, system)
    assert controller.measured_on is not None, (
        "measure it with scripts/make_gaits.py --measure-only"
    )
    if controller.measured_on != build_fingerprint():
        first, again = (play(system, params, cycles=2).qpos for _ in range(2))
        np.testing.assert_array_equal(first, again)
        pytest.skip(
            f"recorded on {controller.measured_on}, not this build: re-measure with make_gaits "
            "--measure-only"
        )
    result = play(system, params, cycles=20)
    summary = result.summary()
    assert summary["snap"] is False and summary["lookahead"] is False
    for key in REPLAYED:
        recorded = controller.metrics[WITHOUT + key]
        if isinstance(recorded, float):
            assert summary[key] == pytest.approx(recorded, rel=1e-3, abs=1e-3), key
        else:
            assert summary[key] == recorded, key
    # it goes forward (the planar walker's pulses alone barely: 0.05 m/s)
    assert result.mean_speed_mps > 0.0


def test_play_json_contract_on_a_shipped_gait(eigengait_cli):
    # the contract, not the lookahead, is under test: a few plans per decision keep it quick
    result = eigengait_cli(
        "play", "kangaroo-hop", "--cycles", "3", "--json", "--push", "100@0.5", "--plans", "8"
    )
    assert result.returncode == 0, result.stderr
    out = json.loads(result.stdout)
    assert out["snap"] is False and out["pushes_survived"] in (0, 1)
    for key in (
        "cadence_spm",
        "stride_m",
        "flight_fraction",
        "duty_factor",
        "stance_slip_m",
        "torso_pitch_deg",
        "torso_roll_deg",
        "footfall",
        "max_frame_jump_deg",
    ):
        assert key in out
    assert set(out["duty_factor"]) == {"foot"}
    # a shipped gait remembers its sketch: how much of the played torque is still the sketch's modes
    assert set(out["energy_split"]) == {"priority", "allowed", "excluded"}
    assert sum(out["energy_split"].values()) == pytest.approx(1.0, abs=1e-3)
    assert set(out["touchdowns_per_cycle"]) == set(out["min_foot_height_m"]) == {"foot"}


def test_snap_is_an_explicit_option(eigengait_cli):
    out = json.loads(
        eigengait_cli("play", "kangaroo-hop", "--cycles", "2", "--json", "--snap").stdout
    )
    assert out["snap"] is True
    bad = eigengait_cli("play", "kangaroo-hop", "--push", "lots@1")
    assert bad.returncode == 2 and "--push" in bad.stderr


def test_play_can_give_the_motors_an_activation_time(eigengait_cli):
    """The kangaroo's pulses (its file states no lag) played with a 40 ms and a 1 ms motor lag."""

    def pulses_with_lag(seconds: str) -> dict:
        return json.loads(
            eigengait_cli(
                "play", "kangaroo-hop", "--cycles", "1", "--json", "--no-lookahead",
                "--activation-time", seconds,
            ).stdout
        )  # fmt: skip

    lagged, instant = pulses_with_lag("0.04"), pulses_with_lag("0.001")
    assert lagged["activation_time"] == 0.04 and instant["activation_time"] == 0.001
    # the hop's 80-100 ms rectangular pulses lose much of their energy through a 40 ms lag, little
    # through 1 ms
    assert lagged["mean_squared_torque"] < 0.7 * instant["mean_squared_torque"]
    bad = eigengait_cli("play", "kangaroo-hop", "--activation-time", "-1")
    assert bad.returncode == 2 and "--activation-time" in bad.stderr and "0.01-0.05" in bad.stderr


def test_play_switches_the_swing_servo_on_and_off(eigengait_cli):
    """The servo's torques are in what is played: the same pulses with and without it apply other
    torques, and the JSON says which was played."""

    def pulses(flag: str) -> dict:
        return json.loads(
            eigengait_cli(
                "play", "dog-trot", "--cycles", "1", "--json", "--no-lookahead", flag
            ).stdout
        )

    on, off = pulses("--servo"), pulses("--no-servo")
    assert on["swing_servo"] is True and off["swing_servo"] is False
    assert on["mean_squared_torque"] != pytest.approx(off["mean_squared_torque"], rel=1e-3)
