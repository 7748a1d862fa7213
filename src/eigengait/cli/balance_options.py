"""Options shared by `eigengait track` and `eigengait balance`: the controller, the robustness
slider and, beside it, the cylinder foot model the momentum controller's slider acts through
(control/balance/foot.py, E30): radius, COM height and friction.

`balance_settings` checks them all before any simulation runs and turns the foot's into
`TrackerSettings` fields.
"""

from __future__ import annotations

import typer

from eigengait.inputs import check_range

CONTROLLER_OPTION = typer.Option(
    "qp",
    "--controller",
    help="qp: whole-body inverse dynamics, one least-squares problem over accelerations and "
    "contact forces per step; momentum: joint PD with balance through the momentum Jacobian and "
    "the stance-foot compensation (the chapter's).",
)
ROBUSTNESS_OPTION = typer.Option(
    0.5,
    "--robustness",
    help=(
        "0 = physically correct (no artificial torque) … 1 = artificial torque on the pelvis "
        "nearly free (qp) or the stance-foot torque fully cancelled (momentum): very stable."
    ),
)
FOOT_RADIUS_OPTION = typer.Option(
    0.1,
    "--foot-radius",
    help="Foot model radius (m), momentum controller: with the robustness, sets the stance-foot "
    "torque cancelled.",
)
FOOT_HEIGHT_OPTION = typer.Option(
    0.05, "--foot-height", help="Foot model COM height above the floor (m), momentum controller."
)
FOOT_FRICTION_OPTION = typer.Option(
    1.0,
    "--foot-friction",
    help="Foot model friction coefficient μ, momentum controller (the friction cone's edge is "
    "atan(1/μ)).",
)


def balance_settings(
    robustness: float, foot_radius: float, foot_height: float, foot_friction: float
) -> dict:
    """One clear error for any value out of range; else the foot model as `TrackerSettings` keyword
    arguments."""
    check_range(
        robustness,
        "--robustness",
        0,
        1,
        fix="use a value between 0 (physically correct) and 1 (fully compensated).",
    )
    check_range(foot_radius, "--foot-radius", 0, 1, unit="m")
    check_range(foot_height, "--foot-height", 0, 1, unit="m")
    check_range(foot_friction, "--foot-friction", 0.01, 10)
    return {
        "foot_radius_m": foot_radius,
        "foot_com_height_m": foot_height,
        "foot_friction": foot_friction,
    }
