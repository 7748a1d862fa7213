"""From a sketch to a closed-loop gait in two stages, each a method-of-multipliers run in the same
run folder.

1. **Open loop, one cycle** (`RUN/open-loop/`): the sketch without feedback, simulated for one
   cycle; the cyclic constraint (end of the cycle against (q₀, q̇₀), plus the mirrored half cycle)
   until it holds within the sketch's tolerance or `OPEN_LOOP_SHARE` of the budget is spent. This
   finds the orbit quickly.
2. **Closed loop** (`RUN/`): the whole sketch (feedback gains, `horizon_cycles` cycles with no
   reset), started from stage 1's best with every gain at zero, i.e. from the open-loop gait.

A sketch without feedback and with a one-cycle horizon runs stage 2 alone. `resume=True` resumes
whichever stage was interrupted.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from eigengait.control.sketch import Sketch
from eigengait.optimize.checkpoint import load_state
from eigengait.optimize.mom import MomState, SearchSettings
from eigengait.optimize.parameters import feedback_gain_count
from eigengait.optimize.run import optimize

OPEN_LOOP_SHARE = 0.4  # at most this share of the evaluation or time budget goes to stage 1
# stage 2's first step size (normalized): near the open-loop gait, room for the gains
CLOSED_LOOP_SIGMA = 0.1
STAGE_ONE = "open-loop"
CHECKPOINT = "checkpoint.npz"


def open_loop_sketch(sketch: Sketch) -> Sketch:
    """The same sketch without feedback, simulated for one cycle."""
    return sketch.model_copy(
        update={
            "feedback": sketch.feedback.model_copy(update={"mechanisms": [], "horizon_cycles": 1})
        }
    )


def _share(settings: SearchSettings, share: float) -> SearchSettings:
    return replace(
        settings,
        max_evaluations=int(settings.max_evaluations * share) if settings.max_evaluations else None,
        max_seconds=settings.max_seconds * share if settings.max_seconds else None,
    )


def _spent(settings: SearchSettings, state: MomState) -> SearchSettings:
    return replace(
        settings,
        max_evaluations=(
            max(1, settings.max_evaluations - state.evaluations)
            if settings.max_evaluations
            else None
        ),
        max_seconds=max(1.0, settings.max_seconds - state.elapsed)
        if settings.max_seconds
        else None,
    )


def optimize_gait(
    sketch: Sketch,
    folder: Path,
    settings: SearchSettings,
    evaluator: str = "threads",
    workers: int | None = None,
    resume: bool = False,
    progress: bool = True,
    sketch_source: str | Path | None = None,
    seed: int | None = None,
) -> MomState:
    """Optimize a sketch into a gait (two stages when it has feedback or a multi-cycle horizon).
    Returns the last stage's state with the generations, evaluations and seconds of both
    stages. `seed`: the seed the user asked for explicitly, if any (a resumed run refuses a
    different one)."""
    if not sketch.feedback.mechanisms and sketch.feedback.horizon_cycles == 1:
        return optimize(
            sketch, folder, settings, evaluator, workers, resume, progress, sketch_source, seed=seed
        )
    stage = folder / STAGE_ONE
    # nothing of stage 1 to resume: the run folder says why
    if resume and not (stage / CHECKPOINT).exists():
        return optimize(
            sketch, folder, settings, evaluator, workers, True, progress, sketch_source, seed=seed
        )
    if resume and (folder / CHECKPOINT).exists():
        first = load_state(stage / CHECKPOINT)
        last = optimize(
            sketch,
            folder,
            replace(_spent(settings, first), sigma0=CLOSED_LOOP_SIGMA),
            evaluator,
            workers,
            True,
            progress,
            sketch_source,
            seed=seed,
        )
        return _whole_run(last, first)
    first = optimize(
        open_loop_sketch(sketch),
        stage,
        _share(settings, OPEN_LOOP_SHARE),
        evaluator,
        workers,
        resume,
        progress,
        sketch_source,
        seed=seed,
    )
    last = closed_loop_stage(
        sketch, folder, _spent(settings, first), first, evaluator, workers, progress, sketch_source
    )
    return _whole_run(last, first)


def _whole_run(last: MomState, first: MomState) -> MomState:
    """Stage 2's state `last` counting stage 1's generations, evaluations and seconds too: what the
    run spent from the sketch, as its budget counts it."""
    return replace(
        last,
        generation=last.generation + first.generation,
        evaluations=last.evaluations + first.evaluations,
        elapsed=last.elapsed + first.elapsed,
    )


def closed_loop_stage(
    sketch: Sketch,
    folder: Path,
    settings: SearchSettings,
    first: MomState,
    evaluator: str = "threads",
    workers: int | None = None,
    progress: bool = True,
    sketch_source: str | Path | None = None,
) -> MomState:
    """Stage 2 from an open-loop run's best, every feedback gain at zero."""
    gains = feedback_gain_count(sketch)
    x_start = np.r_[first.best_x, np.full(gains, 0.5)]  # normalized 0.5 = zero gain
    return optimize(
        sketch,
        folder,
        replace(settings, sigma0=CLOSED_LOOP_SIGMA),
        evaluator,
        workers,
        False,
        progress,
        sketch_source,
        x_start=x_start,
    )
