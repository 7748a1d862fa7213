"""What eigengait guesses about a model without a sidecar: feet and left/right mirror pairs.

* **Feet**: the creature's named end bodies (no child body) whose lowest geom point at the model's
  zero pose lies within `FOOT_BAND` of the creature's height above its lowest point. Each gets one
  contact point (a site named `eigengait:foot:<body>`) at the bottom of its lowest geom, with that
  geom's radius (capsule, sphere, cylinder) or smallest half-size (box, ellipsoid, mesh bounding
  sphere otherwise). The foot is named after the body. A sidecar may name such a site
  (`toe: eigengait:foot:<body>`) for any body: the point is placed the same way.
* **Mirror pairs**: joints whose names differ only by left/right (`left`/`right`, `l`/`r` at the
  start, `_l`/`_r` or `_left`/`_right` anywhere) are paired.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import mujoco
import numpy as np

from eigengait.body_tree import in_subtree

FOOT_BAND = 0.1
FOOT_SITE_PREFIX = "eigengait:foot:"


@dataclass(frozen=True)
class FootPoint:
    """A guessed foot: its body, the contact point in the body frame (m) and the contact sphere
    radius (m)."""

    body: str
    pos: tuple[float, float, float]
    radius: float

    @property
    def site(self) -> str:
        return FOOT_SITE_PREFIX + self.body


def _geom_bottom(model: mujoco.MjModel, data: mujoco.MjData, g: int) -> tuple[np.ndarray, float]:
    """(world centre of the contact sphere at the geom's lowest point, its radius)."""
    centre, R, size = data.geom_xpos[g], data.geom_xmat[g].reshape(3, 3), model.geom_size[g]
    kind = model.geom_type[g]
    if kind in (mujoco.mjtGeom.mjGEOM_CAPSULE, mujoco.mjtGeom.mjGEOM_CYLINDER):
        ends = [centre + s * size[1] * R[:, 2] for s in (-1, 1)]
        return min(ends, key=lambda p: p[2]), float(size[0])
    if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
        return centre.copy(), float(size[0])
    if kind in (mujoco.mjtGeom.mjGEOM_BOX, mujoco.mjtGeom.mjGEOM_ELLIPSOID):
        r = float(size.min())
        drop = float(np.abs(R[2, :]) @ size) - r
        return centre - [0, 0, drop], r
    r = float(model.geom_rbound[g])
    return centre.copy(), r


def foot_at(model: mujoco.MjModel, body: str) -> FootPoint | None:
    """The contact point at the bottom of a named body's lowest geom (None if it has no geom)."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    b = model.body(body).id
    bottoms = [
        _geom_bottom(model, data, g) for g in range(model.ngeom) if model.geom_bodyid[g] == b
    ]
    if not bottoms:
        return None
    c, r = min(bottoms, key=lambda cr: cr[0][2] - cr[1])
    local = data.xmat[b].reshape(3, 3).T @ (c - data.xpos[b])
    return FootPoint(body, tuple(float(x) for x in local), r)


def find_feet(model: mujoco.MjModel, root: int) -> list[FootPoint]:
    """Guessed feet of the creature rooted at body id `root`, in model order."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    bodies = [b for b in range(model.nbody) if in_subtree(model, b, root)]
    bottoms = {}
    for g in range(model.ngeom):
        b = int(model.geom_bodyid[g])
        if b in bodies and model.geom_type[g] != mujoco.mjtGeom.mjGEOM_PLANE:
            c, r = _geom_bottom(model, data, g)
            if b not in bottoms or c[2] - r < bottoms[b][0][2] - bottoms[b][1]:
                bottoms[b] = (c, r)
    if not bottoms:
        return []
    low = min(c[2] - r for c, r in bottoms.values())
    high = max(
        data.geom_xpos[g][2] + model.geom_rbound[g]
        for g in range(model.ngeom)
        if int(model.geom_bodyid[g]) in bodies
    )
    leaves = [
        b
        for b in bodies
        if b in bottoms
        and model.body(b).name
        and not any(model.body_parentid[c] == b for c in bodies if c != b)
    ]
    feet = []
    for b in leaves:
        c, r = bottoms[b]
        if c[2] - r <= low + FOOT_BAND * (high - low):
            R = data.xmat[b].reshape(3, 3)
            local = R.T @ (c - data.xpos[b])
            feet.append(FootPoint(model.body(b).name, tuple(float(x) for x in local), r))
    return feet


_SIDES = [("left", "right"), ("Left", "Right"), ("LEFT", "RIGHT")]


def _partner(name: str) -> str | None:
    for a, b in _SIDES:
        if a in name:
            return name.replace(a, b)
        if b in name:
            return name.replace(b, a)
    for pattern, swap in (
        (r"^l(?=[a-z_])", "r"),
        (r"^r(?=[a-z_])", "l"),
        (r"_l(?=$|_)", "_r"),
        (r"_r(?=$|_)", "_l"),
    ):
        if re.search(pattern, name):
            return re.sub(pattern, swap, name, count=1)
    return None


def mirror_pairs(joints: list[str]) -> dict[str, str]:
    """Left -> right joint pairs found from the names (each pair once, keyed by the first in model
    order)."""
    known, pairs, seen = set(joints), {}, set()
    for j in joints:
        p = _partner(j)
        if p and p in known and p != j and j not in seen:
            pairs[j] = p
            seen |= {j, p}
    return pairs
