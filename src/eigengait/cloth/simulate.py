"""The time loop: integrate, enforce constraints, limit strain, resolve contacts, emit frames every
1/fps s."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Iterator

import numpy as np

from eigengait.cloth import contact, kernels
from eigengait.cloth.collision import TriangleSoup, collide_self, collide_with_obstacles
from eigengait.cloth.integrators import INTEGRATORS, make_stepper
from eigengait.cloth.model import ClothModel
from eigengait.cloth.stability import check_step
from eigengait.cloth.strain import DEFAULT_BOUND, limit_strain, projection_order
from eigengait.errors import SimulationBlowUp, UserInputError
from eigengait.inputs import check_choice


@dataclass(frozen=True)
class Frame:
    """Positions (N, 3) m and velocities (N, 3) m/s at ``time`` s; ``index`` counts frames
    from 0."""

    index: int
    time: float
    positions: np.ndarray
    velocities: np.ndarray


class Simulation:
    """State and stepping of one :class:`ClothModel`.

    Args:
        time_step: h in s. integrator: one of :data:`INTEGRATORS`.
        thickness: collision offset in m (default 5 % of the shortest rest length; 2 % in
            dissertation mode).
        restitution: normal restitution at contacts, 0 (inelastic) … 1 (FLEX3D's elastic bounce).
        self_collision: also collide each surface's points with its own and other surfaces'
            triangles.
        strain_limit: largest spring strain kept after each step (Provot 1995; 0.1 = 10 %); None
            switches it off.
        floor: height (m, world z) of an infinite floor plane the cloth rests on; None for no floor.
        dissertation: FLEX3D as published — no strain limiting, only swept point–triangle hits
            (no resting contact or obstacle-edge test), thickness 2 % — for reproducing the
            dissertation's results.
    """

    def __init__(
        self,
        model: ClothModel,
        time_step: float,
        integrator: str = "euler",
        *,
        thickness: float | None = None,
        restitution: float = 0.0,
        self_collision: bool = False,
        strain_limit: float | None = DEFAULT_BOUND,
        floor: float | None = None,
        dissertation: bool = False,
    ):
        check_choice(integrator, INTEGRATORS, "integrator", "integrator")
        if len(model.targets):
            model = replace(
                model, fixed=model.fixed.copy(), rest_positions=model.rest_positions.copy()
            )
        self.model = model
        self.h = float(time_step)
        self.integrator = integrator
        self.step_function = make_stepper(integrator, model, self.h)
        rest = float(model.spring_rest.min()) if len(model.spring_rest) else 1.0
        self.thickness = (
            thickness if thickness is not None else (0.02 if dissertation else 0.05) * rest
        )
        self.restitution = restitution
        self.self_collision = self_collision
        self.strain_limit = None if dissertation else strain_limit
        self.floor = floor
        self.dissertation = dissertation
        self._cloth_grid = TriangleGrid(model.triangles, float(model.spring_rest.max()))
        self.obstacles = (
            Obstacles(model, self.thickness, self._cloth_grid) if model.obstacles else None
        )
        self._reached = np.zeros(len(model.targets), bool)
        self._order_springs()
        self.x = model.rest_positions.copy()
        self.v = np.zeros_like(self.x)
        self.t = 0.0
        self.steps = 0
        self.contacts = 0

    def step(self) -> None:
        """One step: integrate, prescribed points, strain limit, contacts, links, targets."""
        m = self.model
        x_new, v_new = self.step_function(self.x, self.v, self.t)
        self.steps += 1
        t_new = self.steps * self.h
        m.apply_constraints(x_new, v_new, t_new)
        if self.strain_limit is not None:
            limit_strain(
                x_new,
                v_new,
                self._strain_springs,
                self._strain_rest,
                self._strain_weights,
                self.strain_limit,
                self.h,
            )
        movable = m.free
        if self.obstacles is not None:
            if self.dissertation:
                self.contacts += collide_with_obstacles(
                    self.obstacles.soup,
                    self.x,
                    x_new,
                    v_new,
                    movable,
                    thickness=self.thickness,
                    restitution=self.restitution,
                )
            else:
                self.contacts += self.obstacles.collide(
                    self.x, x_new, v_new, movable, self.restitution
                )
        if self.floor is not None:
            self.contacts += rest_on_floor(
                x_new, v_new, movable, self.floor + self.thickness, self.restitution
            )
        if self.self_collision and m.compiled:
            grid = self._cloth_grid.build(x_new, self.thickness)
            self.contacts += contact.collide_self(
                self.x,
                x_new,
                v_new,
                m.mass,
                movable,
                self._cloth_grid.triangles,
                *grid,
                self.thickness,
                self.restitution,
            )
        elif self.self_collision:
            self.contacts += collide_self(
                self.x,
                x_new,
                v_new,
                m.mass,
                m.triangles,
                movable,
                thickness=self.thickness,
                restitution=self.restitution,
            )
        if len(m.links):
            m.join_links(x_new, v_new)
        if len(m.targets) and not self._reached.all():
            self._fix_reached(self.x, x_new, v_new)
        self.x, self.v, self.t = x_new, v_new, t_new

    def _order_springs(self) -> None:
        """Sweep order and end weights of the strain limiter for the current set of fixed points."""
        m = self.model
        order, self._strain_weights = projection_order(m.springs, m.mass, m.fixed)
        self._strain_springs, self._strain_rest = m.springs[order], m.spring_rest[order]
        self._strain_k = m.spring_k[order]
        self._runs = kernels.SpringRuns(self._strain_springs, m.size)

    def _fix_reached(self, x0: np.ndarray, x1: np.ndarray, v: np.ndarray) -> None:
        """Fix each target point whose step segment passed within its radius of its target
        position."""
        m = self.model
        open_ = np.flatnonzero(~self._reached)
        idx, goal = m.targets[open_], m.target_positions[open_]
        step = x1[idx] - x0[idx]
        s = np.clip(
            ((goal - x0[idx]) * step).sum(axis=1) / np.maximum((step * step).sum(axis=1), 1e-300),
            0,
            1,
        )
        near = np.linalg.norm(x0[idx] + s[:, None] * step - goal, axis=1) <= m.target_radius[open_]
        for k in open_[near]:
            i = m.targets[k]
            self._reached[k] = True
            m.fixed[i], m.free[i] = True, False
            m.rest_positions[i] = x1[i] = m.target_positions[k]
            v[i] = 0.0
        if near.any():
            self._order_springs()

    def advance(self, steps: int) -> None:
        """Take ``steps`` steps of h s (in one compiled loop when :attr:`_fused` allows it)."""
        if self._fused is None:
            for _ in range(steps):
                self.step()
            return
        m = self.model
        bound = -1.0 if self.strain_limit is None else self.strain_limit
        runs = self._runs
        kernels.explicit_steps(
            self.x,
            self.v,
            steps,
            self.h,
            self._fused,
            m.mass,
            self._strain_springs,
            self._strain_rest,
            self._strain_k,
            self._strain_weights,
            m.bend,
            m.bend_coef,
            m.gravity,
            m.external_force,
            m.friction,
            m.free,
            bound,
            runs.runs,
            runs.touch_start,
            runs.touching,
        )
        self.steps += steps
        self.t = self.steps * self.h

    @property
    def _fused(self) -> int | None:
        """The fused kernel's method code when whole runs of steps can stay compiled, else None: an
        explicit Euler method, compiled model, and no moving constraint, contact or link to resolve
        between steps."""
        m = self.model
        simple = (
            m.compiled
            and not m.motions
            and not m.obstacles
            and not len(m.links)
            and not len(m.targets)
            and self.floor is None
            and not self.self_collision
        )
        return kernels.FUSED.get(self.integrator) if simple else None


class TriangleGrid:
    """A uniform grid over the cloth's triangles, rebuilt from the current positions when asked."""

    def __init__(self, triangles: np.ndarray, cell: float):
        self.triangles = triangles
        self.cell = cell
        self._lo = np.zeros((len(triangles), 3))
        self._hi = np.zeros((len(triangles), 3))

    def build(self, x: np.ndarray, pad: float) -> tuple:
        """(origin, cell, dims, start, items) of the triangles' boxes at ``x``, padded by ``pad``
        m."""
        contact.triangle_boxes(x, self.triangles, pad, self._lo, self._hi)
        origin, cell, dims = contact.grid_layout(self._lo, self._hi, self.cell)
        return (origin, cell, dims, *contact.build_grid(self._lo, self._hi, origin, cell, dims))


class Obstacles:
    """The static obstacles of a model, prepared for the compiled contact tests (grids built
    once)."""

    def __init__(self, model: ClothModel, thickness: float, cloth: TriangleGrid):
        corners = np.concatenate([mesh.vertices[mesh.triangles] for mesh in model.obstacles])
        self.soup = TriangleSoup(corners)
        self.thickness = thickness
        pad = thickness + float(model.spring_rest.max())
        lo, hi = corners.min(axis=1) - pad, corners.max(axis=1) + pad
        self.origin, self.cell, self.dims = contact.grid_layout(
            lo, hi, 2.0 * float(self.soup.radii.mean()) + pad
        )
        self.start, self.items = contact.build_grid(lo, hi, self.origin, self.cell, self.dims)
        spacing = 0.5 * float(model.spring_rest.min())
        samples = [
            contact.convex_edge_samples(mesh.vertices, mesh.triangles, spacing)
            for mesh in model.obstacles
        ]
        self.samples = np.concatenate([s for s, _ in samples])
        self.directions = np.concatenate([d for _, d in samples])
        self.cloth = cloth
        self.depth = float(model.spring_rest.max())

    def collide(
        self, x0: np.ndarray, x1: np.ndarray, v: np.ndarray, movable: np.ndarray, restitution: float
    ) -> int:
        """Crossing, resting and edge contacts, in place on (x1, v); returns the number of
        contacts."""
        count = contact.collide_points(
            x0,
            x1,
            v,
            movable,
            self.soup.corners,
            self.soup.normals,
            self.origin,
            self.cell,
            self.dims,
            self.start,
            self.items,
            self.thickness,
            restitution,
        )
        if len(self.samples) and len(self.cloth.triangles):
            grid = self.cloth.build(x1, 0.0)
            count += contact.collide_edges(
                self.samples,
                self.directions,
                x1,
                v,
                movable,
                self.cloth.triangles,
                *grid,
                self.thickness,
                self.depth,
            )
        return count


def rest_on_floor(
    x: np.ndarray, v: np.ndarray, movable: np.ndarray, level: float, restitution: float
) -> int:
    """Lift movable points below ``level`` (m, world z) onto it; their downward velocity becomes
    ``-e v_z``."""
    below = movable & (x[:, 2] < level)
    x[below, 2] = level
    v[below, 2] = np.where(v[below, 2] < 0.0, -restitution * v[below, 2], v[below, 2])
    return int(below.sum())


def frame_steps(
    time_step: float,
    duration: float,
    frames_per_second: float,
    source: str = "<script>",
    step_field: str = "DELTA_T",
) -> np.ndarray:
    """Step counts of the script's frames 0 … floor(duration·fps): frame k after k·round(1/(fps·h))
    steps of h s.

    Raises:
        UserInputError: h is longer than one frame.
    """
    steps_per_frame = round(1.0 / (frames_per_second * time_step))
    if steps_per_frame < 1:
        raise UserInputError(
            f"DELTA_t = {time_step:g} s is longer than one frame (1/{frames_per_second:g} s).",
            file=source,
            field=step_field,
            fix="make DELTA_t at most 1/QUADROS_SEG.",
        )
    return steps_per_frame * np.arange(int(np.floor(duration * frames_per_second + 1e-9)) + 1)


def video_steps(time_step: float, duration: float, fps: float) -> np.ndarray:
    """Step count nearest t = j/fps s for the video frames j = 0 … round(duration·fps) (repeats when
    h > 1/fps)."""
    count = int(round(duration * fps)) + 1
    return np.rint(np.arange(count) / (fps * time_step)).astype(int)


def run_samples(
    model: ClothModel,
    steps: np.ndarray,
    *,
    time_step: float,
    integrator: str = "euler",
    source: str = "<script>",
    step_field: str = "DELTA_T",
    warn: bool = True,
    **options,
) -> Iterator[Frame]:
    """Yield the state after each of the increasing step counts ``steps`` (h = ``time_step`` s),
    numbered from 0.

    Raises:
        SimulationBlowUp: positions became NaN/inf or ran away (> 10⁶ m); names the time and the
            step.
    """
    if warn:
        check_step(model, integrator, time_step, int(steps[-1]) * time_step)
    sim = Simulation(model, time_step, integrator, **options)
    for index, step in enumerate(steps):
        sim.advance(int(step) - sim.steps)
        if not np.isfinite(sim.x).all() or np.abs(sim.x).max() > 1e6:
            raise SimulationBlowUp(
                f"the simulation diverged before t = {sim.t:.3f} s (positions became NaN or ran "
                f"away) with the '{integrator}' integrator at DELTA_t = {time_step:g} s.",
                file=source,
                field=step_field,
                fix="use a smaller DELTA_t, more ATRITO, or integrator='implicit'.",
            )
        yield Frame(index, sim.t, sim.x.copy(), sim.v.copy())


def run_frames(
    model: ClothModel,
    *,
    time_step: float,
    duration: float,
    frames_per_second: float,
    source: str = "<script>",
    step_field: str = "DELTA_T",
    **options,
) -> Iterator[Frame]:
    """Yield the script's frames 0 … floor(duration·fps), frame k at t ≈ k/fps s (see
    :func:`frame_steps`)."""
    steps = frame_steps(time_step, duration, frames_per_second, source, step_field)
    yield from run_samples(
        model, steps, time_step=time_step, source=source, step_field=step_field, **options
    )
