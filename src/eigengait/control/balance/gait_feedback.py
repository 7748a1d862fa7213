"""Closing the loop on modal gaits: play a pulse controller without the kinematic snap, with balance feedback.

`play(system, params, snap=False)` (control/playback.py) lets an optimised open-loop gait run on its own; small
errors grow from cycle to cycle until it falls. Here the gait's own first cycle (simulated open loop from
(q₀, q̇₀)) is the reference: it is replayed kinematically (`kinematic_replay`), which gives its COM, COM velocity
and acceleration, angular momentum and support points. Every later cycle reuses it, shifted forward by the first
cycle's horizontal COM displacement per cycle. At every physics step the balance torque of the momentum-Jacobian
controller (virtual force/torque at the COM, stance-foot rooted, E3–E32, exactly as in `Tracker._balance`) is added
to the pulse torques. No joint PD is added: the gait's own springs and pulses stay in charge of the joints, the
feedback only steers the COM and the root orientation. The character's passive springs stay on.

Robustness 0 (the default) adds no artificial foot torque, so the result stays physically correct.
A fall is the playback's: COM below half its standing height, the root upside down, or non-finite state.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout

from eigengait.control.balance.reference import kinematic_replay
from eigengait.control.balance.tracker import Tracker, TrackerSettings
from eigengait.control.balance.virtual import VirtualGains
from eigengait.control.gait import GaitParameters, GaitSystem

FRAME_STEPS = 4   # the reference is sampled every 4 physics steps (2 ms at the 0.5 ms step)

# Feedback only: the pulses and springs already carry the body and produce the reference's own momentum rates,
# so neither gravity compensation (E21) nor the momentum-rate feed-forward is added.
GAIT_GAINS = VirtualGains(k_fs=300.0, k_fd=80.0, k_P=1.0, k_ts=300.0, k_td=30.0, k_ma=1.0, feedforward=0.0,
                          gravity=0.0)


@dataclass
class FeedbackResult:
    cycles_completed: int
    fell: bool
    mean_speed_mps: float
    com_error_m: float             # RMS horizontal-and-vertical COM error against the shifted first cycle
    balance_torque_rms: float      # N·m, RMS over steps of the balance torque vector
    artificial_torque: float       # N·m, mean over steps (0 at robustness 0)
    qpos: np.ndarray               # (frames, nq) every FRAME_STEPS physics steps

    def summary(self) -> dict:
        return {"cycles_completed": self.cycles_completed, "fell": self.fell,
                "mean_speed_mps": round(self.mean_speed_mps, 4), "com_error_m": round(self.com_error_m, 4),
                "balance_torque_rms": round(self.balance_torque_rms, 2),
                "artificial_torque": round(self.artificial_torque, 3)}


def first_cycle(system: GaitSystem, p: GaitParameters) -> tuple[np.ndarray, np.ndarray]:
    """Open-loop first cycle: per-step controls (n, nu) and qpos every FRAME_STEPS steps, both ends included."""
    model = system.world.model
    u = system.controls(p, cycles=1)
    states, _ = rollout.rollout(model, [mujoco.MjData(model)], system.initial_state(p)[None], u[None])
    qpos = np.vstack([p.qpos0[None], states[0, FRAME_STEPS - 1::FRAME_STEPS, 1:1 + model.nq]])
    return u, qpos


def play_with_feedback(system: GaitSystem, p: GaitParameters, cycles: int = 10, robustness: float = 0.0,
                       gains: VirtualGains = GAIT_GAINS) -> FeedbackResult:
    """Play `cycles` cycles of the gait with no snap, the balance torque added to the pulse torques."""
    world = system.world
    model_src = world.model
    dt = model_src.opt.timestep
    u, ref_qpos = first_cycle(system, p)
    reference = kinematic_replay(world, ref_qpos, FRAME_STEPS * dt)
    shift = reference.com[-1, :2] - reference.com[0, :2]
    tracker = Tracker(world, reference, robustness, TrackerSettings(virtual=gains, joint_gains={}))
    model, data = tracker.model, tracker.data
    # Tracker switched the springs off and set PD damping: give the gait its own passive dynamics back.
    model.jnt_stiffness[:] = model_src.jnt_stiffness
    model.actuator_biasprm[:] = model_src.actuator_biasprm
    model.dof_damping[:] = model_src.dof_damping
    data.qpos[:], data.qvel[:] = p.qpos0, p.qvel0
    mujoco.mj_forward(model, data)
    standing = world.new_data().subtree_com[world.root_body][2]
    n, nm = len(u), world.nmotor
    start_x = float(data.subtree_com[world.root_body][0])
    com_err, torque_sq, artificial = [], [], []
    frames = [data.qpos.copy()]
    completed, fell = 0, False
    for cycle in range(cycles):
        for k in range(n):
            ref = tracker._reference_at(min(k * dt, reference.duration))
            ref["com"] = ref["com"].copy()
            ref["com"][:2] += cycle * shift
            ref["support"] = ref["support"] + cycle * shift
            mujoco.mj_forward(model, data)
            tau, art = tracker._balance(ref, tracker._stance_forces())
            data.ctrl[:] = u[k]
            data.ctrl[:nm] += tau[tracker.joint_dofs]
            com_err.append(np.linalg.norm(data.subtree_com[world.root_body] - ref["com"]))
            torque_sq.append(float(tau @ tau))
            artificial.append(art)
            mujoco.mj_step(model, data)
            quat = data.qpos[tracker.root_qpos + 3:tracker.root_qpos + 7]
            up_z = 1 - 2 * (quat[1] ** 2 + quat[2] ** 2)
            if not np.all(np.isfinite(data.qpos)) or up_z < 0 or \
                    data.subtree_com[world.root_body][2] < 0.5 * standing:
                fell = True
                break
            if (k + 1) % FRAME_STEPS == 0:
                frames.append(data.qpos.copy())
        if fell:
            break
        completed += 1
    duration = max(float(data.time), dt)
    return FeedbackResult(cycles_completed=completed, fell=fell,
                          mean_speed_mps=(float(data.subtree_com[world.root_body][0]) - start_x) / duration,
                          com_error_m=float(np.sqrt(np.mean(np.square(com_err)))),
                          balance_torque_rms=float(np.sqrt(np.mean(torque_sq))),
                          artificial_torque=float(np.mean(artificial)), qpos=np.array(frames))
