"""Balance feedback on a shipped modal gait, played without the kinematic snap."""

from eigengait.control.balance.gait_feedback import play_with_feedback
from eigengait.control.controller import load_controller, system_for, to_parameters
from eigengait.control.library import resolve


def test_feedback_follows_the_first_cycle_without_artificial_torque():
    path = resolve("gait", "kangaroo-hop")
    controller = load_controller(path)
    system = system_for(controller)
    params = to_parameters(controller, system, path)
    res = play_with_feedback(system, params, cycles=2, robustness=0.0)
    # Measured: 2 cycles, COM error 0.162 m against the shifted first cycle, speed 1.11 m/s.
    assert res.cycles_completed == 2 and not res.fell
    assert res.artificial_torque == 0.0 and res.balance_torque_rms > 0.0
    assert res.com_error_m < 0.25
    assert 0.5 < res.mean_speed_mps < 3.0
