"""Balance feedback on a shipped modal gait, played without the kinematic snap."""

from pathlib import Path

import pytest

from eigengait.control.balance.gait_feedback import play_with_feedback
from eigengait.control.controller import load_controller, system_for, to_parameters

GAIT = Path(__file__).resolve().parents[2] / "src/eigengait/data/gaits/humanoid-basic-run.json"


@pytest.mark.skipif(not GAIT.exists(), reason="shipped gait missing")
def test_feedback_follows_the_first_cycle_without_artificial_torque():
    controller = load_controller(GAIT)
    system = system_for(controller)
    params = to_parameters(controller, system, GAIT)
    res = play_with_feedback(system, params, cycles=2, robustness=0.0)
    # Measured: 2 cycles, COM error 0.041 m against the shifted first cycle, speed 2.1 m/s.
    assert res.cycles_completed == 2 and not res.fell
    assert res.artificial_torque == 0.0 and res.balance_torque_rms > 0.0
    assert res.com_error_m < 0.12
    assert 1.5 < res.mean_speed_mps < 3.0
