"""Where a population is simulated: threads in C on this machine (default), worker processes, or a
Ray cluster.

Every evaluator is a callable X (P × n, normalized) -> list[Outcome], built from the sketch so
remote workers can rebuild the same problem. Processes and Ray split the population into one batch
per worker.
"""

from __future__ import annotations

import multiprocessing as mp
from typing import Callable

import numpy as np

from eigengait.control.sketch import Sketch
from eigengait.errors import UserInputError
from eigengait.optimize.evaluate import BatchEvaluator, Outcome, default_threads
from eigengait.optimize.problem import Problem
from eigengait.outputs import keep_mujoco_log_out_of_the_folder

EVALUATORS = ("threads", "processes", "ray")
_worker: BatchEvaluator | None = None


def _batch_evaluator(sketch_json: dict, threads: int) -> BatchEvaluator:
    """A worker process's or Ray actor's evaluator; MuJoCo's warnings go to its standard error."""
    keep_mujoco_log_out_of_the_folder()
    return batch_evaluator(Problem.from_sketch(Sketch.model_validate(sketch_json)), threads)


def batch_evaluator(problem: Problem, threads: int) -> BatchEvaluator:
    """The sketch's batched closed-loop evaluator (its targets and optimization horizon)."""
    return BatchEvaluator(
        problem.system,
        problem.space,
        problem.sketch.targets,
        threads=threads,
        cycles=problem.sketch.feedback.horizon_cycles,
    )


def _process_init(sketch_json: dict) -> None:
    global _worker
    _worker = _batch_evaluator(sketch_json, threads=1)


def _process_evaluate(X: np.ndarray) -> list[Outcome]:
    return _worker.evaluate(X)


class ProcessEvaluator:
    def __init__(self, sketch: Sketch, workers: int):
        self.pool = mp.get_context("spawn").Pool(
            workers, _process_init, (sketch.model_dump(mode="json"),)
        )
        self.workers = workers

    def __call__(self, X: np.ndarray) -> list[Outcome]:
        parts = self.pool.map(_process_evaluate, np.array_split(X, self.workers))
        return [o for part in parts for o in part]

    def close(self) -> None:
        self.pool.terminate()


class RayEvaluator:
    """One Ray actor per worker, each holding its own BatchEvaluator (connects to RAY_ADDRESS or
    starts local)."""

    def __init__(self, sketch: Sketch, workers: int, address: str | None = None):
        try:
            import ray
        except ImportError:
            raise UserInputError(
                "Ray is not installed",
                field="evaluator",
                fix="pip install 'eigengait[ray]' or use evaluator='threads'",
            ) from None
        self.ray = ray
        if not ray.is_initialized():
            ray.init(
                address=address,
                num_cpus=None if address else workers,
                include_dashboard=False,
                log_to_driver=False,
                ignore_reinit_error=True,
            )
        actor = ray.remote(num_cpus=1)(_RayWorker)
        payload = sketch.model_dump(mode="json")
        self.actors = [actor.remote(payload) for _ in range(workers)]

    def __call__(self, X: np.ndarray) -> list[Outcome]:
        parts = np.array_split(X, len(self.actors))
        futures = [a.evaluate.remote(part) for a, part in zip(self.actors, parts) if len(part)]
        return [o for part in self.ray.get(futures) for o in part]

    def close(self) -> None:
        for a in self.actors:
            self.ray.kill(a)


class _RayWorker:
    def __init__(self, sketch_json: dict):
        self.evaluator = _batch_evaluator(sketch_json, threads=1)

    def evaluate(self, X: np.ndarray) -> list[Outcome]:
        return self.evaluator.evaluate(X)


class ThreadEvaluator:
    def __init__(self, problem: Problem, threads: int):
        self.batch = batch_evaluator(problem, threads)

    def __call__(self, X: np.ndarray) -> list[Outcome]:
        return self.batch.evaluate(X)

    def close(self) -> None:
        self.batch.close()


def make_evaluator(
    kind: str, problem: Problem, workers: int | None = None, ray_address: str | None = None
) -> Callable[[np.ndarray], list[Outcome]]:
    workers = workers or default_threads()
    if kind == "threads":
        return ThreadEvaluator(problem, workers)
    if kind == "processes":
        return ProcessEvaluator(problem.sketch, workers)
    if kind == "ray":
        return RayEvaluator(problem.sketch, workers, ray_address)
    raise UserInputError(
        f"unknown evaluator '{kind}'", field="evaluator", fix=f"use one of {', '.join(EVALUATORS)}"
    )
