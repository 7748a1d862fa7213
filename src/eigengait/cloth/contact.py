"""Compiled cloth–obstacle contact: swept point–triangle hits, resting contact, and obstacle edges
vs cloth.

Three tests run after every step (all lengths in m, velocities in m/s):

* **Crossing** — as FLEX3D, the segment a point sweeps during the step, x(t) → x(t+h), against the
  obstacle triangles (Möller–Trumbore); the earliest hit wins. The point is put back on the side it
  came from at ``thickness`` from the triangle, keeping the tangential part of its motion; its
  normal velocity becomes ``-e v_n``.
* **Resting** — a point that stays on one side but ends closer than ``thickness`` to a triangle
  (projected inside it) is lifted to ``thickness`` and loses its approach velocity, so cloth rests
  *on* an obstacle at a constant gap instead of sinking into it between hits.
* **Edges** — points sampled along the obstacle's convex edges (at most half a cloth spacing apart)
  cast a ray along the edge's outward bisector; a cloth triangle that the ray meets closer than
  ``thickness`` (or behind the edge, up to one cloth spacing inside) is pushed out along the
  bisector, its three points weighted by their barycentric coordinates. This is what keeps a table's
  edge and corners under the cloth draped over them.

Candidates come from uniform grids: one over the static obstacle triangles, built once, and one over
the cloth triangles, rebuilt each step when edge samples exist.
"""

from __future__ import annotations

import numba as nb
import numpy as np

_MAX_CELLS = 64**3


# Small 3-vectors are tuples inside the kernels: they live in registers, where arrays would be
# heap-allocated.
@nb.njit(cache=True, inline="always")
def _row(a, i):
    return (a[i, 0], a[i, 1], a[i, 2])


@nb.njit(cache=True, inline="always")
def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@nb.njit(cache=True, inline="always")
def _axpy(s, a, b):
    """s·a + b"""
    return (s * a[0] + b[0], s * a[1] + b[1], s * a[2] + b[2])


@nb.njit(cache=True, inline="always")
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@nb.njit(cache=True, inline="always")
def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@nb.njit(cache=True, inline="always")
def _store(a, i, value):
    a[i, 0], a[i, 1], a[i, 2] = value


@nb.njit(cache=True)
def _cell_range(lo, hi, origin, cell, dims):
    """First and last cell (i, j, k) of the box [lo, hi], clipped to the grid."""
    a = (
        max(int(np.floor((lo[0] - origin[0]) / cell)), 0),
        max(int(np.floor((lo[1] - origin[1]) / cell)), 0),
        max(int(np.floor((lo[2] - origin[2]) / cell)), 0),
    )
    b = (
        min(int(np.floor((hi[0] - origin[0]) / cell)), dims[0] - 1),
        min(int(np.floor((hi[1] - origin[1]) / cell)), dims[1] - 1),
        min(int(np.floor((hi[2] - origin[2]) / cell)), dims[2] - 1),
    )
    return a, b


@nb.njit(cache=True)
def build_grid(lo, hi, origin, cell, dims):
    """Bucket boxes [lo, hi] (B, 3) into a uniform grid; returns CSR (start (C+1,), items)."""
    count = np.zeros(dims[0] * dims[1] * dims[2] + 1, np.int64)
    for t in range(lo.shape[0]):
        a, b = _cell_range(_row(lo, t), _row(hi, t), origin, cell, dims)
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                for k in range(a[2], b[2] + 1):
                    count[(i * dims[1] + j) * dims[2] + k + 1] += 1
    start = np.cumsum(count)
    fill = start[:-1].copy()
    items = np.empty(start[-1], np.int64)
    for t in range(lo.shape[0]):
        a, b = _cell_range(_row(lo, t), _row(hi, t), origin, cell, dims)
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                for k in range(a[2], b[2] + 1):
                    c = (i * dims[1] + j) * dims[2] + k
                    items[fill[c]] = t
                    fill[c] += 1
    return start, items


def grid_layout(lo: np.ndarray, hi: np.ndarray, cell: float):
    """(origin, cell size, dims) of a grid covering boxes [lo, hi]; the cell grows if there would be
    too many."""
    origin = lo.min(axis=0)
    extent = np.maximum(hi.max(axis=0) - origin, 1e-9)
    cell = max(cell, float(np.cbrt(np.prod(extent) / _MAX_CELLS)), 1e-9)
    dims = np.maximum(np.ceil(extent / cell).astype(np.int64), 1)
    return origin, cell, dims


@nb.njit(cache=True)
def _ray_triangle(p, d, a, b, c):
    """(hit, s, u, v) for the line p + s d against triangle abc (s unbounded; u, v barycentric of b,
    c)."""
    e1 = _sub(b, a)
    e2 = _sub(c, a)
    pvec = _cross(d, e2)
    det = _dot(e1, pvec)
    if abs(det) < 1e-14:
        return False, 0.0, 0.0, 0.0
    inv = 1.0 / det
    tvec = _sub(p, a)
    u = _dot(tvec, pvec) * inv
    qvec = _cross(tvec, e1)
    v = _dot(d, qvec) * inv
    s = _dot(e2, qvec) * inv
    tol = 1e-9
    return (u >= -tol) and (v >= -tol) and (u + v <= 1.0 + tol), s, u, v


@nb.njit(cache=True)
def collide_points(
    x0, x1, v, movable, corners, normals, origin, cell, dims, start, items, thickness, restitution
):
    """Crossing and resting contacts of the points with static triangles ``corners`` (T, 3, 3);
    returns the count."""
    stamp = np.full(corners.shape[0], -1, np.int64)
    contacts = 0
    for p in range(x0.shape[0]):
        if not movable[p]:
            continue
        p0, p1 = _row(x0, p), _row(x1, p)
        lo = (
            min(p0[0], p1[0]) - thickness,
            min(p0[1], p1[1]) - thickness,
            min(p0[2], p1[2]) - thickness,
        )
        hi = (
            max(p0[0], p1[0]) + thickness,
            max(p0[1], p1[1]) + thickness,
            max(p0[2], p1[2]) + thickness,
        )
        a, b = _cell_range(lo, hi, origin, cell, dims)
        best_s, best_t, rest_depth, rest_t = 2.0, -1, 0.0, -1
        step = _sub(p1, p0)
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                for k in range(a[2], b[2] + 1):
                    c = (i * dims[1] + j) * dims[2] + k
                    for slot in range(start[c], start[c + 1]):
                        t = items[slot]
                        if stamp[t] == p:
                            continue
                        stamp[t] = p
                        n = _row(normals, t)
                        ca, cb, cc = _row(corners[t], 0), _row(corners[t], 1), _row(corners[t], 2)
                        side0 = _dot(_sub(p0, ca), n)
                        side1 = _dot(_sub(p1, ca), n)
                        if side0 * side1 <= 0.0:
                            hit, s, _, _ = _ray_triangle(p0, step, ca, cb, cc)
                            if hit and 0.0 <= s <= 1.0 and s < best_s:
                                best_s, best_t = s, t
                        elif abs(side1) < thickness:
                            hit, _, _, _ = _ray_triangle(p1, n, ca, cb, cc)
                            if hit and thickness - abs(side1) > rest_depth:
                                rest_depth, rest_t = thickness - abs(side1), t
        if best_t >= 0:
            n = _row(normals, best_t)
            if _dot(_sub(p0, _row(corners[best_t], 0)), n) < 0.0:
                n = _axpy(-2.0, n, n)
            tangential = _axpy(-_dot(step, n), n, step)
            _store(
                x1, p, _axpy(thickness, n, _axpy(1.0 - best_s, tangential, _axpy(best_s, step, p0)))
            )
        elif rest_t >= 0:
            n = _row(normals, rest_t)
            if _dot(_sub(p1, _row(corners[rest_t], 0)), n) < 0.0:
                n = _axpy(-2.0, n, n)
            _store(x1, p, _axpy(rest_depth, n, p1))
        else:
            continue
        vp = _row(v, p)
        vn = _dot(vp, n)
        if vn < 0.0:
            _store(v, p, _axpy(-(1.0 + restitution) * vn, n, vp))
        contacts += 1
    return contacts


@nb.njit(cache=True)
def collide_edges(
    samples,
    directions,
    x,
    v,
    movable,
    triangles,
    origin,
    cell,
    dims,
    start,
    items,
    thickness,
    depth,
):
    """Push cloth triangles out of the obstacle edge samples (S, 3) along ``directions``; returns
    the count."""
    contacts = 0
    for f in range(samples.shape[0]):
        p = _row(samples, f)
        d = _row(directions, f)
        back, ahead = _axpy(-depth, d, p), _axpy(thickness, d, p)
        lo = (min(back[0], ahead[0]), min(back[1], ahead[1]), min(back[2], ahead[2]))
        hi = (max(back[0], ahead[0]), max(back[1], ahead[1]), max(back[2], ahead[2]))
        a, b = _cell_range(lo, hi, origin, cell, dims)
        best_s, best_t, best_u, best_v = thickness, -1, 0.0, 0.0
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                for k in range(a[2], b[2] + 1):
                    c = (i * dims[1] + j) * dims[2] + k
                    for slot in range(start[c], start[c + 1]):
                        t = items[slot]
                        hit, s, u, w = _ray_triangle(
                            p,
                            d,
                            _row(x, triangles[t, 0]),
                            _row(x, triangles[t, 1]),
                            _row(x, triangles[t, 2]),
                        )
                        if hit and -depth <= s < best_s:
                            best_s, best_t, best_u, best_v = s, t, u, w
        if best_t < 0:
            continue
        weights = (1.0 - best_u - best_v, best_u, best_v)
        norm = 0.0
        for q in range(3):
            if movable[triangles[best_t, q]]:
                norm += weights[q] ** 2
        if norm == 0.0:
            continue
        push = (thickness - best_s) / norm
        for q in range(3):
            node = triangles[best_t, q]
            if movable[node]:
                _store(x, node, _axpy(weights[q] * push, d, _row(x, node)))
                vq = _row(v, node)
                vn = _dot(vq, d)
                if vn < 0.0:
                    _store(v, node, _axpy(-vn, d, vq))
        contacts += 1
    return contacts


@nb.njit(cache=True)
def collide_self(
    x0, x1, v, mass, movable, triangles, origin, cell, dims, start, items, thickness, restitution
):
    """Compiled self-collision, in place on (x1, v); returns the number of contacts.

    Each movable point closer than ``thickness`` to a cloth triangle that does not contain it (its
    projection inside the triangle) is pushed halfway back towards ``thickness`` on the side it was
    on at the start of the step, and an impulse along the normal, shared by the triangle's points by
    their barycentric weights, removes the approach velocity (restitution e; for e = 1 and equal
    masses it swaps normal velocities). Same rule as the NumPy ``collision.collide_self``, applied
    point by point.
    """
    contacts = 0
    for p in range(x1.shape[0]):
        if not movable[p]:
            continue
        point = _row(x1, p)
        lo = (point[0] - thickness, point[1] - thickness, point[2] - thickness)
        hi = (point[0] + thickness, point[1] + thickness, point[2] + thickness)
        a, b = _cell_range(lo, hi, origin, cell, dims)
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                for k in range(a[2], b[2] + 1):
                    c = (i * dims[1] + j) * dims[2] + k
                    for slot in range(start[c], start[c + 1]):
                        t0, t1, t2 = (
                            triangles[items[slot], 0],
                            triangles[items[slot], 1],
                            triangles[items[slot], 2],
                        )
                        if t0 == p or t1 == p or t2 == p:
                            continue
                        point = _row(x1, p)
                        pa, pb, pc = _row(x1, t0), _row(x1, t1), _row(x1, t2)
                        normal = _cross(_sub(pb, pa), _sub(pc, pa))
                        size = np.sqrt(_dot(normal, normal))
                        if size == 0.0:
                            continue
                        normal = (normal[0] / size, normal[1] / size, normal[2] / size)
                        dist = _dot(_sub(point, pa), normal)
                        if abs(dist) >= thickness:
                            continue
                        hit, _, u, w = _ray_triangle(point, normal, pa, pb, pc)
                        if not hit or min(u, w, 1.0 - u - w) < 0.0:
                            continue
                        if _dot(_sub(_row(x0, p), _row(x0, t0)), normal) < 0.0:
                            normal = (-normal[0], -normal[1], -normal[2])
                            dist = -dist
                        _store(x1, p, _axpy(0.5 * (thickness - dist), normal, point))
                        weights = (1.0 - u - w, u, w)
                        nodes = (t0, t1, t2)
                        relative = _row(v, p)
                        for q in range(3):
                            relative = _axpy(-weights[q], _row(v, nodes[q]), relative)
                        approach = _dot(relative, normal)
                        if approach < 0.0:
                            share = 1.0 / mass[p]
                            for q in range(3):
                                share += weights[q] ** 2 / mass[nodes[q]]
                            impulse = (1.0 + restitution) * approach / share
                            _store(v, p, _axpy(-impulse / mass[p], normal, _row(v, p)))
                            for q in range(3):
                                _store(
                                    v,
                                    nodes[q],
                                    _axpy(
                                        weights[q] * impulse / mass[nodes[q]],
                                        normal,
                                        _row(v, nodes[q]),
                                    ),
                                )
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
    """Points along the convex edges of a closed triangle mesh, at most ``spacing`` apart (ends
    included), and their outward directions (unit bisector of the two faces' outward normals).

    The fan diagonals inside flat polygons are skipped (their two faces are coplanar). Outward means
    away from the enclosed volume: the normals are flipped if the mesh's signed volume is negative.
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
        s = np.clip(
            ((point - p) * edge).sum(axis=1) / np.maximum((edge * edge).sum(axis=1), 1e-300),
            0.0,
            1.0,
        )
        candidates.append(p + s[:, None] * edge)
    every = np.concatenate(candidates)
    return every[np.argmin(np.linalg.norm(every - point, axis=1))]
