"""The FLEX3D mass–spring surface: particles, springs, angular springs, forces and their Jacobian.

All surfaces of a scene are packed into one particle system (positions (N, 3) in m, z-up world).

* Elastic springs join each mass point to its 8 neighbours: horizontal (k_h, rest r), vertical
  (k_v, rest r) and diagonal (k_d, rest r√2). The force on the end i of a spring i→j is
  ``k (|d| - rest) d/|d|``, d = x_j - x_i.
* Angular springs (FLEX3D's bending): for each opposite neighbour pair (a, b) of a point c, with
  unit vectors u_a, u_b from c towards a and b, ``F_c = k_c (r/2)(u_a + u_b)`` — the pull towards
  the midpoint of the two points at distance r along the neighbours. It acts on c only, as in
  FLEX3D, and vanishes when a, c, b are collinear. Horizontal, vertical and diagonal pairs take the
  three CONST_CURVATURA values.
* Gravity ``m g`` and one external force vector (N per point) act on every point.
* Friction removes a fraction μ (ATRITO) of the resultant force, opposite to the velocity:
  ``F_fric = -min(μ |F|, m |v| / h) v/|v|``. The cap stops friction from reversing a velocity within
one step, so the friction power ``F_fric · v`` is never positive.
* Point constraints: fixed points (with timed translations), ``targets`` that become fixed on
  reaching a position (within ``target_radius`` m), and ``links`` (pairs of points of two surfaces
  held together).

Forces are computed by the compiled kernels of :mod:`eigengait.cloth.kernels`; with ``compiled``
off, the NumPy reference path (:meth:`ClothModel.internal_forces_reference`) runs instead.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from eigengait.cloth import contact, kernels
from eigengait.cloth.obt import Mesh
from eigengait.cloth.par import Script, SurfaceSpec
from eigengait.errors import UserInputError

#: (row step, col step, stiffness class) for the 4 spring directions that cover the 8-neighbourhood
#: once.
_SPRING_DIRECTIONS = ((0, 1, 0), (1, 0, 1), (1, 1, 2), (1, -1, 2))


@dataclass(frozen=True)
class SurfaceLayout:
    """Where one surface's ``rows × cols`` points live in the packed arrays (row-major from
    ``start``)."""

    name: str
    start: int
    rows: int
    cols: int

    @property
    def indices(self) -> np.ndarray:
        return np.arange(self.start, self.start + self.rows * self.cols)

    @property
    def quads(self) -> np.ndarray:
        """(Q, 4) point indices of the grid cells, counter-clockwise seen from the normal side."""
        r, c = np.meshgrid(np.arange(self.rows - 1), np.arange(self.cols - 1), indexing="ij")
        base = self.start + r.ravel() * self.cols + c.ravel()
        return np.stack([base, base + self.cols, base + self.cols + 1, base + 1], axis=1)

    @property
    def triangles(self) -> np.ndarray:
        """(T, 3) point indices: every grid cell split into two triangles."""
        q = self.quads
        return np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])


@dataclass(frozen=True)
class KinematicMotion:
    """Prescribed translation of ``indices``: ``velocity`` (K, 3) m/s active on [start_k, end_k]
    s."""

    indices: np.ndarray
    velocity: np.ndarray
    start: np.ndarray
    end: np.ndarray

    def displacement(self, t: float) -> np.ndarray:
        return (self.velocity * np.clip(t - self.start, 0.0, self.end - self.start)[:, None]).sum(
            axis=0
        )

    def velocity_at(self, t: float) -> np.ndarray:
        active = (t >= self.start) & (t < self.end)
        return self.velocity[active].sum(axis=0)


@dataclass
class ClothModel:
    """A packed particle system; see the module docstring for the force laws."""

    rest_positions: np.ndarray
    mass: np.ndarray
    springs: np.ndarray
    spring_rest: np.ndarray
    spring_k: np.ndarray
    bend: np.ndarray
    bend_k: np.ndarray
    bend_r: np.ndarray
    fixed: np.ndarray
    surfaces: list[SurfaceLayout]
    motions: list[KinematicMotion] = field(default_factory=list)
    gravity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    external_force: np.ndarray = field(default_factory=lambda: np.zeros(3))
    friction: float = 0.0
    obstacles: list[Mesh] = field(default_factory=list)
    targets: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    target_positions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    target_radius: np.ndarray = field(default_factory=lambda: np.zeros(0))
    links: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int64))
    compiled: bool = True

    def __post_init__(self):
        n, s, b = len(self.mass), len(self.springs), len(self.bend)
        # Incidence matrices scatter per-spring / per-angular-spring forces onto points with one
        # sparse product.
        self._spring_scatter = sp.csr_matrix(
            (
                np.r_[np.ones(s), -np.ones(s)],
                (self.springs.T.ravel(), np.r_[np.arange(s), np.arange(s)]),
            ),
            shape=(n, s),
        )
        self._bend_scatter = sp.csr_matrix(
            (np.ones(b), (self.bend[:, 1], np.arange(b))), shape=(n, b)
        )
        self.free = ~self.fixed
        self.bend_coef = 0.5 * self.bend_k * self.bend_r

    @property
    def size(self) -> int:
        return len(self.mass)

    @property
    def triangles(self) -> np.ndarray:
        return (
            np.concatenate([s.triangles for s in self.surfaces])
            if self.surfaces
            else np.zeros((0, 3), int)
        )

    def internal_forces(self, x: np.ndarray) -> np.ndarray:
        """Elastic + angular-spring forces (N, 3) in N at positions ``x`` (compiled kernel unless
        ``compiled`` is off, then the NumPy reference below)."""
        if self.compiled:
            force = np.empty_like(x)
            kernels.internal_forces(
                x, self.springs, self.spring_rest, self.spring_k, self.bend, self.bend_coef, force
            )
            return force
        return self.internal_forces_reference(x)

    def internal_forces_reference(self, x: np.ndarray) -> np.ndarray:
        """NumPy reference of :meth:`internal_forces`: vectorized over springs, scattered by sparse
        products."""
        d = x[self.springs[:, 1]] - x[self.springs[:, 0]]
        length = np.linalg.norm(d, axis=1)
        tension = self.spring_k * (length - self.spring_rest) / np.maximum(length, 1e-12)
        force = self._spring_scatter @ (tension[:, None] * d)
        if len(self.bend):
            c = x[self.bend[:, 1]]
            ua = x[self.bend[:, 0]] - c
            ub = x[self.bend[:, 2]] - c
            ua /= np.maximum(np.linalg.norm(ua, axis=1), 1e-12)[:, None]
            ub /= np.maximum(np.linalg.norm(ub, axis=1), 1e-12)[:, None]
            force += self._bend_scatter @ (self.bend_coef[:, None] * (ua + ub))
        return force

    def applied_forces(self, x: np.ndarray) -> np.ndarray:
        """Everything but friction: internal + gravity + external (N, 3) in N."""
        return self.internal_forces(x) + self.mass[:, None] * self.gravity + self.external_force

    def friction_force(self, force: np.ndarray, v: np.ndarray, h: float) -> np.ndarray:
        """``-min(μ|F|, m|v|/h) v̂`` (N, 3) in N; zero where v = 0."""
        if self.friction == 0.0:
            return np.zeros_like(v)
        speed = np.linalg.norm(v, axis=1)
        magnitude = np.minimum(self.friction * np.linalg.norm(force, axis=1), self.mass * speed / h)
        return -(magnitude / np.maximum(speed, 1e-300))[:, None] * v

    def acceleration(self, x: np.ndarray, v: np.ndarray, h: float) -> np.ndarray:
        """Acceleration (N, 3) in m/s²; zero at fixed points (their motion is prescribed)."""
        force = self.applied_forces(x)
        a = (force + self.friction_force(force, v, h)) / self.mass[:, None]
        a[self.fixed] = 0.0
        return a

    def prescribed(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities (N, 3) of the constrained points at time t (rows of free points
        unused)."""
        x = self.rest_positions.copy()
        v = np.zeros_like(x)
        for motion in self.motions:
            x[motion.indices] += motion.displacement(t)
            v[motion.indices] = motion.velocity_at(t)
        return x, v

    def apply_constraints(self, x: np.ndarray, v: np.ndarray, t: float) -> None:
        """Overwrite fixed points in place with their prescribed state at time t."""
        index = np.flatnonzero(self.fixed)
        x[index] = self.rest_positions[index]
        v[index] = 0.0
        for motion in self.motions:
            x[motion.indices] += motion.displacement(t)
            v[motion.indices] = motion.velocity_at(t)

    def join_links(self, x: np.ndarray, v: np.ndarray) -> None:
        """Give both points of every link their common mass-weighted position and velocity, in
        place; a fixed point keeps its own and the other follows it."""
        a, b = self.links[:, 0], self.links[:, 1]
        wa = np.where(self.fixed[a], 1.0, np.where(self.fixed[b], 0.0, self.mass[a]))
        wb = np.where(self.fixed[b], 1.0, np.where(self.fixed[a], 0.0, self.mass[b]))
        share = (wa / (wa + wb))[:, None]
        for state in (x, v):
            common = share * state[a] + (1.0 - share) * state[b]
            state[a] = common
            state[b] = common

    def energy(self, x: np.ndarray, v: np.ndarray) -> float:
        """Kinetic + spring + gravity + external-force potential energy in J (angular springs
        excluded)."""
        length = np.linalg.norm(x[self.springs[:, 1]] - x[self.springs[:, 0]], axis=1)
        kinetic = 0.5 * float((self.mass * (v**2).sum(axis=1)).sum())
        elastic = 0.5 * float((self.spring_k * (length - self.spring_rest) ** 2).sum())
        potential = -float((self.mass[:, None] * self.gravity * x).sum()) - float(
            (self.external_force * x).sum()
        )
        return kinetic + elastic + potential


def surface_frame(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(row direction, column direction) of a grid with unit ``normal`` (z-up).

    Rows run "down" the surface (world -z projected on its plane), so FLEX3D's row 0 is the top edge
    of a vertical surface; a horizontal surface's rows run along -y. Columns are ``normal × row``.
    """
    down = np.array([0.0, 0.0, -1.0]) - normal * -normal[2]
    if np.linalg.norm(down) < 1e-9:
        down = np.array([0.0, -1.0, 0.0]) - normal * -normal[1]
    row = down / np.linalg.norm(down)
    col = np.cross(normal, row)
    return row, col / np.linalg.norm(col)


def grid_positions(rows: int, cols: int, spacing: float, position, normal) -> np.ndarray:
    """(rows·cols, 3) row-major points ``spacing`` m apart, centred on ``position``, facing
    ``normal``."""
    row_dir, col_dir = surface_frame(np.asarray(normal, float) / np.linalg.norm(normal))
    i, j = np.meshgrid(
        np.arange(rows) - (rows - 1) / 2, np.arange(cols) - (cols - 1) / 2, indexing="ij"
    )
    return np.asarray(position, float) + spacing * (
        i.ravel()[:, None] * row_dir + j.ravel()[:, None] * col_dir
    )


def grid_springs(
    rows: int, cols: int, start: int, spacing: float, stiffness
) -> tuple[np.ndarray, ...]:
    """Springs of a grid: (S, 2) point pairs, rest lengths (S,) m and constants (S,) N/m."""
    idx = start + np.arange(rows * cols).reshape(rows, cols)
    pairs, rest, k = [], [], []
    for di, dj, kind in _SPRING_DIRECTIONS:
        r1, c0, c1 = rows - di, max(0, -dj), cols - max(0, dj)
        if r1 <= 0 or c1 <= c0:
            continue
        a = idx[:r1, c0:c1]
        b = idx[di : r1 + di, c0 + dj : c1 + dj]
        pairs.append(np.stack([a.ravel(), b.ravel()], axis=1))
        rest.append(np.full(a.size, spacing * (np.sqrt(2.0) if kind == 2 else 1.0)))
        k.append(np.full(a.size, float(stiffness[kind])))
    return np.concatenate(pairs), np.concatenate(rest), np.concatenate(k)


def grid_bending(rows: int, cols: int, start: int, constants) -> tuple[np.ndarray, np.ndarray]:
    """Angular springs of a grid: (B, 3) triples (a, centre, b) and constants (B,) N/m."""
    idx = start + np.arange(rows * cols).reshape(rows, cols)
    triples, k = [], []
    for di, dj, kind in _SPRING_DIRECTIONS:
        r0, r1 = di, rows - di
        c0, c1 = abs(dj), cols - abs(dj)
        if r1 <= r0 or c1 <= c0:
            continue
        centre = idx[r0:r1, c0:c1]
        before = idx[r0 - di : r1 - di, c0 - dj : c1 - dj]
        after = idx[r0 + di : r1 + di, c0 + dj : c1 + dj]
        triples.append(np.stack([before.ravel(), centre.ravel(), after.ravel()], axis=1))
        k.append(np.full(centre.size, float(constants[kind])))
    if not triples:
        return np.zeros((0, 3), np.int64), np.zeros(0)
    return np.concatenate(triples), np.concatenate(k)


def surface_model(
    surfaces: list[SurfaceSpec],
    *,
    frames_per_second: float = 1.0,
    stretch: float = 1.0,
    gravity=(0.0, 0.0, 0.0),
    external_force=(0.0, 0.0, 0.0),
    friction: float = 0.0,
    obstacles: list[Mesh] | None = None,
    source: str = "<script>",
) -> ClothModel:
    """Pack ``surfaces`` into one :class:`ClothModel`.

    ``stretch`` scales the initial spacing (1.05 starts every spring 5 % longer than rest: a
    pre-tensioned surface); translations are per frame, so ``frames_per_second`` turns them into
    velocities. A target point is reached when its path passes within 10 % of its surface's spacing
    of the target. A point attached to an obstacle is moved to the nearest point of the obstacle's
    surface and fixed there (obstacles are static).

    Raises:
        UserInputError: an attachment names no surface or obstacle of the scene (``source`` names
            the file).
    """
    positions, mass, springs, rest, k, bend, bend_k, bend_r, fixed, layouts, motions = (
        [] for _ in range(11)
    )
    start = 0
    for spec in surfaces:
        count = spec.rows * spec.cols
        positions.append(
            grid_positions(spec.rows, spec.cols, spec.spacing * stretch, spec.position, spec.normal)
        )
        mass.append(np.full(count, spec.mass))
        s_pairs, s_rest, s_k = grid_springs(
            spec.rows, spec.cols, start, spec.spacing, spec.stiffness
        )
        springs.append(s_pairs), rest.append(s_rest), k.append(s_k)
        b_triples, b_k = grid_bending(spec.rows, spec.cols, start, spec.bending)
        keep = b_k != 0
        (
            bend.append(b_triples[keep]),
            bend_k.append(b_k[keep]),
            bend_r.append(np.full(keep.sum(), spec.spacing)),
        )
        mask = np.zeros(count, bool)
        for i, j in spec.fixed:
            mask[i * spec.cols + j] = True
        fixed.append(mask)
        if spec.translations and mask.any():
            motions.append(
                KinematicMotion(
                    indices=start + np.flatnonzero(mask),
                    velocity=np.array([t.step * frames_per_second for t in spec.translations]),
                    start=np.array([t.start for t in spec.translations], float),
                    end=np.array([t.end for t in spec.translations], float),
                )
            )
        layouts.append(SurfaceLayout(spec.name, start, spec.rows, spec.cols))
        start += count
    model = ClothModel(
        rest_positions=np.concatenate(positions),
        mass=np.concatenate(mass),
        springs=np.concatenate(springs).astype(np.int64),
        spring_rest=np.concatenate(rest),
        spring_k=np.concatenate(k),
        bend=np.concatenate(bend).astype(np.int64).reshape(-1, 3),
        bend_k=np.concatenate(bend_k),
        bend_r=np.concatenate(bend_r),
        fixed=np.concatenate(fixed),
        surfaces=layouts,
        motions=motions,
        gravity=np.asarray(gravity, float),
        external_force=np.asarray(external_force, float),
        friction=friction,
        obstacles=list(obstacles or []),
    )
    _add_point_constraints(model, surfaces, source)
    return model


def _add_point_constraints(model: ClothModel, surfaces: list[SurfaceSpec], source: str) -> None:
    """Targets and attachments of ``surfaces`` into ``model`` (in place; rebuilds its derived
    arrays)."""
    starts = {layout.name: layout.start for layout in model.surfaces}
    meshes = {mesh.name: mesh for mesh in model.obstacles}
    targets, positions, radius, links = [], [], [], []
    for spec, layout in zip(surfaces, model.surfaces):
        for target in spec.targets:
            targets.append(layout.start + target.i * spec.cols + target.j)
            positions.append(target.position)
            radius.append(0.1 * spec.spacing)
        for attached in spec.attachments:
            point = layout.start + attached.i * spec.cols + attached.j
            other = next((s for s in surfaces if s.name == attached.body), None)
            if attached.point is not None and other is not None:
                k, l_ = attached.point
                if not (0 <= k < other.rows and 0 <= l_ < other.cols):
                    raise UserInputError(
                        f"point ({k} {l_}) is outside surface '{other.name}' "
                        f"({other.rows}x{other.cols}).",
                        file=source,
                        field=f"line {attached.line}: {attached.body}",
                    )
                links.append((point, starts[other.name] + k * other.cols + l_))
            elif attached.point is None and attached.body in meshes:
                mesh = meshes[attached.body]
                model.rest_positions[point] = contact.closest_surface_point(
                    model.rest_positions[point], mesh.vertices[mesh.triangles]
                )
                model.fixed[point] = True
            else:
                kind = "surface" if attached.point is not None else "obstacle"
                names = sorted(starts) if attached.point is not None else sorted(meshes)
                raise UserInputError(
                    f"there is no {kind} named '{attached.body}' to attach to.",
                    file=source,
                    field=f"line {attached.line}: {attached.body}",
                    fix=f"use one of: {', '.join(names) or '(none in this scene)'}.",
                )
    model.targets = np.array(targets, np.int64)
    model.target_positions = np.array(positions, float).reshape(-1, 3)
    model.target_radius = np.array(radius, float)
    model.links = np.array(links, np.int64).reshape(-1, 2)
    model.__post_init__()


def script_model(
    script: Script, obstacles: list[Mesh] | None = None, *, gravity: bool = True
) -> ClothModel:
    """The model a ``.PAR`` script describes; ``gravity=False`` drops gravity whatever GRAVIDADE
    says."""
    g = np.array([0.0, 0.0, -script.gravity]) if gravity else np.zeros(3)
    return surface_model(
        script.surfaces,
        frames_per_second=script.frames_per_second,
        gravity=g,
        external_force=script.external_force,
        friction=script.friction,
        obstacles=obstacles,
        source=script.path,
    )
