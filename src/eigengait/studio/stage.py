"""The stage: one full-size character in front of the palette, playing a motion at real time.

It shows either the live sketch (gravity off) or a controller played on the ground with gravity.
When a motion is shown with `follow=True`, every tab's camera is carried along with the character's
root (the animator can still orbit). Frames are precomputed box poses; `tick` picks the one for the
wall-clock time.
"""

from __future__ import annotations

import threading
import time

import numpy as np
import viser

from eigengait.sim.world import World
from eigengait.studio.figures import UNIT_CUBE_FACES, UNIT_CUBE_VERTICES, Figure

FLOOR_X = (-4.0, 40.0)  # m: the floor runs ahead of the stage, where played gaits go
FLOOR_HALF_WIDTH = 6.0  # m
FLOOR_LINE_SPACING = 1.0  # m


class Stage:
    def __init__(self, server: viser.ViserServer):
        self.server = server
        self.lock = threading.Lock()
        self.mesh: viser.BatchedMeshHandle | None = None
        self.showing = ""  # "sketch" or "playback"
        self.positions = self.wxyzs = self.roots = None
        self.fps = 30.0
        self.started = 0.0
        self.follow = False
        self.last_root: np.ndarray | None = None
        self.shown_frame = -1
        self.shown = 0  # how many motions have been shown (tests and latency read it)
        self.floor = add_floor(server)

    def show(
        self, name: str, world: World, qpos: np.ndarray, fps: float, follow: bool = False
    ) -> None:
        """Play `qpos` (frames × nq at `fps`) in a loop from now on."""
        figure = Figure.of(world)
        positions, wxyzs = figure.poses(qpos)
        roots = qpos[:, :3].copy()
        with self.lock:
            if (
                self.mesh is None
                or len(self.mesh.batched_positions) != figure.count
                or self.showing != name
            ):
                if self.mesh is not None:
                    self.mesh.remove()
                self.mesh = self.server.scene.add_batched_meshes_simple(
                    "/stage/character",
                    UNIT_CUBE_VERTICES,
                    UNIT_CUBE_FACES,
                    batched_wxyzs=wxyzs[0],
                    batched_positions=positions[0],
                    batched_scales=figure.sizes,
                    batched_colors=figure.colors,
                    flat_shading=True,
                    lod="off",
                    cast_shadow=False,
                    receive_shadow=False,
                )
            self.showing, self.fps, self.follow = name, fps, follow
            self.positions, self.wxyzs, self.roots = positions, wxyzs, roots
            self.started = time.perf_counter()
            self.last_root = None
            self.shown_frame = -1
            self.shown += 1

    def frame_index(self, now: float) -> int:
        return int((now - self.started) * self.fps) % len(self.positions)

    def tick(self, now: float) -> None:
        with self.lock:
            if self.mesh is None:
                return
            k = self.frame_index(now)
            if k == self.shown_frame:
                return
            self.shown_frame = k
            self.mesh.batched_positions = self.positions[k]
            self.mesh.batched_wxyzs = self.wxyzs[k]
            root = self.roots[k]
            if self.follow:
                if self.last_root is not None:
                    self._carry_cameras(root - self.last_root)
                self.last_root = root

    def _carry_cameras(self, delta: np.ndarray) -> None:
        delta = delta * [1.0, 1.0, 0.0]
        if not np.any(delta):
            return
        for client in self.server.get_clients().values():
            with client.atomic():
                client.camera.look_at = np.asarray(client.camera.look_at) + delta
                client.camera.position = np.asarray(client.camera.position) + delta


def add_floor(server: viser.ViserServer) -> viser.BatchedMeshHandle:
    """A light floor with a line every FLOOR_LINE_SPACING m (flat boxes: cheap to draw, unlike a
    shader grid)."""
    xs = np.arange(FLOOR_X[0], FLOOR_X[1] + 1e-9, FLOOR_LINE_SPACING)
    ys = np.arange(-FLOOR_HALF_WIDTH, FLOOR_HALF_WIDTH + 1e-9, FLOOR_LINE_SPACING)
    length, width = FLOOR_X[1] - FLOOR_X[0], 2 * FLOOR_HALF_WIDTH
    centre_x = (FLOOR_X[0] + FLOOR_X[1]) / 2
    positions = (
        [(centre_x, 0.0, -0.01)] + [(x, 0.0, 0.0) for x in xs] + [(centre_x, y, 0.0) for y in ys]
    )
    scales = (
        [(length, width, 0.02)]
        + [(0.015, width, 0.002)] * len(xs)
        + [(length, 0.015, 0.002)] * len(ys)
    )
    colors = [(236, 236, 232)] + [(185, 185, 185)] * (len(xs) + len(ys))
    return server.scene.add_batched_meshes_simple(
        "/stage/floor",
        UNIT_CUBE_VERTICES,
        UNIT_CUBE_FACES,
        batched_wxyzs=np.tile([1.0, 0, 0, 0], (len(positions), 1)),
        batched_positions=np.array(positions),
        batched_scales=np.array(scales),
        batched_colors=np.array(colors),
        lod="off",
        cast_shadow=False,
        receive_shadow=False,
    )
