"""Headless rendering of surface frames to PNG and MP4 with matplotlib (Agg) — no display needed.

Cloth quads and obstacle polygons are flat-shaded by a fixed directional light (two-sided); the camera and the
axis limits stay fixed over a run (bounds of all frames), so motion reads correctly.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Sequence

import matplotlib

matplotlib.use("Agg")
import imageio.v2 as imageio  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from eigengait.cloth.model import ClothModel  # noqa: E402

LIGHT = np.array([0.4, -0.6, 0.7]) / np.linalg.norm([0.4, -0.6, 0.7])
SURFACE_COLOURS = [(0.75, 0.12, 0.15), (0.15, 0.35, 0.75), (0.9, 0.75, 0.2), (0.2, 0.6, 0.3)]
#: (elevation, azimuth) in degrees per example; vertical surfaces are seen from their front (-y).
CAMERAS = {"curtain": (12, -75), "theatre": (12, -80), "paper": (15, -55), "cardboard": (15, -55),
           "wind": (20, -35), "tablecloth": (28, -55)}


def shade(polygons: np.ndarray, colour) -> np.ndarray:
    """RGBA per polygon (P, k, 3): ambient + two-sided Lambert from :data:`LIGHT`."""
    normal = np.cross(polygons[:, 2] - polygons[:, 0], polygons[:, -1] - polygons[:, 1])
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-12)[:, None]
    intensity = 0.35 + 0.65 * np.abs(normal @ LIGHT)
    rgb = np.clip(np.asarray(colour)[None, :] * intensity[:, None], 0, 1)
    return np.c_[rgb, np.ones(len(rgb))]


def subdivide(triangle: np.ndarray, size: float) -> np.ndarray:
    """Split a triangle (3, 3) into k² similar triangles (k², 3, 3) with edges of about ``size``."""
    k = max(1, int(np.ceil(np.linalg.norm(triangle - np.roll(triangle, 1, axis=0), axis=1).max() / size)))
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


class FrameRenderer:
    """Draws frames of one model with a fixed camera; ``bounds`` (2, 3) m fixes the view box."""

    def __init__(self, model: ClothModel, bounds: np.ndarray, camera=(20, -60), size=(800, 600), title=""):
        self.model = model
        self.fig = plt.figure(figsize=(size[0] / 100, size[1] / 100), dpi=100)
        self.ax = self.fig.add_subplot(projection="3d")
        lo, hi = bounds
        centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo).max() * 1.05
        span = np.maximum(hi - lo, 0.2 * (hi - lo).max()) * 1.1
        for setter, c, s in zip((self.ax.set_xlim, self.ax.set_ylim, self.ax.set_zlim), centre, span):
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
            # Cut into cloth-sized pieces and pushed away from the camera along the view direction (invisible in
            # the orthographic view) so matplotlib's painter's sort puts touching cloth in front of the obstacle.
            vertices = mesh.vertices - 0.75 * piece * view
            materials = mesh.face_material or [0] * len(mesh.faces)
            for triangle, m in zip(mesh.triangles, _triangle_materials(mesh.faces, materials)):
                pieces = subdivide(vertices[triangle], piece)
                self.static_polygons += list(pieces)
                static_colours.append(shade(pieces, mesh.materials.get(m, (0.6, 0.45, 0.3))[:3]))
        self.static_colours = np.concatenate(static_colours) if static_colours else np.zeros((0, 4))
        self.fig.subplots_adjust(0, 0, 1, 1)

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
            quads = positions[layout.quads]
            polygons += list(quads)
            colours.append(shade(quads, colour))
        # One collection, so that cloth and obstacle polygons are depth-sorted together; edges drawn in the face
        # colour close the anti-aliasing seams that otherwise show the background between neighbouring quads.
        faces = np.concatenate(colours)
        collection = Poly3DCollection(polygons, facecolors=faces, edgecolors=faces, linewidths=0.3)
        self.ax.add_collection3d(collection)
        self.dynamic.append(collection)
        self.dynamic.append(self.ax.text2D(0.02, 0.95, f"{self.title}  t = {time:6.2f} s",
                                           transform=self.ax.transAxes, fontsize=11))
        buffer = io.BytesIO()
        self.fig.savefig(buffer, format="png")
        buffer.seek(0)
        return imageio.imread(buffer)[..., :3]

    def close(self) -> None:
        plt.close(self.fig)


def frame_bounds(model: ClothModel, frames: Sequence[np.ndarray]) -> np.ndarray:
    """(2, 3) box around every frame's points and the obstacles."""
    points = [f for f in frames] + [m.vertices for m in model.obstacles]
    stacked = np.concatenate(points)
    return np.stack([stacked.min(axis=0), stacked.max(axis=0)])


def render_run(model: ClothModel, frames: Sequence[tuple[float, np.ndarray]], png_dir: Path | None,
               video: Path | None, *, camera=(20, -60), title: str = "", fps: float = 10.0,
               on_frame=None) -> None:
    """Render ``frames`` [(time s, positions)] to ``png_dir/frame_XXXX.png`` and/or an MP4 ``video``."""
    renderer = FrameRenderer(model, frame_bounds(model, [p for _, p in frames]), camera=camera, title=title)
    writer = imageio.get_writer(video, fps=fps, codec="libx264", quality=7, macro_block_size=8) if video else None
    try:
        for index, (time, positions) in enumerate(frames):
            image = renderer.draw(positions, time)
            if png_dir is not None:
                imageio.imwrite(png_dir / f"frame_{index:04d}.png", image)
            if writer is not None:
                writer.append_data(image)
            if on_frame is not None:
                on_frame()
    finally:
        renderer.close()
        if writer is not None:
            writer.close()
