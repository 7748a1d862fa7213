"""The optimization benchmarks' baseline: the wall time of one closed-loop population evaluation of
a sketch."""

from __future__ import annotations

import time

import numpy as np

from eigengait.control.sketch import Sketch
from eigengait.optimize.evaluate import BatchEvaluator
from eigengait.optimize.problem import Problem


def population_seconds(sketch: Sketch) -> tuple[float, int]:
    """Seconds to evaluate one CMA-ES population (default size 4 + 3 ln n) of the sketch's initial
    guess over its horizon, and the population size."""
    problem = Problem.from_sketch(sketch)
    evaluator = BatchEvaluator(
        problem.system, problem.space, sketch.targets, cycles=sketch.feedback.horizon_cycles
    )
    population = np.tile(problem.space.initial(), (4 + int(3 * np.log(problem.space.size)), 1))
    start = time.perf_counter()
    evaluator.evaluate(population)
    return time.perf_counter() - start, len(population)
