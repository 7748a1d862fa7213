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
        self.ax.set_box_aspect(span / half)
        self.ax.view_init(*camera)
        self.ax.set_axis_off()
        self.title = title
        self.dynamic: list = []
        for mesh in model.obstacles:
            polys = [mesh.vertices[f] for f in mesh.faces]
            colours = []
            for poly, m in zip(polys, mesh.face_material or [0] * len(polys)):
                colours.append(shade(poly[None], mesh.materials.get(m, (0.6, 0.45, 0.3))[:3])[0])
            self.ax.add_collection3d(Poly3DCollection(polys, facecolors=colours, edgecolors=(0, 0, 0, 0.3),
                                                      linewidths=0.3))

    def draw(self, positions: np.ndarray, time: float) -> np.ndarray:
        """RGB image (H, W, 3) of the surfaces at ``positions`` (N, 3)."""
        for artist in self.dynamic:
            artist.remove()
        self.dynamic = []
        for k, layout in enumerate(self.model.surfaces):
            colour = SURFACE_COLOURS[k % len(SURFACE_COLOURS)]
            if layout.rows == 1 or layout.cols == 1:
                line = positions[layout.indices]
                self.dynamic += self.ax.plot(*line.T, color=colour, lw=2, marker="o", ms=2)
                continue
            quads = positions[layout.quads]
            collection = Poly3DCollection(quads, facecolors=shade(quads, colour),
                                          edgecolors=(0, 0, 0, 0.15), linewidths=0.2)
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
