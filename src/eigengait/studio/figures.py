"""A character drawn as boxes: one box per geom (its local bounding box, exact for box geoms), posed
by qpos.

Poses come out as arrays ready for one viser batched mesh: positions (m) and wxyz quaternions per
geom, and can be moved into a display cell (translated, scaled, turned about z) so many copies share
one scene node.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from scipy.spatial.transform import Rotation

from eigengait.render.video import creature_geoms
from eigengait.sim.world import World

UNIT_CUBE_VERTICES = np.array(
    [[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)], np.float32
)


def _outward_cube_faces() -> np.ndarray:
    """Two triangles per cube side, wound counter-clockwise seen from outside."""
    faces = []
    for axis in range(3):
        for side in (-0.5, 0.5):
            quad = [i for i, v in enumerate(UNIT_CUBE_VERTICES) if v[axis] == side]
            for tri in ([quad[0], quad[1], quad[2]], [quad[1], quad[3], quad[2]]):
                a, b, c = UNIT_CUBE_VERTICES[tri]
                faces.append(tri if np.dot(np.cross(b - a, c - a), a + b + c) > 0 else tri[::-1])
    return np.array(faces, np.uint32)


UNIT_CUBE_FACES = _outward_cube_faces()


@dataclass(frozen=True)
class Figure:
    """The boxes of a creature: geom ids, full box sizes (G×3, m), box centres in geom frames, geom
    colours."""

    model: mujoco.MjModel
    geoms: np.ndarray
    sizes: np.ndarray
    centres: np.ndarray
    colors: np.ndarray  # G×3 uint8

    @classmethod
    def of(cls, world: World) -> "Figure":
        model = world.model
        geoms = creature_geoms(model, world.root_body)
        aabb = model.geom_aabb[geoms]
        colors = (np.clip(model.geom_rgba[geoms, :3], 0, 1) * 255).astype(np.uint8)
        return cls(
            model=model, geoms=geoms, sizes=2 * aabb[:, 3:], centres=aabb[:, :3], colors=colors
        )

    @property
    def count(self) -> int:
        return len(self.geoms)

    def poses(self, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Box positions (T×G×3) and wxyz quaternions (T×G×4) for qpos frames (T×nq)."""
        qpos = np.atleast_2d(qpos)
        data = mujoco.MjData(self.model)
        positions = np.empty((len(qpos), self.count, 3))
        matrices = np.empty((len(qpos), self.count, 3, 3))
        for t, q in enumerate(qpos):
            data.qpos[:] = q
            mujoco.mj_kinematics(self.model, data)
            matrices[t] = data.geom_xmat[self.geoms].reshape(-1, 3, 3)
            positions[t] = data.geom_xpos[self.geoms] + np.einsum(
                "gij,gj->gi", matrices[t], self.centres
            )
        xyzw = Rotation.from_matrix(matrices.reshape(-1, 3, 3)).as_quat()
        return positions, np.roll(xyzw, 1, axis=-1).reshape(len(qpos), self.count, 4)

    def extent(self, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(lowest corner, highest corner) of the boxes over all frames (m)."""
        positions, wxyz = self.poses(qpos)
        rot = Rotation.from_quat(np.roll(wxyz.reshape(-1, 4), -1, axis=-1)).as_matrix()
        half = np.abs(rot) @ (np.tile(self.sizes, (len(positions), 1))[..., None] / 2)
        centres = positions.reshape(-1, 3)
        return (centres - half[..., 0]).min(axis=0), (centres + half[..., 0]).max(axis=0)


def place(
    positions: np.ndarray,
    wxyz: np.ndarray,
    anchor: np.ndarray,
    cell: np.ndarray,
    scale: float,
    yaw_deg: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Move posed boxes so `anchor` lands on `cell`, scaled by `scale` and turned by `yaw_deg` about
    z."""
    yaw = Rotation.from_euler("z", yaw_deg, degrees=True)
    moved = cell + scale * yaw.apply((positions - anchor).reshape(-1, 3)).reshape(positions.shape)
    turned = (yaw * Rotation.from_quat(np.roll(wxyz.reshape(-1, 4), -1, axis=-1))).as_quat()
    return moved, np.roll(turned, 1, axis=-1).reshape(wxyz.shape)
