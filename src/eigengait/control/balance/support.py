"""The support polygon of a stance foot from its actual contacts, and the part of an ankle torque it
can carry.

A foot resting on the floor with normal force N (newtons) balances a horizontal torque τ from its
ankle (world, N·m, about the ankle) only by moving its centre of pressure to the offset r = (τ_y,
−τ_x) / N from the ankle's floor point (horizontal forces and the foot's own dynamics neglected).
The ground can put the centre of pressure only inside the convex hull of the foot's contact points;
a torque asking for a point outside tips the foot about the hull's edge, and the foot-rooted
Jacobian's premise (the foot stays put) fails. `carried_torque` returns the part of τ the contacts
carry: the torque of the centre of pressure moved to the hull's nearest point.
"""

from __future__ import annotations

import numpy as np


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z component of the cross product of horizontal vectors (..., 2)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Vertices (k, 2) of the convex hull of horizontal points (n, 2), counter-clockwise (monotone
    chain); one or two vertices when the points are one point or on a line."""
    pts = np.unique(np.round(np.asarray(points, float), 9), axis=0)
    if len(pts) <= 2:
        return pts

    def chain(ordered: np.ndarray) -> list[np.ndarray]:
        out: list[np.ndarray] = []
        for p in ordered:
            while len(out) >= 2 and _cross(out[-1] - out[-2], p - out[-2]) <= 1e-12:
                out.pop()
            out.append(p)
        return out

    lower, upper = chain(pts), chain(pts[::-1])
    hull = np.array(lower[:-1] + upper[:-1])
    return hull if len(hull) >= 2 else pts[[0, -1]]


def nearest_in_hull(point: np.ndarray, hull: np.ndarray) -> np.ndarray:
    """The point of the convex polygon `hull` (k, 2; k = 1 or 2: a point or a segment) nearest to
    `point` (2,)."""
    if len(hull) == 1:
        return hull[0].copy()
    if len(hull) >= 3:
        edges = np.roll(hull, -1, axis=0) - hull
        if np.all(_cross(edges, point - hull) >= 0.0):
            return np.asarray(point, float).copy()
    best, best_d = hull[0], np.inf
    for a, b in zip(hull, np.roll(hull, -1, axis=0)[: len(hull) if len(hull) >= 3 else 1]):
        t = np.clip(np.dot(point - a, b - a) / max(np.dot(b - a, b - a), 1e-12), 0.0, 1.0)
        q = a + t * (b - a)
        d = np.linalg.norm(point - q)
        if d < best_d:
            best, best_d = q, d
    return np.asarray(best, float).copy()


def carried_torque(
    torque: np.ndarray, normal: float, ankle: np.ndarray, contacts: np.ndarray
) -> np.ndarray:
    """Horizontal part (3,) of the ankle's torque on the foot `torque` (3,) that the foot's contact
    points `contacts` (n, 3, world, m) carry with normal force `normal` (N) about the ankle at
    `ankle` (3,); see the module doc. Zero without normal force or contacts."""
    if normal <= 0.0 or len(contacts) == 0:
        return np.zeros(3)
    needed = ankle[:2] + np.array([torque[1], -torque[0]]) / normal
    cop = nearest_in_hull(needed, convex_hull(contacts[:, :2])) - ankle[:2]
    return np.array([-cop[1] * normal, cop[0] * normal, 0.0])
