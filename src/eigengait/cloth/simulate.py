"""The time loop: integrate, enforce constraints, resolve collisions, emit frames every 1/fps s."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterator

import numpy as np

from eigengait.cloth.collision import TriangleSoup, collide_self, collide_with_obstacles
from eigengait.cloth.integrators import INTEGRATORS, make_stepper
from eigengait.cloth.model import ClothModel
from eigengait.cloth.stability import check_step
from eigengait.errors import SimulationBlowUp, UserInputError


@dataclass(frozen=True)
class Frame:
    """Positions (N, 3) m and velocities (N, 3) m/s at ``time`` s; ``index`` counts frames from 0."""

    index: int
    time: float
    positions: np.ndarray
    velocities: np.ndarray


class Simulation:
    """State and stepping of one :class:`ClothModel`.

    Args:
        time_step: h in s. integrator: one of :data:`INTEGRATORS`.
        thickness: collision offset in m (default 2 % of the shortest rest length).
        restitution: normal restitution at contacts, 0 (inelastic) … 1 (FLEX3D's elastic bounce).
        self_collision: also collide each surface's points with its own and other surfaces' triangles.
    """

    def __init__(self, model: ClothModel, time_step: float, integrator: str = "euler", *,
                 thickness: float | None = None, restitution: float = 0.0, self_collision: bool = False):
        if integrator not in INTEGRATORS:
            raise UserInputError(f"unknown integrator '{integrator}'.", field="--integrator",
                                 fix=f"use one of: {', '.join(INTEGRATORS)}.")
        self.model = model
        self.h = float(time_step)
        self.integrator = integrator
        self.step_function = make_stepper(integrator, model, self.h)
        self.thickness = thickness if thickness is not None else 0.02 * float(model.spring_rest.min())
        self.restitution = restitution
        self.self_collision = self_collision
        corners = [mesh.vertices[mesh.triangles] for mesh in model.obstacles]
        self.obstacles = TriangleSoup(np.concatenate(corners)) if corners else None
        self.x = model.rest_positions.copy()
        self.v = np.zeros_like(self.x)
        self.t = 0.0
        self.steps = 0
        self.contacts = 0

    def step(self) -> None:
        x_new, v_new = self.step_function(self.x, self.v, self.t)
        self.steps += 1
        t_new = self.steps * self.h
        self.model.apply_constraints(x_new, v_new, t_new)
        movable = self.model.free
        if self.obstacles is not None:
            self.contacts += collide_with_obstacles(self.obstacles, self.x, x_new, v_new, movable,
                                                    thickness=self.thickness, restitution=self.restitution)
        if self.self_collision:
            self.contacts += collide_self(self.x, x_new, v_new, self.model.mass, self.model.triangles, movable,
                                          thickness=self.thickness, restitution=self.restitution)
        self.x, self.v, self.t = x_new, v_new, t_new

    def advance(self, steps: int) -> None:
        for _ in range(steps):
            self.step()


def run_frames(model: ClothModel, *, time_step: float, duration: float, frames_per_second: float,
               integrator: str = "euler", source: str = "<script>", step_field: str = "DELTA_T",
               warn: bool = True, **options) -> Iterator[Frame]:
    """Yield frames 0 … floor(duration·fps), frame k at t = k/fps s.

    Raises:
        SimulationBlowUp: positions became NaN/inf or ran away (> 10⁶ m); names the time and the step.
    """
    steps_per_frame = round(1.0 / (frames_per_second * time_step))
    if steps_per_frame < 1:
        raise UserInputError(f"DELTA_t = {time_step:g} s is longer than one frame (1/{frames_per_second:g} s).",
                             file=source, field=step_field, fix="make DELTA_t at most 1/QUADROS_SEG.")
    if warn:
        check_step(model, integrator, time_step, duration)
    sim = Simulation(model, time_step, integrator, **options)
    count = int(np.floor(duration * frames_per_second + 1e-9))
    yield Frame(0, 0.0, sim.x.copy(), sim.v.copy())
    for index in range(1, count + 1):
        sim.advance(steps_per_frame)
        if not np.isfinite(sim.x).all() or np.abs(sim.x).max() > 1e6:
            raise SimulationBlowUp(
                f"the simulation diverged before t = {sim.t:.3f} s (positions became NaN or ran away) with the "
                f"'{integrator}' integrator at DELTA_t = {time_step:g} s.", file=source, field=step_field,
                fix="use a smaller DELTA_t, more ATRITO, or --integrator implicit.")
        yield Frame(index, sim.t, sim.x.copy(), sim.v.copy())
