"""E30–E32: tunable compensation of the balance torque on the stance foot, from a cylinder-foot
friction cone.

The foot is modelled as a cylinder of radius r whose COM is h above the floor; the largest ground
reaction GRF_max = m lies on the friction cone's edge at θ = atan(1/μ) from the horizontal. The
largest torque the ground can absorb is ‖τ_comp‖ = |h m cosθ + r m sinθ| (E30). ratio = min(1,
‖τ_comp‖ / ‖horizontal ^foot τ_eq‖) (E31) is the fraction of the horizontal balance torque on the
foot cancelled by an artificial torque (E32); the vertical part is cancelled by the same robustness
fraction (the chapter always cancels it fully, which would leave artificial torque even at
robustness 0).

Robustness R ∈ [0, 1] sets m = R/(1 − R) × body weight: R = 0 cancels nothing (physically correct),
R = 1 cancels the whole stance-foot torque (very stable), R = 0.5 lets the model foot carry the body
weight at the cone edge.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from eigengait.errors import UserInputError

UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class FootModel:
    """Cylinder foot: radius_m, com_height_m, grf_max_n (N, may be inf), friction μ; robustness it
    came from."""

    radius_m: float
    com_height_m: float
    grf_max_n: float
    friction: float
    robustness: float

    def compensable_torque(self) -> float:
        """E30: ‖τ_comp‖ in N·m."""
        if self.grf_max_n == 0.0:
            return 0.0
        theta = np.arctan(1.0 / self.friction)
        return float(
            abs(
                self.com_height_m * self.grf_max_n * np.cos(theta)
                + self.radius_m * self.grf_max_n * np.sin(theta)
            )
        )


def foot_model_for_robustness(
    robustness: float, weight_n: float, radius_m: float, com_height_m: float, friction: float = 1.0
) -> FootModel:
    """Map the user's robustness R ∈ [0, 1] onto the foot model's GRF_max = R/(1−R) × weight."""
    if not 0.0 <= robustness <= 1.0 or not np.isfinite(robustness):
        raise UserInputError(
            f"robustness {robustness} is out of range.",
            field="robustness",
            fix="use a value between 0 (physically correct) and 1 (fully compensated).",
        )
    grf = np.inf if robustness == 1.0 else weight_n * robustness / (1.0 - robustness)
    return FootModel(radius_m, com_height_m, float(grf), friction, robustness)


def compensation(foot_torque: np.ndarray, foot: FootModel) -> tuple[np.ndarray, float]:
    """E31–E32 for the balance torque on a stance foot (world, N·m): the artificial torque to add
    and the ratio."""
    vertical = UP * (foot_torque @ UP)
    horizontal = foot_torque - vertical
    size = float(np.linalg.norm(horizontal))
    comp = foot.compensable_torque()
    ratio = 1.0 if size <= comp else comp / size
    return -(ratio * horizontal + foot.robustness * vertical), ratio
