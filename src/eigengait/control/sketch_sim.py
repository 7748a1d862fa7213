"""Simulate a sketch as the animator sees it: gravity off, priority activations only, from the relax
pose."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
from mujoco import rollout

from eigengait.control.gait import GaitParameters
from eigengait.control.sketch import Sketch
from eigengait.control.binding import bind_sketch
from eigengait.control.gait import GaitSystem
from eigengait.sim.stepping import blown_up_dof, blown_up_steps, raise_blow_up
from eigengait.sim.world import World

SKETCH_FPS = 30.0


@dataclass
class SketchRun:
    world: World
    qpos: np.ndarray  # (frames × nq) at `fps`
    fps: float
    wall_seconds: float
    max_joint_rotation_deg: float


def sketch_parameters(sk: Sketch, system: GaitSystem) -> GaitParameters:
    """The sketch's own controller: its timing, priority ψ only, relax pose at rest."""
    activations = system.dense_activations(lambda foot, phase: sk.phase(phase).priority)
    model = system.world.model
    return GaitParameters(
        period=sk.timing.period,
        air_ratio=sk.timing.air_ratio,
        pulse_air=sk.timing.pulse_air,
        pulse_ground=sk.timing.pulse_ground,
        activations=activations,
        qpos0=model.qpos0.copy(),
        qvel0=np.zeros(model.nv),
    )


def simulate_sketch(
    sketch: Sketch,
    seconds: float,
    source: str | Path | None = None,
    system: GaitSystem | None = None,
) -> SketchRun:
    """`seconds` of the sketch with gravity off; `system` (gravity off, bound to the sketch) saves a
    modal analysis."""
    system = system or bind_sketch(sketch, source, gravity=False)
    model = system.world.model
    p = sketch_parameters(sketch, system)
    u = system.controls(p, span=seconds)
    start = time.perf_counter()
    states, _ = rollout.rollout(model, mujoco.MjData(model), system.initial_state(p)[None], u[None])
    wall = time.perf_counter() - start
    view = system.world.view
    qvel, times = view.qvel(states[0]), view.time(states[0])
    blown = blown_up_steps(qvel, np.r_[0.0, times], model.opt.timestep)
    if blown.any():
        step = int(np.argmax(blown))
        # the time of the step itself: MuJoCo's reset of a diverged simulation restarts the recorded
        # clock
        raise_blow_up(
            system.world, (step + 1) * model.opt.timestep, blown_up_dof(qvel, step), source
        )
    stride = max(1, int(round(1 / (SKETCH_FPS * model.opt.timestep))))
    qpos = view.qpos(states[0, stride - 1 :: stride])
    biggest = 0.0
    for q in qpos:
        for j in system.world.internal_qpos_joints:
            a = model.jnt_qposadr[j]
            ball = model.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL
            biggest = max(biggest, 2 * np.arccos(np.clip(abs(q[a]), 0, 1)) if ball else abs(q[a]))
    return SketchRun(
        world=system.world,
        qpos=qpos,
        fps=1 / (stride * model.opt.timestep),
        wall_seconds=wall,
        max_joint_rotation_deg=float(np.rad2deg(biggest)),
    )
