"""Headless rendering of surface frames to PNG and MP4 with matplotlib (Agg) — no display needed.

A fixed directional light (two-sided Lambert) shades everything: obstacle polygons and the floor's
checkered tiles flat, the cloth smoothly — each grid cell is cut into ``SMOOTH``² pieces shaded with
the normal interpolated from the per-vertex normals (Phong-style). The camera and the axis limits
stay fixed over a run (bounds of all frames), so motion reads correctly. Positions are world m, z
up.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Mapping, Sequence

import imageio.v2 as imageio
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
from PIL import Image

from eigengait.cloth.model import ClothModel
from eigengait.figures import agg_figure

LIGHT = np.array([0.4, -0.6, 0.7]) / np.linalg.norm([0.4, -0.6, 0.7])
SURFACE_COLOURS = [(0.75, 0.12, 0.15), (0.15, 0.35, 0.75), (0.9, 0.75, 0.2), (0.2, 0.6, 0.3)]
#: (elevation, azimuth) in degrees per example; vertical surfaces are seen from their front (-y).
CAMERAS = {
    "curtain": (12, -75),
    "theatre": (12, -80),
    "paper": (15, -55),
    "cardboard": (15, -55),
    "wind": (20, -35),
    "tablecloth": (24, -55),
}
#: pieces per grid-cell side in smooth shading; the floor's tile colours; contact-sheet tiles
#: (columns, rows, px).
SMOOTH = 3
FLOOR_COLOURS = ((0.82, 0.82, 0.8), (0.7, 0.7, 0.68))
SHEET = (4, 3, (320, 240))


def lambert(normals: np.ndarray, colour) -> np.ndarray:
    """RGBA (P, 4) for unit or unnormalized ``normals`` (P, 3): ambient + two-sided Lambert from
    :data:`LIGHT`."""
    normals = normals / np.maximum(np.linalg.norm(normals, axis=1), 1e-12)[:, None]
    intensity = 0.35 + 0.65 * np.abs(normals @ LIGHT)
    rgb = np.clip(np.asarray(colour)[None, :] * intensity[:, None], 0, 1)
    return np.c_[rgb, np.ones(len(rgb))]


def shade(polygons: np.ndarray, colour) -> np.ndarray:
    """RGBA per flat polygon (P, k, 3), lit by its own normal."""
    return lambert(
        np.cross(polygons[:, 2] - polygons[:, 0], polygons[:, -1] - polygons[:, 1]), colour
    )


def vertex_normals(positions: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Unit normal (N, 3) at every point: the area-weighted sum of its triangles' normals
    (zero if it has none)."""
    a, b, c = (positions[triangles[:, k]] for k in range(3))
    weighted = np.cross(b - a, c - a)  # length = 2 × area
    normals = np.zeros_like(positions)
    for k in range(3):
        np.add.at(normals, triangles[:, k], weighted)
    return normals / np.maximum(np.linalg.norm(normals, axis=1), 1e-12)[:, None]


def _bilinear(corners: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Points (Q, S, 3) at parameters (S,) of quads (Q, 4, 3) with corners ordered (0,0), (1,0),
    (1,1), (0,1)."""
    w = np.stack([(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v], axis=1)
    return np.einsum("sk,qkd->qsd", w, corners)


def smooth_quads(
    positions: np.ndarray, normals: np.ndarray, quads: np.ndarray, colour, pieces: int = SMOOTH
) -> tuple[np.ndarray, np.ndarray]:
    """Cut each grid cell into ``pieces``² quads; returns them (Q·pieces², 4, 3) and RGBA shaded at
    their centres with the bilinearly interpolated vertex normal."""
    i, j = np.meshgrid(np.arange(pieces), np.arange(pieces), indexing="ij")
    u, v = i.ravel() / pieces, j.ravel() / pieces
    step = 1.0 / pieces
    corners = positions[quads]
    sub = np.stack(
        [
            _bilinear(corners, u + du, v + dv)
            for du, dv in ((0, 0), (step, 0), (step, step), (0, step))
        ],
        axis=2,
    )
    centre_normals = _bilinear(normals[quads], u + step / 2, v + step / 2)
    return sub.reshape(-1, 4, 3), lambert(centre_normals.reshape(-1, 3), colour)


def floor_tiles(bounds: np.ndarray, level: float, size: float) -> tuple[np.ndarray, np.ndarray]:
    """Square tiles (T, 4, 3) of side about ``size`` m at height ``level`` m covering the x–y extent
    of ``bounds``, and their checkerboard parity (T,)."""
    lo, hi = bounds[0, :2], bounds[1, :2]
    counts = np.maximum(1, np.ceil((hi - lo) / size)).astype(int)
    xs, ys = (np.linspace(lo[k], hi[k], counts[k] + 1) for k in range(2))
    i, j = (
        a.ravel() for a in np.meshgrid(np.arange(counts[0]), np.arange(counts[1]), indexing="ij")
    )
    tiles = [
        np.stack([xs[i + a], ys[j + b], np.full(len(i), level)], axis=1)
        for a, b in ((0, 0), (1, 0), (1, 1), (0, 1))
    ]
    return np.stack(tiles, axis=1), (i + j) % 2


def subdivide(triangle: np.ndarray, size: float) -> np.ndarray:
    """Split a triangle (3, 3) into k² similar triangles (k², 3, 3) with edges of about ``size``."""
    k = max(
        1,
        int(np.ceil(np.linalg.norm(triangle - np.roll(triangle, 1, axis=0), axis=1).max() / size)),
    )
    a, b, c = triangle
    out = []
    for i in range(k):
        for j in range(k - i):
            p = lambda u, v: a + (b - a) * u / k + (c - a) * v / k  # noqa: E731
            out.append([p(i, j), p(i + 1, j), p(i, j + 1)])
            if j < k - i - 1:
                out.append([p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)])
    return np.array(out)


def _triangle_materials(faces, materials) -> list[int]:
    return [m for f, m in zip(faces, materials) for _ in range(len(f) - 2)]


class ClothFrameRenderer:
    """Draws frames of one model with a fixed camera; ``bounds`` (2, 3) m fixes the view box (see
    :func:`frame_bounds`); ``floor`` (m, world z) draws a checkered floor plane over the box's x–y
    extent."""

    def __init__(
        self,
        model: ClothModel,
        bounds: np.ndarray,
        camera=(20, -60),
        size=(800, 600),
        title="",
        floor: float | None = None,
    ):
        self.model = model
        self.fig = agg_figure(size[0] / 100, size[1] / 100)
        self.ax = self.fig.add_subplot(projection="3d")
        lo, hi = bounds
        centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo).max() * 1.05
        span = np.maximum(hi - lo, 0.2 * (hi - lo).max()) * 1.1
        for setter, c, s in zip(
            (self.ax.set_xlim, self.ax.set_ylim, self.ax.set_zlim), centre, span
        ):
            setter(c - s / 2, c + s / 2)
        self.ax.set_box_aspect(span / half, zoom=1.25)
        self.ax.view_init(*camera)
        self.ax.set_proj_type("ortho")
        elev, azim = np.radians(camera)
        view = np.array([np.cos(elev) * np.cos(azim), np.cos(elev) * np.sin(azim), np.sin(elev)])
        self.ax.set_axis_off()
        self.title = title
        self.dynamic: list = []
        self.static_polygons: list[np.ndarray] = []
        static_colours = []
        piece = 0.8 * float(model.spring_rest.min()) if len(model.spring_rest) else 1.0
        for mesh in model.obstacles:
            # Cut into cloth-sized pieces and pushed away from the camera along the view direction
            # (invisible in the orthographic view) so matplotlib's painter's sort puts touching
            # cloth in front of the obstacle.
            vertices = mesh.vertices - 0.75 * piece * view
            materials = mesh.face_material or [0] * len(mesh.faces)
            for triangle, m in zip(mesh.triangles, _triangle_materials(mesh.faces, materials)):
                pieces = subdivide(vertices[triangle], piece)
                self.static_polygons += list(pieces)
                static_colours.append(shade(pieces, mesh.materials.get(m, (0.6, 0.45, 0.3))[:3]))
        if floor is not None:
            self._add_floor(bounds, floor, 2.5 * piece)
        self.static_colours = np.concatenate(static_colours) if static_colours else np.zeros((0, 4))
        self.fig.subplots_adjust(0, 0, 1, 1)

    def _add_floor(self, bounds: np.ndarray, level: float, tile: float) -> None:
        """Checkered floor at ``level`` m, drawn before everything else (the camera looks down on
        it)."""
        tiles, parity = floor_tiles(bounds, level, tile)
        colours = np.array(FLOOR_COLOURS)[parity]
        self.ax.computed_zorder = False
        self.ax.add_collection3d(
            Poly3DCollection(
                tiles, facecolors=colours, edgecolors=colours, linewidths=0.3, zorder=0
            )
        )

    def draw(self, positions: np.ndarray, time: float) -> np.ndarray:
        """RGB image (H, W, 3) of the surfaces at ``positions`` (N, 3)."""
        for artist in self.dynamic:
            artist.remove()
        self.dynamic = []
        polygons, colours = list(self.static_polygons), [self.static_colours]
        for k, layout in enumerate(self.model.surfaces):
            colour = SURFACE_COLOURS[k % len(SURFACE_COLOURS)]
            if layout.rows == 1 or layout.cols == 1:
                line = positions[layout.indices]
                self.dynamic += self.ax.plot(*line.T, color=colour, lw=2, marker="o", ms=2)
                continue
            quads, rgba = smooth_quads(
                positions, vertex_normals(positions, layout.triangles), layout.quads, colour
            )
            polygons += list(quads)
            colours.append(rgba)
        # One collection, so that cloth and obstacle polygons are depth-sorted together; edges drawn
        # in the face colour close the anti-aliasing seams that otherwise show the background
        # between neighbouring quads.
        faces = np.concatenate(colours)
        collection = Poly3DCollection(
            polygons, facecolors=faces, edgecolors=faces, linewidths=0.3, zorder=1
        )
        self.ax.add_collection3d(collection)
        self.dynamic.append(collection)
        self.dynamic.append(
            self.ax.text2D(
                0.02,
                0.95,
                f"{self.title}  t = {time:6.2f} s",
                transform=self.ax.transAxes,
                fontsize=11,
            )
        )
        buffer = io.BytesIO()
        self.fig.savefig(buffer, format="png")
        buffer.seek(0)
        return imageio.imread(buffer)[..., :3]

    def close(self) -> None:
        self.fig.clear()


def frame_bounds(
    model: ClothModel, frames: Sequence[np.ndarray], floor: float | None = None
) -> np.ndarray:
    """(2, 3) box around every frame's points and the obstacles; with a ``floor`` (m), widened in x
    and y by a fifth of its largest side and reaching down to the floor."""
    stacked = np.concatenate(list(frames) + [m.vertices for m in model.obstacles])
    lo, hi = stacked.min(axis=0), stacked.max(axis=0)
    if floor is not None:
        margin = 0.2 * (hi - lo).max()
        lo, hi = (
            np.r_[lo[:2] - margin, min(lo[2], floor)],
            np.r_[hi[:2] + margin, max(hi[2], floor)],
        )
    return np.stack([lo, hi])


def contact_sheet(
    images: Sequence[np.ndarray], columns: int = SHEET[0], tile=SHEET[2]
) -> np.ndarray:
    """RGB image tiling ``images`` (H, W, 3) row by row, each scaled to ``tile`` (width, height)
    px."""
    rows = -(-len(images) // columns)
    sheet = np.full((rows * tile[1], columns * tile[0], 3), 255, np.uint8)
    for k, image in enumerate(images):
        small = np.asarray(Image.fromarray(image).resize(tile, Image.LANCZOS))
        r, c = divmod(k, columns)
        sheet[r * tile[1] : (r + 1) * tile[1], c * tile[0] : (c + 1) * tile[0]] = small
    return sheet


def sheet_picks(count: int, tiles: int = SHEET[0] * SHEET[1]) -> np.ndarray:
    """Indices of ``tiles`` video frames evenly spread over ``count`` (first and last included)."""
    return np.unique(np.linspace(0, count - 1, min(tiles, count)).round().astype(int))


def render_run(
    model: ClothModel,
    states: Mapping[int, tuple[float, np.ndarray]],
    png_steps: Sequence[int],
    video_steps: Sequence[int],
    png_dir: Path | None,
    video: Path | None,
    *,
    fps: float,
    camera=(20, -60),
    title: str = "",
    floor: float | None = None,
    sheet: Path | None = None,
    on_frame=None,
) -> None:
    """Render the states {step: (time s, positions (N, 3) m)} once each, in step order.

    The state at ``png_steps[k]`` becomes ``png_dir/frame_{k:04d}.png``; the video at ``fps`` frames
    per second shows the state at ``video_steps[j]`` as its frame j (non-decreasing steps; a
    repeated step holds the frame); ``sheet`` gets a contact sheet of :data:`SHEET` video frames
    spread evenly over the run.
    """
    bounds = frame_bounds(model, [p for _, p in states.values()], floor)
    renderer = ClothFrameRenderer(model, bounds, camera=camera, title=title, floor=floor)
    png_index = {step: k for k, step in enumerate(png_steps)}
    video_steps = list(video_steps)
    picks = set(sheet_picks(len(video_steps)).tolist()) if sheet is not None else set()
    tiles, j = [], 0
    writer = (
        imageio.get_writer(video, fps=fps, codec="libx264", quality=7, macro_block_size=8)
        if video
        else None
    )
    try:
        for step in sorted(set(png_index) | set(video_steps)):
            image = renderer.draw(states[step][1], states[step][0])
            if png_dir is not None and step in png_index:
                imageio.imwrite(png_dir / f"frame_{png_index[step]:04d}.png", image)
            while j < len(video_steps) and video_steps[j] == step:
                if writer is not None:
                    writer.append_data(image)
                if j in picks:
                    tiles.append(image)
                j += 1
            if on_frame is not None:
                on_frame()
    finally:
        renderer.close()
        if writer is not None:
            writer.close()
    if sheet is not None:
        imageio.imwrite(sheet, contact_sheet(tiles))
