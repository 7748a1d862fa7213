"""The stage: one full-size character in front of the palette, playing a motion at real time.

It shows either the live sketch (gravity off) or a controller played on the ground with gravity. When a motion
is shown with `follow=True`, every tab's camera is carried along with the character's root (the animator can
still orbit). Frames are precomputed box poses; `tick` picks the one for the wall-clock time.
"""

from __future__ import annotations

import threading
import time

import numpy as np
import viser

from eigengait.sim.world import World
from eigengait.studio.figures import UNIT_CUBE_FACES, UNIT_CUBE_VERTICES, Figure


class Stage:
    def __init__(self, server: viser.ViserServer):
        self.server = server
        self.lock = threading.Lock()
        self.mesh: viser.BatchedMeshHandle | None = None
        self.showing = ""                  # "sketch" or "playback"
        self.positions = self.wxyzs = self.roots = None
        self.fps = 30.0
        self.started = 0.0
        self.follow = False
        self.last_root: np.ndarray | None = None
        self.shown = 0                     # how many motions have been shown (tests and latency read it)
        self.floor = server.scene.add_grid("/stage/floor", 40.0, 40.0, cell_size=0.5, section_size=2.0,
                                           position=(0.0, 0.0, 0.0), infinite_grid=True, fade_distance=40.0)

    def show(self, name: str, world: World, qpos: np.ndarray, fps: float, follow: bool = False) -> None:
        """Play `qpos` (frames × nq at `fps`) in a loop from now on."""
        figure = Figure.of(world)
        positions, wxyzs = figure.poses(qpos)
        roots = qpos[:, :3].copy()
        with self.lock:
            if self.mesh is None or len(self.mesh.batched_positions) != figure.count or self.showing != name:
                if self.mesh is not None:
                    self.mesh.remove()
                self.mesh = self.server.scene.add_batched_meshes_simple(
                    "/stage/character", UNIT_CUBE_VERTICES, UNIT_CUBE_FACES, batched_wxyzs=wxyzs[0],
                    batched_positions=positions[0], batched_scales=figure.sizes, batched_colors=figure.colors,
                    flat_shading=True, lod="off")
            self.showing, self.fps, self.follow = name, fps, follow
            self.positions, self.wxyzs, self.roots = positions, wxyzs, roots
            self.started = time.perf_counter()
            self.last_root = None
            self.shown += 1

    def frame_index(self, now: float) -> int:
        return int((now - self.started) * self.fps) % len(self.positions)

    def tick(self, now: float) -> None:
        with self.lock:
            if self.mesh is None:
                return
            k = self.frame_index(now)
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
