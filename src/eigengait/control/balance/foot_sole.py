"""Give the tracked character's feet a sole: an area of support instead of a heel-toe line.

A world's feet touch the floor only through their contact spheres (`sim.world`: one at the toe, one
at the heel, on the foot's centre line). A stance foot can then carry no roll torque: standing on
one foot, the character's sideways balance rests on the artificial torque alone, and a walk or a
weight shift falls sideways (docs/balance.md). The walker's foot body carries a box (its visible
foot, 22 × 10 cm) whose bottom is 3 cm above the spheres' bottoms, so it touches the floor only when
the foot tips; on the tracker's private model copy that box is moved down onto the plane of the
spheres' bottoms and set to touch the floor as a foot, so a flat stance foot stands on its whole
rectangle, as the chapter's foot (a cylinder of radius r) does. Mass and inertia stay as compiled;
the spheres keep touching, so the reference's foot measures (`motion.soles`) still hold.

Only a box whose axes are the foot body's own (identity geom frame, up to a turn about z) is used:
its bottom face is then level when the foot is.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.sim.world import FOOT_GROUP


def _level_box(model: mujoco.MjModel, geom: int) -> bool:
    """A box whose local z axis is its body's z axis."""
    if model.geom_type[geom] != mujoco.mjtGeom.mjGEOM_BOX:
        return False
    w, x, y, _ = model.geom_quat[geom]
    return bool(np.hypot(x, y) < 1e-6 and abs(w) > 0)


def add_soles(model: mujoco.MjModel, foot_spheres: dict[str, list[int]]) -> list[int]:
    """Make each foot body's level boxes touch the floor, their bottoms on the plane of the foot's
    contact spheres' bottoms (body frame); returns the geoms changed. Modifies `model` (a private
    copy)."""
    changed = []
    for spheres in foot_spheres.values():
        sole_z = float(np.min(model.geom_pos[spheres, 2] - model.geom_size[spheres, 0]))
        for geom in _level_boxes(model, spheres):
            model.geom_pos[geom, 2] = sole_z + model.geom_size[geom, 2]
            model.geom_contype[geom] = FOOT_GROUP
            model.geom_conaffinity[geom] = 0
            changed.append(int(geom))
    return changed


def _level_boxes(model: mujoco.MjModel, spheres: list[int]) -> list[int]:
    """The level boxes (`_level_box`) of the foot body that carries the contact spheres."""
    body = int(model.geom_bodyid[spheres[0]])
    return [
        int(g)
        for g in np.flatnonzero(model.geom_bodyid == body)
        if g not in spheres and _level_box(model, int(g))
    ]


def sole_geoms(model: mujoco.MjModel, spheres: list[int]) -> list[int]:
    """The level boxes of the spheres' foot body that touch the floor (`add_soles`' result on
    this model)."""
    return [g for g in _level_boxes(model, spheres) if model.geom_contype[g]]


def lowest_sole_point(
    model: mujoco.MjModel, data: mujoco.MjData, spheres: list[int], boxes: list[int]
) -> np.ndarray:
    """The lowest point ((3,), world, m) of a foot's floor geometry in the pose in `data` (after
    kinematics): its contact spheres' bottoms and its sole boxes' bottom corners."""
    points = [data.geom_xpos[g] - [0.0, 0.0, model.geom_size[g, 0]] for g in spheres]
    for g in boxes:
        sx, sy, sz = model.geom_size[g]
        corners = np.array([[a * sx, b * sy, -sz] for a in (-1, 1) for b in (-1, 1)])
        points.extend(data.geom_xpos[g] + corners @ data.geom_xmat[g].reshape(3, 3).T)
    points = np.asarray(points)
    return points[int(np.argmin(points[:, 2]))]
