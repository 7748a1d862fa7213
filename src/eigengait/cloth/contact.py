"""Compiled cloth–obstacle contact: swept point–triangle hits, resting contact, and obstacle edges vs cloth.

Three tests run after every step (all lengths in m, velocities in m/s):

* **Crossing** — as FLEX3D, the segment a point sweeps during the step, x(t) → x(t+h), against the obstacle
  triangles (Möller–Trumbore); the earliest hit wins. The point is put back on the side it came from at
  ``thickness`` from the triangle, keeping the tangential part of its motion; its normal velocity becomes
  ``-e v_n``.
* **Resting** — a point that stays on one side but ends closer than ``thickness`` to a triangle (projected inside
  it) is lifted to ``thickness`` and loses its approach velocity, so cloth rests *on* an obstacle at a constant
  gap instead of sinking into it between hits.
* **Edges** — points sampled along the obstacle's convex edges (at most half a cloth spacing apart) cast a ray
  along the edge's outward bisector; a cloth triangle that the ray meets closer than ``thickness`` (or behind the
  edge, up to one cloth spacing inside) is pushed out along the bisector, its three points weighted by their
  barycentric coordinates. This is what keeps a table's edge and corners under the cloth draped over them.

Candidates come from uniform grids: one over the static obstacle triangles, built once, and one over the cloth
triangles, rebuilt each step when edge samples exist.
"""

from __future__ import annotations

import numba as nb
import numpy as np

_MAX_CELLS = 64 ** 3


@nb.njit(cache=True)
def _cell_range(lo, hi, origin, cell, dims):
    a = np.empty(3, np.int64)
    b = np.empty(3, np.int64)
    for q in range(3):
        a[q] = max(int(np.floor((lo[q] - origin[q]) / cell)), 0)
        b[q] = min(int(np.floor((hi[q] - origin[q]) / cell)), dims[q] - 1)
    return a, b


@nb.njit(cache=True)
def build_grid(lo, hi, origin, cell, dims):
    """Bucket boxes [lo, hi] (B, 3) into a uniform grid; returns CSR (start (C+1,), items)."""
    count = np.zeros(dims[0] * dims[1] * dims[2] + 1, np.int64)
    for t in range(lo.shape[0]):
        a, b = _cell_range(lo[t], hi[t], origin, cell, dims)
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                for k in range(a[2], b[2] + 1):
                    count[(i * dims[1] + j) * dims[2] + k + 1] += 1
    start = np.cumsum(count)
    fill = start[:-1].copy()
    items = np.empty(start[-1], np.int64)
    for t in range(lo.shape[0]):
        a, b = _cell_range(lo[t], hi[t], origin, cell, dims)
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                for k in range(a[2], b[2] + 1):
                    c = (i * dims[1] + j) * dims[2] + k
                    items[fill[c]] = t
                    fill[c] += 1
    return start, items


def grid_layout(lo: np.ndarray, hi: np.ndarray, cell: float):
    """(origin, cell size, dims) of a grid covering boxes [lo, hi]; the cell grows if there would be too many."""
    origin = lo.min(axis=0)
    extent = np.maximum(hi.max(axis=0) - origin, 1e-9)
    cell = max(cell, float(np.cbrt(np.prod(extent) / _MAX_CELLS)), 1e-9)
    dims = np.maximum(np.ceil(extent / cell).astype(np.int64), 1)
    return origin, cell, dims


@nb.njit(cache=True)
def _ray_triangle(p, d, a, b, c):
    """(hit, s, u, v) for the line p + s d against triangle abc (s unbounded; u, v barycentric of b, c)."""
    e1 = b - a
    e2 = c - a
    pvec = np.cross(d, e2)
    det = (e1 * pvec).sum()
    if abs(det) < 1e-14:
        return False, 0.0, 0.0, 0.0
    inv = 1.0 / det
    tvec = p - a
    u = (tvec * pvec).sum() * inv
    qvec = np.cross(tvec, e1)
    v = (d * qvec).sum() * inv
    s = (e2 * qvec).sum() * inv
    tol = 1e-9
    return (u >= -tol) and (v >= -tol) and (u + v <= 1.0 + tol), s, u, v


@nb.njit(cache=True)
def collide_points(x0, x1, v, movable, corners, normals, origin, cell, dims, start, items, thickness, restitution):
    """Crossing and resting contacts of the points with static triangles ``corners`` (T, 3, 3); returns the count."""
    stamp = np.full(corners.shape[0], -1, np.int64)
    contacts = 0
    for p in range(x0.shape[0]):
        if not movable[p]:
            continue
        lo = np.minimum(x0[p], x1[p]) - thickness
        hi = np.maximum(x0[p], x1[p]) + thickness
        a, b = _cell_range(lo, hi, origin, cell, dims)
        best_s, best_t, rest_depth, rest_t = 2.0, -1, 0.0, -1
        step = x1[p] - x0[p]
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                for k in range(a[2], b[2] + 1):
                    c = (i * dims[1] + j) * dims[2] + k
                    for slot in range(start[c], start[c + 1]):
                        t = items[slot]
                        if stamp[t] == p:
                            continue
                        stamp[t] = p
                        n = normals[t]
                        side0 = ((x0[p] - corners[t, 0]) * n).sum()
                        side1 = ((x1[p] - corners[t, 0]) * n).sum()
                        if side0 * side1 <= 0.0:
                            hit, s, _, _ = _ray_triangle(x0[p], step, corners[t, 0], corners[t, 1], corners[t, 2])
                            if hit and 0.0 <= s <= 1.0 and s < best_s:
                                best_s, best_t = s, t
                        elif abs(side1) < thickness:
                            hit, _, _, _ = _ray_triangle(x1[p], n, corners[t, 0], corners[t, 1], corners[t, 2])
                            if hit and thickness - abs(side1) > rest_depth:
                                rest_depth, rest_t = thickness - abs(side1), t
        if best_t >= 0:
            n = normals[best_t].copy()
            if ((x0[p] - corners[best_t, 0]) * n).sum() < 0.0:
                n = -n
            tangential = step - (step * n).sum() * n
            x1[p] = x0[p] + best_s * step + (1.0 - best_s) * tangential + thickness * n
        elif rest_t >= 0:
            n = normals[rest_t].copy()
            if ((x1[p] - corners[rest_t, 0]) * n).sum() < 0.0:
                n = -n
            x1[p] += rest_depth * n
        else:
            continue
        vn = (v[p] * n).sum()
        if vn < 0.0:
            v[p] -= (1.0 + restitution) * vn * n
        contacts += 1
    return contacts


@nb.njit(cache=True)
def collide_edges(samples, directions, x, v, movable, triangles, origin, cell, dims, start, items, thickness, depth):
    """Push cloth triangles out of the obstacle edge samples (S, 3) along ``directions``; returns the count."""
    contacts = 0
    for f in range(samples.shape[0]):
        p = samples[f]
        d = directions[f]
        lo = np.minimum(p - depth * d, p + thickness * d)
        hi = np.maximum(p - depth * d, p + thickness * d)
        a, b = _cell_range(lo, hi, origin, cell, dims)
        best_s, best_t, best_u, best_v = thickness, -1, 0.0, 0.0
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                for k in range(a[2], b[2] + 1):
                    c = (i * dims[1] + j) * dims[2] + k
                    for slot in range(start[c], start[c + 1]):
                        t = items[slot]
                        tri = triangles[t]
                        hit, s, u, w = _ray_triangle(p, d, x[tri[0]], x[tri[1]], x[tri[2]])
                        if hit and -depth <= s < best_s:
                            best_s, best_t, best_u, best_v = s, t, u, w
        if best_t < 0:
            continue
        tri = triangles[best_t]
        weights = np.array([1.0 - best_u - best_v, best_u, best_v])
        norm = 0.0
        for q in range(3):
            if movable[tri[q]]:
                norm += weights[q] ** 2
        if norm == 0.0:
            continue
        push = (thickness - best_s) / norm
        for q in range(3):
            node = tri[q]
            if movable[node]:
                x[node] += weights[q] * push * d
                vn = (v[node] * d).sum()
                if vn < 0.0:
                    v[node] -= vn * d
        contacts += 1
    return contacts


@nb.njit(cache=True)
def triangle_boxes(x, triangles, pad, lo, hi):
    """Fill lo, hi (T, 3) with the bounding boxes of the cloth triangles, padded by ``pad``."""
    for t in range(triangles.shape[0]):
        for q in range(3):
            a = x[triangles[t, 0], q]
            b = x[triangles[t, 1], q]
            c = x[triangles[t, 2], q]
            lo[t, q] = min(a, b, c) - pad
            hi[t, q] = max(a, b, c) + pad


def convex_edge_samples(vertices: np.ndarray, triangles: np.ndarray, spacing: float):
    """Points along the convex edges of a closed triangle mesh, at most ``spacing`` apart (ends included), and
    their outward directions (unit bisector of the two faces' outward normals).

    The fan diagonals inside flat polygons are skipped (their two faces are coplanar). Outward means away from the
    enclosed volume: the normals are flipped if the mesh's signed volume is negative.
    """
    corners = vertices[triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    if np.einsum("ij,ij->", corners[:, 0], normals) < 0:
        normals = -normals
    normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
    faces_of: dict[tuple[int, int], list[int]] = {}
    for t, tri in enumerate(triangles.tolist()):
        for q in range(3):
            a, b = tri[q], tri[(q + 1) % 3]
            faces_of.setdefault((min(a, b), max(a, b)), []).append(t)
    points, directions = [], []
    for (a, b), faces in faces_of.items():
        if len(faces) != 2:
            continue
        f, g = faces
        other = [w for w in triangles[g] if w not in (a, b)][0]
        if np.dot(vertices[other] - vertices[a], normals[f]) > -1e-9 * (1 + np.abs(vertices).max()):
            continue  # coplanar or concave
        bisector = normals[f] + normals[g]
        bisector /= np.linalg.norm(bisector)
        count = int(np.ceil(np.linalg.norm(vertices[b] - vertices[a]) / spacing)) + 1
        s = np.linspace(0.0, 1.0, count)[:, None]
        points.append(vertices[a] + s * (vertices[b] - vertices[a]))
        directions.append(np.repeat(bisector[None], count, axis=0))
    if not points:
        return np.zeros((0, 3)), np.zeros((0, 3))
    return np.concatenate(points), np.concatenate(directions)


def closest_surface_point(point: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """The point of the triangles ``corners`` (T, 3, 3) nearest to ``point`` (3,), all in m."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    normal = np.cross(b - a, c - a)
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    projected = point - ((point - a) * normal).sum(axis=1)[:, None] * normal
    inside = np.ones(len(corners), bool)
    for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
        inside &= (np.cross(q - p, projected - p) * np.cross(q - p, r - p)).sum(axis=1) >= 0
    candidates = [projected[inside]]
    for p, q in ((a, b), (b, c), (c, a)):
        edge = q - p
        s = np.clip(((point - p) * edge).sum(axis=1) / np.maximum((edge * edge).sum(axis=1), 1e-300), 0.0, 1.0)
        candidates.append(p + s[:, None] * edge)
    every = np.concatenate(candidates)
    return every[np.argmin(np.linalg.norm(every - point, axis=1))]
