"""Vibration modes of a surface about an equilibrium: ``K φ = ω² M φ`` on the free points.

K is the exact (unclamped) spring-network stiffness of :mod:`eigengait.cloth.stiffness`, including
the tension (geometric) term that makes a taut surface stiff out of its plane — so the surface must
be under tension: pinned and pre-stretched (:func:`membrane`, :func:`string`) or hanging in
equilibrium under load (:func:`equilibrium`). Modes are sorted by frequency; zero (rigid or
mechanism) modes are dropped and counted; shapes are mass-normalized (φᵀMφ = 1); numbering shown to
users starts at 1.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from eigengait.cloth.model import ClothModel, surface_model
from eigengait.cloth.par import SurfaceSpec
from eigengait.cloth.stiffness import StiffnessAssembler
from eigengait.errors import UserInputError

DENSE_LIMIT = 3000


@dataclass
class SurfaceModes:
    """``frequencies`` (K,) Hz, ``shapes`` (K, N, 3) mass-normalized (zero at fixed points), about
    ``positions``."""

    frequencies: np.ndarray
    shapes: np.ndarray
    positions: np.ndarray
    zero_modes: int


def string(
    points: int,
    *,
    spacing: float = 1.0,
    mass: float = 0.01,
    stiffness: float = 100.0,
    stretch: float = 1.1,
) -> ClothModel:
    """A 1×``points`` chain along x, ends pinned, every spring stretched by ``stretch`` (tension k r
    (s-1) N)."""
    spec = SurfaceSpec(
        "string",
        1,
        points,
        spacing,
        np.zeros(3),
        np.array([0.0, -1.0, 0.0]),
        mass,
        (stiffness,) * 3,
        (0.0,) * 3,
        fixed=[(0, 0), (0, points - 1)],
    )
    return surface_model([spec], stretch=stretch)


def membrane(
    rows: int,
    cols: int,
    *,
    spacing: float = 1.0,
    mass: float = 0.01,
    stiffness: float = 100.0,
    stretch: float = 1.05,
) -> ClothModel:
    """A horizontal rows×cols grid, boundary pinned, uniformly pre-stretched by ``stretch``."""
    fixed = [
        (i, j) for i in range(rows) for j in range(cols) if i in (0, rows - 1) or j in (0, cols - 1)
    ]
    spec = SurfaceSpec(
        "membrane",
        rows,
        cols,
        spacing,
        np.zeros(3),
        np.array([0.0, 0.0, 1.0]),
        mass,
        (stiffness,) * 3,
        (0.0,) * 3,
        fixed=fixed,
    )
    return surface_model([spec], stretch=stretch)


def equilibrium(model: ClothModel, *, iterations: int = 400, tolerance: float = 1e-7) -> np.ndarray:
    """Static equilibrium positions (N, 3) under the model's loads, by damped Newton (pseudo-time)
    steps.

    Raises:
        UserInputError: when no equilibrium is reached (e.g. a surface with no fixed point falls
            forever).
    """
    if not model.fixed.any():
        raise UserInputError(
            "a surface with no fixed point has no equilibrium to vibrate about.",
            field="PONTOS_FIXOS",
            fix="fix some points, or use a size like 20x20.",
        )
    assembler = StiffnessAssembler(model)
    x = model.rest_positions.copy()
    free = np.repeat(model.free, 3)
    scale = max(float(np.abs(model.applied_forces(x)).max()), float(model.spring_k.max()) * 1e-3)
    tau2 = 0.25
    for _ in range(iterations):
        force = model.applied_forces(x).ravel()[free]
        if np.abs(force).max() < tolerance * scale:
            return x
        K = assembler.matrix(x, clamp=True)[free][:, free]
        A = sp.diags(np.repeat(model.mass[model.free], 3) / tau2) - K
        x[model.free] += spla.spsolve(A.tocsc(), force).reshape(-1, 3)
        tau2 = min(tau2 * 1.5, 1e6)
    raise UserInputError(
        "the surface did not settle to an equilibrium for the modal analysis.",
        fix="check that the fixed points can carry the load.",
    )


def vibration_modes(
    model: ClothModel, positions: np.ndarray | None = None, count: int = 12
) -> SurfaceModes:
    """The ``count`` lowest non-zero modes of ``model`` linearized about ``positions`` (default:
    rest)."""
    x = model.rest_positions if positions is None else positions
    free = np.repeat(model.free, 3)
    K = -StiffnessAssembler(model).matrix(x, clamp=False)[free][:, free]
    K = 0.5 * (K + K.T)
    m = np.repeat(model.mass[model.free], 3)
    n = K.shape[0]
    if n <= DENSE_LIMIT:
        w2, vec = scipy.linalg.eigh(K.toarray(), np.diag(m))
    else:
        scale = float(K.diagonal().max() / m.max())
        k = min(count + 12, n - 2)
        w2, vec = spla.eigsh(K.tocsc(), k=k, M=sp.diags(m).tocsc(), sigma=-1e-6 * scale, which="LM")
        order = np.argsort(w2)
        w2, vec = w2[order], vec[:, order]
    threshold = 1e-8 * max(float(np.abs(w2).max()), 1e-300)
    nonzero = w2 > threshold
    zero_modes = int((~nonzero).sum())
    w2, vec = w2[nonzero][:count], vec[:, nonzero][:, :count]
    vec = vec / np.sqrt((m[:, None] * vec**2).sum(axis=0))
    shapes = np.zeros((len(w2), model.size * 3))
    shapes[:, free] = vec.T
    return SurfaceModes(
        np.sqrt(w2) / (2 * np.pi), shapes.reshape(len(w2), model.size, 3), x.copy(), zero_modes
    )


def out_of_plane_fraction(modes: SurfaceModes, normal=(0.0, 0.0, 1.0)) -> np.ndarray:
    """(K,) share of each mode's squared amplitude along ``normal`` (1 = purely transverse)."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    along = ((modes.shapes @ n) ** 2).sum(axis=1)
    return along / np.maximum((modes.shapes**2).sum(axis=(1, 2)), 1e-300)


def draw_palette(
    model: ClothModel, modes: SurfaceModes, path: str | Path, *, columns: int | None = None
) -> None:
    """Save a PNG with one tile per mode: the displaced surface, its number and frequency (Hz)."""
    import matplotlib
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from eigengait.figures import agg_figure

    from eigengait.cloth.render import shade

    count = len(modes.frequencies)
    if count == 0:
        raise UserInputError(
            "there is no non-zero mode to draw.", fix="pin or pre-stretch the surface."
        )
    columns = columns or int(np.ceil(np.sqrt(count)))
    rows = int(np.ceil(count / columns))
    fig = agg_figure(3.2 * columns, 3.0 * rows)
    x = modes.positions
    size = float(np.ptp(x, axis=0).max())
    lo, hi = x.min(axis=0) - 0.3 * size, x.max(axis=0) + 0.3 * size
    for k in range(count):
        ax = fig.add_subplot(rows, columns, k + 1, projection="3d")
        shape = modes.shapes[k]
        shown = x + 0.25 * size * shape / max(float(np.abs(shape).max()), 1e-300)
        for layout in model.surfaces:
            if layout.rows == 1 or layout.cols == 1:
                ax.plot(*shown[layout.indices].T, color="tab:red", lw=2, marker="o", ms=2)
                ax.plot(*x[layout.indices].T, color="0.7", lw=1)
                continue
            quads = shown[layout.quads]
            amplitude = np.linalg.norm(shape[layout.quads], axis=2).mean(axis=1)
            base = matplotlib.colormaps["viridis"](amplitude / max(float(amplitude.max()), 1e-300))[
                :, :3
            ]
            colours = shade(quads, (1.0, 1.0, 1.0))
            colours[:, :3] *= base
            ax.add_collection3d(
                Poly3DCollection(
                    quads, facecolors=colours, edgecolors=(0, 0, 0, 0.1), linewidths=0.2
                )
            )
        ax.set_xlim(lo[0], hi[0]), ax.set_ylim(lo[1], hi[1]), ax.set_zlim(lo[2], hi[2])
        ax.set_box_aspect(np.maximum(hi - lo, 1e-3 * size), zoom=1.5)
        ax.view_init(25, -60)
        ax.set_axis_off()
        ax.set_title(f"mode {k + 1}   {modes.frequencies[k]:.4g} Hz", fontsize=10)
    fig.suptitle(f"vibration modes ({modes.zero_modes} zero modes dropped)", fontsize=11)
    fig.tight_layout()
    fig.savefig(path)
