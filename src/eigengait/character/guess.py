"""What eigengait guesses about a model without a sidecar: feet and left/right mirror pairs.

* **Feet**: the creature's named end bodies (no child body) whose lowest geom point at the model's
  zero pose lies within `FOOT_BAND` of the creature's height above its lowest point, or the body
  above such an end body when its sole is longer (a foot above its toes, as in dm_control's CMU
  humanoid). A foot's sole is the underside of its geoms within `SOLE_BAND` of its lowest point,
  each geom read as contact spheres (a capsule's two ends, a box's lowest corners rounded by its
  smallest half-size, a sphere); the foot gets a toe and a heel contact sphere (sites
  `eigengait:foot:<body>` and `eigengait:heel:<body>`) at the two ends of the sole's long axis, or
  one toe point at its lowest sphere if the sole is shorter than `MIN_SOLE`. The foot is named
  after the body. A sidecar may name such a site (`toe: eigengait:foot:<body>`) for any body: the
  points are placed the same way.
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
# share of the creature's height: geometry this near a foot's lowest point is its sole
SOLE_BAND = 0.03
MIN_SOLE = 0.01  # share of the creature's height: a sole shorter than this is one point
PLANE_M = 5e-3  # m: sole spheres spread this far across their line span a plane
UP = np.array([0.0, 0.0, 1.0])
TIE_M = 1e-3  # m: sole ends this close to equally far from the foot's origin are a tie
MAX_FOOT_DEPTH = 2  # bodies above a lowest end body that may be its foot (a foot above its toes)
FOOT_SITE_PREFIX = "eigengait:foot:"
HEEL_SITE_PREFIX = "eigengait:heel:"


@dataclass(frozen=True)
class FootPoint:
    """A guessed foot: its body, the toe contact sphere's centre in the body frame (m), its radius
    (m), and the heel sphere's centre and radius when the sole is long enough for two."""

    body: str
    pos: tuple[float, float, float]
    radius: float
    heel: tuple[float, float, float] | None = None
    heel_radius: float | None = None
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)  # the sole's normal, body frame

    @property
    def site(self) -> str:
        return FOOT_SITE_PREFIX + self.body

    @property
    def heel_site(self) -> str | None:
        return None if self.heel is None else HEEL_SITE_PREFIX + self.body


def _geom_spheres(
    model: mujoco.MjModel, data: mujoco.MjData, g: int
) -> list[tuple[np.ndarray, float]]:
    """The spheres (world centre, radius) that make a geom's underside in the pose in `data`: a
    capsule's or cylinder's two ends, a sphere, a box's or ellipsoid's four lowest corners rounded
    by its smallest half-size, else the bounding sphere."""
    centre, R, size = data.geom_xpos[g], data.geom_xmat[g].reshape(3, 3), model.geom_size[g]
    kind = int(model.geom_type[g])
    if kind in (mujoco.mjtGeom.mjGEOM_CAPSULE, mujoco.mjtGeom.mjGEOM_CYLINDER):
        return [(centre + s * size[1] * R[:, 2], float(size[0])) for s in (-1, 1)]
    if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
        return [(centre.copy(), float(size[0]))]
    if kind in (mujoco.mjtGeom.mjGEOM_BOX, mujoco.mjtGeom.mjGEOM_ELLIPSOID):
        r = float(size.min())
        inner = np.maximum(size - r, 0.0)
        corners = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)]) * inner
        world = centre + corners @ R.T
        return [(p, r) for p in world[np.argsort(world[:, 2])[:4]]]
    return [(centre.copy(), float(model.geom_rbound[g]))]


def _body_spheres(model, data, body: int) -> list[tuple[np.ndarray, float]]:
    return [
        sphere
        for g in np.flatnonzero(model.geom_bodyid == body)
        if int(model.geom_type[g]) != mujoco.mjtGeom.mjGEOM_PLANE
        for sphere in _geom_spheres(model, data, int(g))
    ]


def _bottom(sphere: tuple[np.ndarray, float]) -> float:
    return float(sphere[0][2] - sphere[1])


def _foot_of(model, data, body: int, band: float, min_sole: float) -> FootPoint | None:
    """The contact spheres of a foot body (world pose in `data`): its sole (the spheres whose bottom
    lies within `band` of its lowest) as a toe and a heel at its two ends along the sole's long
    horizontal axis (each the mean of the spheres at that end, as low as the lowest), the toe the
    end farther from the body's origin (on a sole centred on it, the end toward world +x, MuJoCo's
    forward), and the sole's normal (`_sole_normal`); one point, the lowest, if the sole is
    shorter than `min_sole` (m)."""
    spheres = _body_spheres(model, data, body)
    if not spheres:
        return None
    low = min(_bottom(s) for s in spheres)
    sole = [s for s in spheres if _bottom(s) <= low + band]
    R, origin = data.xmat[body].reshape(3, 3), data.xpos[body]
    centres = np.array([c for c, _ in sole])

    def local(p: np.ndarray) -> tuple[float, float, float]:
        return tuple(float(x) for x in R.T @ (p - origin))

    gaps = np.linalg.norm(centres[:, None, :2] - centres[None, :, :2], axis=-1)
    i, j = np.unravel_index(int(np.argmax(gaps)), gaps.shape)
    if gaps[i, j] < min_sole:
        c, r = min(sole, key=_bottom)
        return FootPoint(model.body(body).name, local(c), r, up=tuple(R.T @ UP))
    axis = (centres[j, :2] - centres[i, :2]) / gaps[i, j]
    along = (centres[:, :2] - origin[:2]) @ axis
    reach = abs(along.max()) - abs(along.min())
    if reach < -TIE_M or (abs(reach) <= TIE_M and axis[0] < 0):
        axis, along = -axis, -along
    span = along.max() - along.min()
    ends = []
    for near in (along >= along.max() - 0.25 * span, along <= along.min() + 0.25 * span):
        group = [sole[k] for k in np.flatnonzero(near)]
        r = float(np.mean([radius for _, radius in group]))
        centre = centres[near].mean(axis=0)
        centre[2] = min(map(_bottom, group)) + r  # as low as the end's lowest sphere
        ends.append((centre, r))
    (toe, r_toe), (heel, r_heel) = ends
    up = tuple(float(x) for x in R.T @ _sole_normal(centres, toe - heel))
    return FootPoint(model.body(body).name, local(toe), r_toe, local(heel), r_heel, up)


def _sole_normal(centres: np.ndarray, heel_to_toe: np.ndarray) -> np.ndarray:
    """Upward unit normal (world) of the plane through a sole's sphere centres (k, 3), or, for
    spheres in a line, world up made square to the heel-to-toe line."""
    spread = np.linalg.svd(centres - centres.mean(axis=0))
    if len(centres) >= 3 and spread.S[1] > PLANE_M:
        normal = spread.Vh[2]
        return normal * np.sign(normal[2])
    line = heel_to_toe / np.linalg.norm(heel_to_toe)
    up = UP - (UP @ line) * line
    return up / np.linalg.norm(up)


def foot_at(model: mujoco.MjModel, body: str) -> FootPoint | None:
    """The contact spheres of a named body (`_foot_of` at the model's zero pose, the bands scaled
    by its creature's height; None if it has no geom)."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    b = model.body(body).id
    top = int(model.body_rootid[b])
    scale = _height(model, data, [k for k in range(model.nbody) if in_subtree(model, k, top)])
    return _foot_of(model, data, b, SOLE_BAND * scale, MIN_SOLE * scale)


def _height(model, data, bodies: list[int]) -> float:
    """Height (m) of the bodies' geometry at the pose in `data`, from its lowest to its highest
    point."""
    geoms = [
        g
        for g in range(model.ngeom)
        if int(model.geom_bodyid[g]) in bodies
        and int(model.geom_type[g]) != mujoco.mjtGeom.mjGEOM_PLANE
    ]
    low = min(_bottom(s) for g in geoms for s in _geom_spheres(model, data, g))
    high = max(data.geom_xpos[g][2] + model.geom_rbound[g] for g in geoms)
    return float(high - low)


def find_feet(model: mujoco.MjModel, root: int) -> list[FootPoint]:
    """Guessed feet of the creature rooted at body id `root`, in model order: each named end body
    whose lowest point lies within FOOT_BAND of the creature's height above the creature's lowest,
    or the body above it (at most MAX_FOOT_DEPTH up, carrying no other such end body) whose sole is
    longer, as a foot's is above its toes."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    bodies = [b for b in range(model.nbody) if in_subtree(model, b, root)]
    lowest = {b: min(map(_bottom, s)) for b in bodies if (s := _body_spheres(model, data, b))}
    if not lowest:
        return []
    height = _height(model, data, bodies)
    low = min(lowest.values())
    leaves = [
        b
        for b in bodies
        if b in lowest
        and model.body(b).name
        and not any(model.body_parentid[c] == b for c in bodies if c != b)
        and lowest[b] <= low + FOOT_BAND * height
    ]
    feet = []
    for leaf in leaves:
        chain = [leaf]
        while len(chain) <= MAX_FOOT_DEPTH:
            up = int(model.body_parentid[chain[-1]])
            if (
                up == root
                or not model.body(up).name
                or any(in_subtree(model, other, up) for other in leaves if other != leaf)
            ):
                break
            chain.append(up)
        options = [
            f
            for b in chain
            if b in lowest
            and (f := _foot_of(model, data, b, SOLE_BAND * height, MIN_SOLE * height))
        ]
        feet.append(max(options, key=lambda f: _sole_length(f)))
    return feet


def _sole_length(foot: FootPoint) -> float:
    """Heel-to-toe distance (m); 0 for a one-point foot."""
    return 0.0 if foot.heel is None else float(np.linalg.norm(np.subtract(foot.pos, foot.heel)))


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
