"""Collisions of moving mass points with triangles, found over each whole step.

Obstacles (static ``.OBT`` meshes): FLEX3D's test — the segment a point sweeps during the step, x(t)
→ x(t+h), against every triangle — is done for all points at once. Candidate (point, triangle) pairs
come from a ``scipy.spatial.cKDTree`` over triangle centroids queried with radius (largest triangle
radius + half the segment); the exact segment–triangle test (Möller–Trumbore) then runs vectorized
over the candidates. For each point the earliest hit wins.

Response at a hit (parameter s along the segment, triangle normal n turned towards the side the
point came from): the point is put back on that side at ``thickness`` from the triangle, keeping the
tangential part of its motion; its normal velocity becomes ``-e·v_n`` (restitution e: 1 is FLEX3D's
elastic bounce, 0 — the default — a cloth-like inelastic contact); the tangential velocity is kept.

Self-collision (optional): a point closer than ``thickness`` to a triangle of the cloth that does
not contain it is pushed back to the side it was on at the start of the step, and the normal
relative velocity is exchanged by an impulse that, for e = 1 and equal masses, swaps the normal
velocities as in the dissertation's eq. 3.6.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.spatial import cKDTree


class TriangleSoup:
    """Static triangles (T, 3, 3) in m with a spatial index over their centroids."""

    def __init__(self, corners: np.ndarray):
        self.corners = np.asarray(corners, float).reshape(-1, 3, 3)
        centroids = self.corners.mean(axis=1)
        normals = np.cross(
            self.corners[:, 1] - self.corners[:, 0], self.corners[:, 2] - self.corners[:, 0]
        )
        self.normals = normals / np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
        self.offsets = (self.normals * self.corners[:, 0]).sum(axis=1)
        self.radii = np.linalg.norm(self.corners - centroids[:, None], axis=2).max(axis=1)
        self.radius = float(self.radii.max()) if len(centroids) else 0.0
        self.tree = cKDTree(centroids) if len(centroids) else None

    def candidates(self, p0: np.ndarray, p1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(point index, triangle index) pairs whose bounding spheres overlap.

        The index is built over whichever set is smaller's complement: the static triangle tree when
        there are more triangles than points, otherwise a tree over the segment midpoints queried by
        each triangle.
        """
        if self.tree is None or len(p0) == 0:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        mid = 0.5 * (p0 + p1)
        half = 0.5 * np.linalg.norm(p1 - p0, axis=1)
        if len(self.corners) >= len(p0):
            found = self.tree.query_ball_point(mid, self.radius + half + 1e-9)
            points, triangles = _flatten(found)
            return points, triangles
        found = cKDTree(mid).query_ball_point(self.tree.data, self.radii + half.max() + 1e-9)
        triangles, points = _flatten(found)
        return points, triangles


def _flatten(found) -> tuple[np.ndarray, np.ndarray]:
    """(owner, item) index arrays from the list-of-lists a ball query returns."""
    counts = np.fromiter(map(len, found), np.int64, len(found))
    owners = np.repeat(np.arange(len(found)), counts)
    items = np.fromiter(itertools.chain.from_iterable(found), np.int64, counts.sum())
    return owners, items


def segment_triangle(p0, p1, a, b, c, eps: float = 1e-12):
    """Vectorized Möller–Trumbore for segments p0→p1 against triangles abc (all (K, 3)).

    Returns (hit mask, s in [0, 1] along the segment, unit normal of the triangle).
    """
    d = p1 - p0
    e1, e2 = b - a, c - a
    pvec = np.cross(d, e2)
    det = (e1 * pvec).sum(axis=1)
    ok = np.abs(det) > eps
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    tvec = p0 - a
    u = (tvec * pvec).sum(axis=1) * inv
    qvec = np.cross(tvec, e1)
    v = (d * qvec).sum(axis=1) * inv
    s = (e2 * qvec).sum(axis=1) * inv
    tol = 1e-9
    hit = ok & (u >= -tol) & (v >= -tol) & (u + v <= 1 + tol) & (s >= 0) & (s <= 1)
    normal = np.cross(e1, e2)
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    return hit, s, normal


def collide_with_obstacles(
    soup: TriangleSoup,
    x0: np.ndarray,
    x1: np.ndarray,
    v: np.ndarray,
    movable: np.ndarray,
    *,
    thickness: float,
    restitution: float,
) -> int:
    """Resolve hits of the segments x0→x1 of ``movable`` points in place (x1, v); returns the number
    of hits."""
    idx = np.flatnonzero(movable)
    points, tris = soup.candidates(x0[idx], x1[idx])
    # Only segments whose ends lie on opposite sides of (or on) a triangle's plane can cross it.
    n_pairs = soup.normals[tris]
    side0 = (x0[idx[points]] * n_pairs).sum(axis=1) - soup.offsets[tris]
    side1 = (x1[idx[points]] * n_pairs).sum(axis=1) - soup.offsets[tris]
    crossing = side0 * side1 <= 0
    points, tris = points[crossing], tris[crossing]
    if len(points) == 0:
        return 0
    corners = soup.corners[tris]
    p0, p1 = x0[idx[points]], x1[idx[points]]
    hit, s, normal = segment_triangle(p0, p1, corners[:, 0], corners[:, 1], corners[:, 2])
    if not hit.any():
        return 0
    points, s, normal, p0, p1 = points[hit], s[hit], normal[hit], p0[hit], p1[hit]
    order = np.lexsort((s, points))
    first = order[np.r_[True, points[order][1:] != points[order][:-1]]]
    who = idx[points[first]]
    n = normal[first]
    side = np.sign(((p0[first] - soup.corners[tris[hit][first], 0]) * n).sum(axis=1))
    n = n * np.where(side == 0, 1.0, side)[:, None]
    step = p1[first] - p0[first]
    tangential = step - (step * n).sum(axis=1)[:, None] * n
    contact = p0[first] + s[first][:, None] * step
    x1[who] = contact + (1.0 - s[first])[:, None] * tangential + thickness * n
    vn = (v[who] * n).sum(axis=1)
    v[who] -= ((1.0 + restitution) * np.minimum(vn, 0.0))[:, None] * n
    return len(who)


def collide_self(
    x0: np.ndarray,
    x1: np.ndarray,
    v: np.ndarray,
    mass: np.ndarray,
    triangles: np.ndarray,
    movable: np.ndarray,
    *,
    thickness: float,
    restitution: float,
) -> int:
    """Push points away from cloth triangles they come within ``thickness`` of; returns the number
    of contacts."""
    corners = x1[triangles]
    centroids = corners.mean(axis=1)
    reach = float(np.linalg.norm(corners - centroids[:, None], axis=2).max()) + thickness
    pairs = cKDTree(centroids).query_ball_point(x1[movable], reach)
    idx = np.flatnonzero(movable)
    owner, tri = _flatten(pairs)
    point = idx[owner]
    keep = (triangles[tri] != point[:, None]).all(axis=1)
    point, tri = point[keep], tri[keep]
    if len(point) == 0:
        return 0
    a, b, c = (x1[triangles[tri, k]] for k in range(3))
    e1, e2 = b - a, c - a
    normal = np.cross(e1, e2)
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    dist = ((x1[point] - a) * normal).sum(axis=1)
    w = _barycentric(x1[point] - dist[:, None] * normal, a, e1, e2)
    close = (np.abs(dist) < thickness) & (w >= 0).all(axis=1)
    if not close.any():
        return 0
    point, tri, normal, w = point[close], tri[close], normal[close], w[close]
    before = x0[triangles[tri]]
    side = np.sign(((x0[point] - before[:, 0]) * normal).sum(axis=1))
    n = normal * np.where(side == 0, 1.0, side)[:, None]
    gap = ((x1[point] - x1[triangles[tri, 0]]) * n).sum(axis=1)
    x1[point] += (thickness - gap)[:, None] * n * 0.5
    vt = (w[:, :, None] * v[triangles[tri]]).sum(axis=1)
    approach = np.minimum(((v[point] - vt) * n).sum(axis=1), 0.0)
    m_tri = mass[triangles[tri]]
    impulse = (1.0 + restitution) * approach / (1.0 / mass[point] + (w**2 / m_tri).sum(axis=1))
    np.add.at(v, point, -(impulse / mass[point])[:, None] * n)
    for k in range(3):
        np.add.at(v, triangles[tri, k], (w[:, k] * impulse / m_tri[:, k])[:, None] * n)
    return len(point)


def _barycentric(p, a, e1, e2) -> np.ndarray:
    """(K, 3) barycentric weights of p in triangles a, a+e1, a+e2."""
    q = p - a
    d00, d01, d11 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    d20, d21 = (q * e1).sum(1), (q * e2).sum(1)
    den = np.maximum(d00 * d11 - d01 * d01, 1e-300)
    wb = (d11 * d20 - d01 * d21) / den
    wc = (d00 * d21 - d01 * d20) / den
    return np.stack([1.0 - wb - wc, wb, wc], axis=1)
