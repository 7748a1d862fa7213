"""Checkpoints as data: one NPZ file of plain arrays plus a JSON text, read without pickle.

A checkpoint holds the optimizer's counters, multipliers, penalty, best solution and log, and the
current inner CMA-ES run as data: its start point and every generation's candidates with their cost
and cycle violation. The CMA object (and pycma's adaptive augmented Lagrangian) is rebuilt on resume
by replaying those generations from the run's seed, which gives back the same object bit for bit.
Nothing in the file can name code to run: arrays are read with `allow_pickle=False` and the rest is
JSON.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from eigengait.errors import UserInputError
from eigengait.optimize.evaluate import Outcome
from eigengait.optimize.mom import MomState
from eigengait.outputs import replacing

FORMAT = "eigengait-checkpoint-1"
SCALARS = ("outer", "sigma", "k", "generation", "evaluations", "elapsed", "finished", "log")


def _history_arrays(state: MomState) -> dict[str, np.ndarray]:
    if not state.history:
        return {}
    return {
        "history_x": np.array([X for X, _ in state.history], dtype=float),
        "history_cost": np.array(
            [[o.cost for o in outs] for _, outs in state.history], dtype=float
        ),
        "history_cycle": np.array(
            [[o.cycle for o in outs] for _, outs in state.history], dtype=float
        ),
    }


def save_state(state: MomState, path: Path | str) -> None:
    """Write the checkpoint atomically (temporary name in the same folder, then rename)."""
    path = Path(path)
    best = state.best
    meta = {
        "format": FORMAT,
        **{k: getattr(state, k) for k in SCALARS},
        "best": None
        if best is None
        else {
            "cost": float(best.cost),
            "fell": bool(best.fell),
            "energy": float(best.energy),
            "soft": best.soft,
        },
    }
    arrays = {"x_start": state.x_start, **_history_arrays(state)}
    for name in ("lam", "best_x", "inner_start"):
        if getattr(state, name) is not None:
            arrays[name] = np.asarray(getattr(state, name), dtype=float)
    if best is not None:
        arrays["best_cycle"], arrays["best_mean_velocity"] = best.cycle, best.mean_velocity
    with replacing(path) as temporary, open(temporary, "wb") as f:
        np.savez(f, meta=np.array(json.dumps(meta)), **arrays)


def _read(path: Path) -> tuple[dict, dict[str, np.ndarray]]:
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {name: npz[name] for name in npz.files}
        meta = json.loads(str(arrays.pop("meta")))
    except Exception as exc:
        raise UserInputError(
            f"the checkpoint is corrupt ({exc.__class__.__name__})",
            file=path,
            fix="delete the run folder's checkpoint.npz to start over, or restore it",
        ) from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise UserInputError("not an eigengait checkpoint", file=path)
    return meta, arrays


def load_state(path: Path | str) -> MomState:
    """Read a checkpoint written by `save_state`; any damage is a `UserInputError`."""
    path = Path(path)
    meta, a = _read(path)
    try:
        state = MomState(
            x_start=a["x_start"],
            lam=a.get("lam"),
            best_x=a.get("best_x"),
            inner_start=a.get("inner_start"),
            **{k: meta[k] for k in SCALARS},
        )
        if meta["best"] is not None:
            state.best = Outcome(
                cycle=a["best_cycle"], mean_velocity=a["best_mean_velocity"], **meta["best"]
            )
        if "history_x" in a:
            state.history = [
                (
                    X,
                    [
                        Outcome(
                            cost=float(c),
                            cycle=phi,
                            fell=False,
                            mean_velocity=np.zeros(3),
                            energy=0.0,
                        )
                        for c, phi in zip(costs, cycles)
                    ],
                )
                for X, costs, cycles in zip(a["history_x"], a["history_cost"], a["history_cycle"])
            ]
    except (KeyError, TypeError, ValueError) as exc:
        raise UserInputError(
            f"the checkpoint is incomplete ({exc.__class__.__name__}: {exc})",
            file=path,
            fix="delete the run folder's checkpoint.npz to start over, or restore it",
        ) from None
    if state.history and state.inner_start is None:
        raise UserInputError(
            "the checkpoint records an inner run without its start point", file=path
        )
    return state
