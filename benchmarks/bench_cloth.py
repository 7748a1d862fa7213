"""Cloth throughput: steps per second for hanging n×n surfaces (top row pinned, gravity, friction 0.5).

Compares, in one process: the vectorized explicit step (symplectic Euler), the implicit backward-Euler step,
a naive per-particle Python loop (the dissertation's algorithm, run for a few steps only), and MuJoCo's own
flex cloth (``<flexcomp type="grid">`` with edge springs) on the same grid. Also reports memory per particle.

Run: python benchmarks/bench_cloth.py [--sizes 20 100 200]
"""

from __future__ import annotations

import argparse
import math
import time
import tracemalloc

import numpy as np

from eigengait.cloth.model import surface_model
from eigengait.cloth.par import SurfaceSpec
from eigengait.cloth.simulate import Simulation


def hanging(n: int):
    spec = SurfaceSpec("cloth", n, n, 1.85, np.zeros(3), np.array([0.0, -1.0, 0.0]), 0.1, (10.0,) * 3,
                       (0.0,) * 3, fixed=[(0, j) for j in range(n)])
    return surface_model([spec], gravity=(0, 0, -9.81), friction=0.5)


def rate(sim: Simulation, budget: float = 3.0, max_steps: int = 2000) -> float:
    sim.advance(2)
    steps, start = 0, time.perf_counter()
    while time.perf_counter() - start < budget and steps < max_steps:
        sim.advance(5)
        steps += 5
    return steps / (time.perf_counter() - start)


def naive_rate(n: int, steps: int) -> float:
    """FLEX3D's loop: for every point, for every neighbour, accumulate forces; then Euler; pure Python."""
    model = hanging(n)
    x = model.rest_positions.tolist()
    v = [[0.0, 0.0, 0.0] for _ in x]
    neighbours = [[] for _ in x]
    for (i, j), rest, k in zip(model.springs.tolist(), model.spring_rest.tolist(), model.spring_k.tolist()):
        neighbours[i].append((j, rest, k))
        neighbours[j].append((i, rest, k))
    mass, fixed, h, mu, g = 0.1, model.fixed.tolist(), 0.001, 0.5, -9.81
    start = time.perf_counter()
    for _ in range(steps):
        new_x, new_v = [], []
        for p, (xp, vp) in enumerate(zip(x, v)):
            if fixed[p]:
                new_x.append(xp), new_v.append(vp)
                continue
            f = [0.0, 0.0, mass * g]
            for q, rest, k in neighbours[p]:
                d = [x[q][0] - xp[0], x[q][1] - xp[1], x[q][2] - xp[2]]
                length = math.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
                s = k * (length - rest) / length
                f = [f[0] + s * d[0], f[1] + s * d[1], f[2] + s * d[2]]
            speed = math.sqrt(vp[0] ** 2 + vp[1] ** 2 + vp[2] ** 2)
            if speed > 0:
                drag = min(mu * math.sqrt(f[0] ** 2 + f[1] ** 2 + f[2] ** 2), mass * speed / h) / speed
                f = [f[c] - drag * vp[c] for c in range(3)]
            new_x.append([xp[c] + h * vp[c] for c in range(3)])
            new_v.append([vp[c] + h * f[c] / mass for c in range(3)])
        x, v = new_x, new_v
    return steps / (time.perf_counter() - start)


def mujoco_rate(n: int, budget: float = 3.0) -> float | None:
    """MuJoCo flex grid of the same size, top row pinned, edge springs; None if the scene cannot be built."""
    try:
        import mujoco
    except ImportError:
        return None
    pins = " ".join(str(i * n + (n - 1)) for i in range(n))
    xml = f"""<mujoco><option timestep="0.001" solver="CG" iterations="5"><flag contact="disable"/></option><worldbody>
      <flexcomp name="cloth" type="grid" count="{n} {n} 1" spacing="1.85 1.85 1.85" pos="0 0 40" radius="0.05"
                dim="2" mass="{0.1 * n * n}">
        <elasticity young="2000" poisson="0.2" thickness="0.1" damping="0.01"/>
        <contact selfcollide="none" conaffinity="0" contype="0"/>
        <pin id="{pins}"/>
      </flexcomp></worldbody></mujoco>"""
    try:
        model = mujoco.MjModel.from_xml_string(xml)
    except ValueError as error:
        print(f"  mujoco flex scene could not be built: {error}")
        return None
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, nstep=5)
    steps, start = 0, time.perf_counter()
    while time.perf_counter() - start < budget and steps < 20000:
        mujoco.mj_step(model, data, nstep=20)
        steps += 20
    return steps / (time.perf_counter() - start)


def memory_per_particle(n: int) -> float:
    tracemalloc.start()
    sim = Simulation(hanging(n), 0.001, "implicit")
    sim.advance(1)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return peak / (n * n)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[20, 100, 200])
    args = parser.parse_args()
    import mujoco
    print(f"mujoco {mujoco.__version__}; steps per second (higher is better)")
    header = f"{'grid':>8} {'explicit':>10} {'implicit':>10} {'naive':>10} {'mujoco':>10} " \
             f"{'expl/naive':>11} {'expl/mj':>9} {'bytes/particle':>15}"
    print(header)
    for n in args.sizes:
        explicit = rate(Simulation(hanging(n), 0.001, "symplectic"))
        implicit = rate(Simulation(hanging(n), 0.01, "implicit"), max_steps=200)
        naive = naive_rate(n, steps=max(1, 40000 // (n * n)))
        mj = mujoco_rate(n)
        mem = memory_per_particle(n)
        ratio_mj = f"{explicit / mj:9.2f}" if mj else f"{'n/a':>9}"
        mj_text = f"{mj:10.0f}" if mj else f"{'n/a':>10}"
        print(f"{n:>4}x{n:<3} {explicit:10.0f} {implicit:10.1f} {naive:10.2f} {mj_text} {explicit / naive:11.0f} "
              f"{ratio_mj} {mem:15.0f}", flush=True)


if __name__ == "__main__":
    main()
