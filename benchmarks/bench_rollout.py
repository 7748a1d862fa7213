"""Rollout throughput of a CMA-ES population, as a ratio to the raw single-thread engine.

Baseline (same process, same model): `mj_step(model, data, nstep)` on one thread, stepping one
humanoid from candidate initial states with the same pulse controls. Measured: the batched evaluator
(`mujoco.rollout` on a thread pool, objective computed from the recorded states) for 1, 2, … threads
up to the cores available. Prints simulated steps per second and the ratio to the baseline.
"""

from __future__ import annotations

import time

import mujoco
import numpy as np

from eigengait.control.library import resolve
from eigengait.control.sketch import load_sketch
from eigengait.optimize.evaluate import BatchEvaluator, default_threads
from eigengait.optimize.problem import Problem


def raw_steps_per_second(problem: Problem, X: np.ndarray) -> float:
    model = problem.system.world.model
    data = mujoco.MjData(model)
    steps, start = 0, time.perf_counter()
    for x in X:
        p = problem.space.decode(x)
        u = problem.system.controls(p, span=0.5 * p.period)
        data.qpos[:], data.qvel[:] = p.qpos0, p.qvel0
        mujoco.mj_forward(model, data)
        # piecewise-constant controls: one mj_step call per constant segment, all stepping in C
        change = np.flatnonzero(np.any(np.diff(u, axis=0) != 0, axis=1)) + 1
        for a, b in zip(np.r_[0, change], np.r_[change, len(u)]):
            data.ctrl[:] = u[a]
            mujoco.mj_step(model, data, int(b - a))
        steps += len(u)
    return steps / (time.perf_counter() - start)


def main() -> None:
    problem = Problem.from_sketch(load_sketch(resolve("sketch", "basic-run")))
    rng = np.random.default_rng(0)
    popsize = 4 + int(3 * np.log(problem.space.size))
    X = np.clip(
        problem.space.initial() + 0.05 * rng.normal(size=(popsize * 4, problem.space.size)), 0, 1
    )
    raw = raw_steps_per_second(problem, X)
    print(
        f"humanoid basic-run, population {popsize}, {len(X)} candidates, "
        f"step {problem.system.world.model.opt.timestep} s"
    )
    print(f"raw single-thread mj_step(nstep=…): {raw:10.0f} steps/s (baseline)")
    for threads in sorted({1, 2, default_threads()}):
        evaluator = BatchEvaluator(
            problem.system, problem.space, problem.sketch.targets, threads=threads
        )
        evaluator.evaluate(X[:popsize])  # warm-up
        evaluator.steps_simulated = 0
        start = time.perf_counter()
        for batch in np.array_split(X, 4):
            evaluator.evaluate(batch)
        rate = evaluator.steps_simulated / (time.perf_counter() - start)
        print(
            f"batched evaluator, {threads} thread(s):  {rate:10.0f} steps/s  ratio "
            f"{rate / raw:5.2f}"
        )
        evaluator.close()


if __name__ == "__main__":
    main()
