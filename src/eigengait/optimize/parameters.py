"""The optimized parameters Ω, normalized to [0, 1] (thesis §4.4).

Ω = (T, α, δa, δc, ψ of the optimized modes per free (foot, phase), root height offset, root pitch,
root forward and vertical speed, and q₀, q̇₀ of the internal joints in the span of the optimized air
modes). Expressing q₀/q̇₀ in mode coordinates keeps the search small for many-DOF characters (the
thesis's own suggestion): the sketch's optimized air modes (none for a canonical sketch) plus the
lowest `initial.modes` ones. Priority modes keep their sign and at least their sketch magnitude.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from eigengait.sim.limits import clip_to_joint_ranges, floor_penetration
from eigengait.sim.stepping import MAX_SPEED
from eigengait.control.activations import mode_index, psi_key
from eigengait.control.feedback import FEATURES, HIP_GAINS, FeedbackGains
from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.control.sketch import Sketch, Timing
from eigengait.sim.world import FLOOR, GRAVITY

MAX_JOINT_ANGLE = 0.3  # rad: largest joint rotation of one initial-pose mode coordinate
PERIOD_RANGE = (0.6, 1.6)  # the period T stays within these multiples of the sketch's guess
# pulse durations δ too: a pulse shrunk to nothing would silence the priority modes
PULSE_RANGE = (0.5, 2.0)
AIR_RATIO_SPAN = 0.25  # α stays within ± this of the sketch's (α → 0 or 1 would erase a state)
HIP_GAIN_RANGE = 0.3  # |hip gains| ≤ this × m g h (N·m per normalized feature unit)
# |modal gains| ≤ this × the sketch's activation scale (N·m per normalized feature unit)
MODAL_GAIN_RANGE = 2.0


def timing_bounds(t: Timing) -> dict[str, tuple[float, float]]:
    """(low, high) of each timing parameter a gait made from a sketch with timing `t` keeps:
    period and pulse durations (s), air ratio."""
    return {
        "period": (PERIOD_RANGE[0] * t.period, PERIOD_RANGE[1] * t.period),
        "air_ratio": (
            max(0.02, t.air_ratio - AIR_RATIO_SPAN),
            min(0.98, t.air_ratio + AIR_RATIO_SPAN),
        ),
        "pulse_air": (PULSE_RANGE[0] * t.pulse_air, PULSE_RANGE[1] * t.pulse_air),
        "pulse_ground": (PULSE_RANGE[0] * t.pulse_ground, PULSE_RANGE[1] * t.pulse_ground),
    }


@dataclass
class Entry:
    name: str
    low: float
    high: float
    initial: float


def feedback_gain_count(sketch: Sketch) -> int:
    """How many feedback gains the sketch's mechanisms add to the parameter space (see
    `_add_feedback`)."""
    mechanisms = sketch.feedback.mechanisms
    hip = len(HIP_GAINS) if "hip" in mechanisms else 0
    modal = (
        sum(len(sketch.phase(ph).priority) * len(FEATURES) for ph in ("air", "ground"))
        if "modal" in mechanisms
        else 0
    )
    return hip + modal


class ParameterSpace:
    def __init__(self, system: GaitSystem, sketch: Sketch):
        self.system, self.sketch = system, sketch
        t = sketch.timing
        self.entries: list[Entry] = [
            Entry(key, low, high, getattr(t, key)) for key, (low, high) in timing_bounds(t).items()
        ]
        self.psi_slots: list[tuple[str, str, int]] = []
        for foot in system.active_feet:
            for phase in ("air", "ground"):
                ps = sketch.phase(phase)
                count = system.mode_count(phase)
                scale = max([abs(v) for v in ps.priority.values()] + [20.0])
                for m in ps.optimized_modes(count):
                    if m in ps.priority:
                        v = ps.priority[m]
                        lo, hi = (abs(v), 3 * scale) if v > 0 else (-3 * scale, -abs(v))
                        self.entries.append(Entry(psi_key(foot, phase, m), lo, hi, v))
                    else:
                        self.entries.append(Entry(psi_key(foot, phase, m), -scale, scale, 0.0))
                    self.psi_slots.append((foot, phase, m))
        init = sketch.initial
        self.entries += [
            Entry("root_height", -0.15, 0.10, init.height),
            Entry("root_pitch", -0.4, 0.4, 0.0),
            Entry("root_speed_x", min(0.0, init.speed), max(4.0, 2 * init.speed), init.speed),
            Entry("root_speed_z", -1.5, 1.5, 0.0),
        ]
        air = system.air_modes
        lowest = range(1, min(init.modes, air.count) + 1)
        # a canonical sketch's numbers are joint dofs, not modes: its initial state spans the lowest
        # modes only
        sketched = (
            set() if sketch.basis == "canonical" else set(sketch.air.optimized_modes(air.count))
        )
        self.pose_modes = sorted(sketched | set(lowest))
        for m in self.pose_modes:
            amp = (
                MAX_JOINT_ANGLE
                / np.abs(air.shapes[system.world.internal_qvel, mode_index(m)]).max()
            )
            omega = 2 * np.pi * air.frequencies_hz[mode_index(m)]
            self.entries.append(Entry(f"q0/{m}", -amp, amp, 0.0))
            self.entries.append(Entry(f"qd0/{m}", -amp * omega, amp * omega, 0.0))
        self._add_feedback(sketch)
        self.floor_geom = mujoco.mj_name2id(system.world.model, mujoco.mjtObj.mjOBJ_GEOM, FLOOR)
        self.low = np.array([e.low for e in self.entries])
        self.high = np.array([e.high for e in self.entries])
        self.index = {e.name: i for i, e in enumerate(self.entries)}

    def _add_feedback(self, sketch: Sketch) -> None:
        """Gains of the sketch's feedback mechanisms, centred on zero (the open-loop controller)."""
        mechanisms = sketch.feedback.mechanisms
        world = self.system.world
        if "hip" in mechanisms:
            bound = HIP_GAIN_RANGE * world.mass() * GRAVITY * world.standing_com_height
            self.entries += [Entry(f"fb/hip/{g}", -bound, bound, 0.0) for g in HIP_GAINS]
        self.modal_feedback_modes: dict[str, list[int]] = {}
        if "modal" in mechanisms:
            for phase in ("air", "ground"):
                prio = sketch.phase(phase).priority
                bound = MODAL_GAIN_RANGE * max([abs(v) for v in prio.values()] + [20.0])
                self.modal_feedback_modes[phase] = sorted(prio)
                self.entries += [
                    Entry(f"fb/modal/{phase}/{m}/{f}", -bound, bound, 0.0)
                    for m in sorted(prio)
                    for f in FEATURES
                ]

    def _decode_feedback(self, v: np.ndarray) -> FeedbackGains:
        gains = FeedbackGains()
        if "fb/hip/" + HIP_GAINS[0] in self.index:
            gains.hip = np.array([v[self.index[f"fb/hip/{g}"]] for g in HIP_GAINS])
        for phase, modes in self.modal_feedback_modes.items():
            if modes:
                K = np.array(
                    [[v[self.index[f"fb/modal/{phase}/{m}/{f}"]] for f in FEATURES] for m in modes]
                )
                gains.modal[phase] = (modes, K)
        return gains

    @property
    def size(self) -> int:
        return len(self.entries)

    def initial(self) -> np.ndarray:
        """Normalized initial guess from the sketch."""
        values = np.array([e.initial for e in self.entries])
        return np.clip((values - self.low) / (self.high - self.low), 0, 1)

    def values(self, x: np.ndarray) -> np.ndarray:
        return self.low + np.clip(x, 0, 1) * (self.high - self.low)

    def decode(self, x: np.ndarray) -> GaitParameters:
        """Normalized vector -> controller parameters."""
        v = self.values(x)
        get = lambda name: float(v[self.index[name]])  # noqa: E731
        system, model = self.system, self.system.world.model
        sparse: dict[tuple[str, str], dict[int, float]] = {}
        for foot, phase, m in self.psi_slots:
            sparse.setdefault((foot, phase), {})[m] = get(psi_key(foot, phase, m))
        activations = system.dense_activations(lambda foot, phase: sparse.get((foot, phase), {}))
        qpos = model.qpos0.copy()
        qvel = np.zeros(model.nv)
        shapes = system.air_modes.shapes
        disp = sum(
            (get(f"q0/{m}") * shapes[:, mode_index(m)] for m in self.pose_modes), np.zeros(model.nv)
        )
        vel = sum(
            (get(f"qd0/{m}") * shapes[:, mode_index(m)] for m in self.pose_modes),
            np.zeros(model.nv),
        )
        root = system.world.root
        # root translation is set below; modes keep joints and rotation
        disp[list(root.translation_qvel)] = 0.0
        mujoco.mj_integratePos(model, qpos, disp, 1.0)
        root.lift_and_pitch(qpos, get("root_height"), get("root_pitch"))
        clip_to_joint_ranges(model, qpos)
        # m: start on the floor, not inside it
        sunk = floor_penetration(model, qpos, self.floor_geom)
        root.lift_and_pitch(qpos, sunk, 0.0)
        # many fast modes at their bounds could sum past it
        qvel[:] = np.clip(vel, -MAX_SPEED, MAX_SPEED)
        for adr, name in (
            (root.forward_qvel, "root_speed_x"),
            (root.vertical_qvel, "root_speed_z"),
        ):
            if adr is not None:
                qvel[adr] += get(name)
        return GaitParameters(
            period=get("period"),
            air_ratio=get("air_ratio"),
            pulse_air=get("pulse_air"),
            pulse_ground=get("pulse_ground"),
            trigger=self.sketch.timing.trigger,
            activations=activations,
            qpos0=qpos,
            qvel0=qvel,
            feedback=self._decode_feedback(v),
        )
