"""Foot contacts of a simulated trajectory, and the footfall diagram (one bar per foot against
time).

A foot is on the ground in a frame by the rule of `sim/contacts.py` (one of its toe/heel contact
spheres within 5 mm of the floor plane). Colours are fixed per foot
order, so videos, strips and diagrams agree.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.sim.contacts import spheres_touching
from eigengait.sim.world import World

FOOT_COLOURS = (
    (0.13, 0.47, 0.80),
    (0.89, 0.35, 0.13),
    (0.18, 0.63, 0.29),
    (0.58, 0.30, 0.70),
    (0.80, 0.63, 0.10),
    (0.40, 0.40, 0.40),
)


def foot_colour(index: int) -> tuple[float, float, float]:
    """RGB (0–1) of the foot at position `index` in the world's foot order."""
    return FOOT_COLOURS[index % len(FOOT_COLOURS)]


def has_floor(world: World) -> bool:
    """Whether the world has a floor plane to stand on."""
    return any(
        world.model.geom_type[g] == mujoco.mjtGeom.mjGEOM_PLANE for g in range(world.model.ngeom)
    )


def contact_points(world: World, data: mujoco.MjData) -> dict[str, np.ndarray | None]:
    """Per foot, the mean world position (m) of its spheres touching the floor in `data`, or None if
    airborne."""
    model, points = world.model, {}
    for foot, spheres in world.foot_spheres.items():
        touching = np.asarray(spheres)[
            spheres_touching(data.geom_xpos[spheres, 2], model.geom_size[spheres, 0])
        ]
        points[foot] = data.geom_xpos[touching].mean(axis=0) if touching.size else None
    return points


def foot_contacts(world: World, qpos: np.ndarray) -> np.ndarray:
    """Contact flags (T × feet, bool) of a trajectory (T × nq), feet in `world.foot_spheres`
    order."""
    data = mujoco.MjData(world.model)
    flags = np.zeros((len(qpos), len(world.foot_spheres)), dtype=bool)
    for t, q in enumerate(qpos):
        data.qpos[:] = q
        mujoco.mj_kinematics(world.model, data)
        flags[t] = [p is not None for p in contact_points(world, data).values()]
    return flags


def contact_diagram(
    ax,
    times: np.ndarray,
    contacts: np.ndarray,
    feet: list[str],
    period_s: float | None = None,
    marks: np.ndarray | None = None,
) -> None:
    """Draw the footfall diagram on a matplotlib axis: a bar per foot where it touches the ground.

    `times` (s) are the frame times of `contacts` (T × feet). With `period_s` the cycle boundaries
    are dashed and the top axis shows the phase in cycles; `marks` (s) draws thin grey lines, e.g.
    at a picture strip's frames.
    """
    step = float(np.median(np.diff(times))) if len(times) > 1 else 0.0
    for row, foot in enumerate(feet):
        on = contacts[:, row].astype(int)
        starts = np.flatnonzero(np.diff(np.r_[0, on]) == 1)
        ends = np.flatnonzero(np.diff(np.r_[on, 0]) == -1)
        spans = [(times[s], times[e] - times[s] + step) for s, e in zip(starts, ends)]
        ax.broken_barh(spans, (row - 0.35, 0.7), color=foot_colour(row))
    ax.set_yticks(range(len(feet)), feet)
    ax.set_ylim(len(feet) - 0.5, -0.5)
    ax.set_xlim(times[0], times[-1] + step)
    ax.set_xlabel("time (s)")
    ax.set_title("foot contacts (bar: on the ground)", fontsize=10, loc="left")
    for t in marks if marks is not None else ():
        ax.axvline(t, color="#999999", lw=0.6, zorder=0)
    if period_s:
        start = np.ceil(times[0] / period_s - 1e-9) * period_s
        for t in np.arange(start, times[-1] + step + 1e-9, period_s):
            ax.axvline(t, color="black", lw=1.0, ls="--")
        top = ax.secondary_xaxis("top", functions=(lambda t: t / period_s, lambda c: c * period_s))
        top.set_xlabel(f"phase (cycles of {period_s:.3f} s)")
    ax.grid(axis="x", alpha=0.25)
