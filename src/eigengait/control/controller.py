"""The controller file: a versioned JSON document that names its character and relax pose.

It holds the pulse state machine's values (period T s, air ratio α, pulse durations δ s, activations
ψ in N·m per foot, phase and mode number), the initial state (q₀, q̇₀ in MuJoCo's coordinates) and a
fingerprint of the lowest mode frequencies, so a controller applied to another character or relax
pose is refused.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from eigengait.control.activations import dense_to_sparse
from eigengait.control.feedback import (
    EVENT_FEATURES,
    FEATURES,
    HIP_GAINS,
    EventGains,
    FeedbackGains,
)
from eigengait.control.legacy_modes import LEGACY_FORMAT, in_canonical_modes
from eigengait.control.lookahead import (
    EFFORT_WEIGHT,
    LIGHT_LIMB_SHARE,
    SAMPLES,
    SLIP_WEIGHT,
    SPEED_WEIGHT,
    LookaheadSettings,
)
from eigengait.control.sketch import PhaseSketch, Sketch
from eigengait.control.simbicon import SimbiconSettings
from eigengait.control.swing_servo import ServoSettings

from eigengait.files import dump, read_mapping, validate
from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.errors import UserInputError
from eigengait.json_text import finite
from eigengait.sim.stepping import MAX_CONTROL, MAX_SPEED
from eigengait.sim.world import MAX_ACTIVATION_TIME

# format 2 numbers the modes in the canonical bases; format 1 files are read as they played
# (control/legacy_modes.py)
FORMAT_VERSION = 2
FINGERPRINT_MODES = 6
# a sketch phase's `allowed: null` means every mode: the plans keep those that exist
MODES_AT_MOST = 10_000


def _check_gain_rows(rows: dict[int, list[float]], features: tuple[str, ...], where: str) -> None:
    """Each mode's row of gains has one gain per feature (the message names `where`)."""
    for m, row in rows.items():
        if len(row) != len(features):
            raise ValueError(f"{where}mode {m} needs {len(features)} gains ({', '.join(features)})")


def _gain_matrix(rows: dict[int, list[float]]) -> tuple[list[int], np.ndarray]:
    """(sorted mode numbers, their gains as rows) of a file's mode -> gains mapping."""
    modes = sorted(rows)
    return modes, np.array([rows[m] for m in modes])


def _gain_rows(modes: list[int], K: np.ndarray) -> dict[int, list[float]]:
    """A file's mode -> gains mapping of modes and their gain rows."""
    return {int(m): [float(x) for x in row] for m, row in zip(modes, K)}


class EventFile(BaseModel):
    """The ``event`` mechanism: target forward speed (m/s) and, per phase, mode number -> its ten
    gains (N·m per normalized unit, in EVENT_FEATURES order)."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    speed: float = Field(ge=-MAX_SPEED, le=MAX_SPEED)
    air: dict[int, list[float]] = Field(default_factory=dict)
    ground: dict[int, list[float]] = Field(default_factory=dict)

    @field_validator("air", "ground")
    @classmethod
    def _ten_features(cls, v):
        _check_gain_rows(v, EVENT_FEATURES, "")
        return v

    def gains(self) -> EventGains:
        phases = {
            ph: _gain_matrix(rows)
            for ph, rows in (("air", self.air), ("ground", self.ground))
            if rows
        }
        return EventGains(speed=self.speed, phases=phases)

    @classmethod
    def of(cls, gains: EventGains) -> "EventFile":
        rows = {ph: _gain_rows(modes, K) for ph, (modes, K) in gains.phases.items()}
        return cls(speed=float(gains.speed), **rows)


class FeedbackFile(BaseModel):
    """Balance-feedback gains (N·m per normalized feature unit, see control/feedback.py); empty:
    open loop."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    hip: dict[Literal[HIP_GAINS], float] | None = None
    modal: dict[Literal["air", "ground"], dict[int, list[float]]] = Field(default_factory=dict)
    event: EventFile | None = None

    @field_validator("hip")
    @classmethod
    def _all_hip_gains(cls, v):
        if v is not None and set(v) != set(HIP_GAINS):
            raise ValueError(f"hip needs all of {', '.join(HIP_GAINS)}")
        return v

    @field_validator("modal")
    @classmethod
    def _eight_features(cls, v):
        for phase, rows in v.items():
            _check_gain_rows(rows, FEATURES, f"{phase} ")
        return v

    def gains(self) -> FeedbackGains:
        modal = {ph: _gain_matrix(rows) for ph, rows in self.modal.items()}
        hip = np.array([self.hip[g] for g in HIP_GAINS]) if self.hip is not None else None
        event = self.event.gains() if self.event is not None else None
        return FeedbackGains(hip=hip, modal=modal, event=event)

    @classmethod
    def of(cls, gains: FeedbackGains) -> "FeedbackFile":
        hip = {g: float(x) for g, x in zip(HIP_GAINS, gains.hip)} if gains.hip is not None else None
        modal = {ph: _gain_rows(modes, K) for ph, (modes, K) in gains.modal.items()}
        event = EventFile.of(gains.event) if gains.event is not None else None
        return cls(hip=hip, modal=modal, event=event)


class LookaheadFile(BaseModel):
    """How `play` searches each state start's pulses (see control/lookahead.py); absent: the gait
    plays as is."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    speed: float = Field(ge=-MAX_SPEED, le=MAX_SPEED)  # m/s, target forward COM speed
    samples: int = Field(SAMPLES, ge=2, le=4096)  # plans per decision
    horizon_cycles: float = Field(2.0, gt=0, le=50)
    spread: float = Field(0.5, gt=0, le=10)
    refinements: int = Field(1, ge=0, le=10)
    modes: int | None = Field(None, ge=1, le=10_000)
    plan_substeps: int = Field(2, ge=1, le=16)
    seed: int = 0
    feedback: bool = False  # plans and played motion add the controller's balance feedback
    # plans move only the sketch's priority and allowed modes (the file's `sketch`)
    in_sketch: bool = False
    # plans scale their torque on a joint off the feet's chains by its subtree's share of the
    # body's mass over this share, at most 1 (0: plans move every joint in full)
    min_mass_share: float = Field(LIGHT_LIMB_SHARE, ge=0, le=1)
    # weight of the plans' speed term (higher: the target speed held harder)
    speed_weight: float = Field(SPEED_WEIGHT, ge=0, le=1000)
    # weight of the plans' sliding-feet term (0: the plans do not look at the feet)
    slip_weight: float = Field(SLIP_WEIGHT, ge=0, le=1000)
    # weight of the plans' size (0: any of the plans that score alike may win)
    effort_weight: float = Field(EFFORT_WEIGHT, ge=0, le=1000)
    # degrees from upright past which a plan counts as falling (None: the character's fall rule)
    max_tilt_deg: float | None = Field(None, gt=0, le=180)

    def settings(self, sketch: dict[str, PhaseSketch] | None = None) -> LookaheadSettings:
        """The runner's settings; with `in_sketch`, the modes of `sketch` (the controller file's)
        per phase."""
        values = self.model_dump(exclude={"in_sketch"})
        if self.in_sketch:
            values["chosen"] = {
                ph: tuple(sketch[ph].optimized_modes(MODES_AT_MOST)) for ph in ("air", "ground")
            }
        return LookaheadSettings(**values)

    @classmethod
    def of(cls, settings: LookaheadSettings | None) -> "LookaheadFile | None":
        if settings is None:
            return None
        values = {k: v for k, v in settings.__dict__.items() if k != "chosen"}
        return cls(**values, in_sketch=settings.chosen is not None)


class ControllerFile(BaseModel):
    """Every number finite; torques and initial speeds within what the simulation can take."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    eigengait_controller: int = FORMAT_VERSION
    name: str = ""
    character: str
    relax_pose: str | dict[str, list[float] | float] = "default"
    feet: list[str]
    symmetric: bool
    basis: Literal["modal", "canonical"] = "modal"
    torque_limit: float = Field(gt=0, le=MAX_CONTROL)
    activation_time: float | None = Field(
        None, gt=0, le=MAX_ACTIVATION_TIME
    )  # s: the motors' first-order lag (none: at once)
    period: float = Field(gt=0)
    air_ratio: float = Field(ge=0, le=1)
    pulse_air: float = Field(gt=0)
    pulse_ground: float = Field(gt=0)
    trigger: Literal["clock", "touchdown"] = "clock"
    activations: dict[str, dict[str, dict[int, float]]]  # foot -> phase -> mode number -> ψ (N·m)
    initial_qpos: list[float]
    initial_qvel: list[Annotated[float, Field(ge=-MAX_SPEED, le=MAX_SPEED)]]
    air_frequencies_hz: list[float]  # fingerprint of the character at its relax pose
    feedback: FeedbackFile = Field(default_factory=lambda: FeedbackFile())
    # the swing-foot servo added to every simulation of the gait (none: pulses and feedback alone)
    swing_servo: ServoSettings | None = None
    # SIMBICON's balance layer added to every simulation of the gait (control/simbicon.py)
    simbicon: SimbiconSettings | None = None
    # foot -> feet pinned with it in its ground modes (control/gait.py)
    stance_partners: dict[str, list[str]] = Field(default_factory=dict)
    lookahead: LookaheadFile | None = None
    # the modes of the sketch it was made from
    sketch: dict[Literal["air", "ground"], PhaseSketch] | None = None
    metrics: dict[str, float | bool | int] = Field(default_factory=dict)
    # the build the metrics were played on (sim/build.py)
    measured_on: dict[str, str | list[str]] | None = None

    def planner(self) -> LookaheadSettings | None:
        """The lookahead settings `play` uses, or None when the controller plays its pulses as they
        are."""
        return None if self.lookahead is None else self.lookahead.settings(self.sketch)

    @model_validator(mode="after")
    def _sketch_for_in_sketch_plans(self):
        if self.lookahead is not None and self.lookahead.in_sketch and self.sketch is None:
            raise ValueError(
                "lookahead.in_sketch needs the sketch's modes: add 'sketch' or set in_sketch: false"
            )
        return self

    @model_validator(mode="after")
    def _event_feedback_without_plans(self):
        if self.lookahead is not None and self.feedback.event is not None:
            raise ValueError(
                "feedback.event corrects the pulses the plans would replace: remove 'lookahead' "
                "or 'feedback.event'"
            )
        return self

    @model_validator(mode="after")
    def _balance_layer_without_plans(self):
        if self.lookahead is not None and self.simbicon is not None:
            raise ValueError(
                "the plans are made without the SIMBICON layer: remove 'lookahead' or 'simbicon'"
            )
        return self

    @model_validator(mode="after")
    def _lookahead_on_the_clock(self):
        if self.lookahead is not None and self.trigger != "clock":
            raise ValueError(
                "lookahead plays the states on the clock: remove 'lookahead' or set trigger: clock"
            )
        return self


def to_file(
    system: GaitSystem,
    p: GaitParameters,
    name: str = "",
    metrics: dict | None = None,
    lookahead: LookaheadSettings | None = None,
    sketch: dict[str, PhaseSketch] | None = None,
) -> ControllerFile:
    """The file of controller `p`; `sketch` (its sketch's modes, `sketch_modes`) is kept for
    `play`'s figures."""
    acts: dict[str, dict[str, dict[int, float]]] = {}
    for (foot, phase), psi in p.activations.items():
        acts.setdefault(foot, {})[phase] = dense_to_sparse(psi)
    return ControllerFile(
        name=name,
        character=system.character.name
        if _is_builtin(system)
        else str(system.character.reference.resolve()),
        relax_pose=system.pose,
        feet=system.feet,
        symmetric=system.mirror is not None,
        basis=system.basis,
        torque_limit=system.torque_limit,
        activation_time=system.options.activation_time,
        swing_servo=system.swing_servo,
        simbicon=system.simbicon,
        stance_partners=system.stance_partners,
        period=p.period,
        air_ratio=p.air_ratio,
        pulse_air=p.pulse_air,
        pulse_ground=p.pulse_ground,
        trigger=p.trigger,
        activations=acts,
        initial_qpos=[float(v) for v in p.qpos0],
        initial_qvel=[float(v) for v in p.qvel0],
        air_frequencies_hz=[float(f) for f in system.air_modes.frequencies_hz[:FINGERPRINT_MODES]],
        feedback=FeedbackFile.of(p.feedback),
        lookahead=LookaheadFile.of(lookahead),
        sketch=sketch,
        metrics={k: v for k, v in finite(metrics or {}).items() if v is not None},
    )


def sketch_modes(sketch: Sketch) -> dict[str, PhaseSketch]:
    """The priority/allowed/excluded modes of each phase of a sketch, as a controller file keeps
    them."""
    return {"air": sketch.air, "ground": sketch.ground}


def _is_builtin(system: GaitSystem) -> bool:
    from eigengait.character.library import library_dir

    return system.character.path.parent == library_dir()


def save_controller(controller: ControllerFile, path: Path) -> None:
    dump(controller, path)


def load_controller(path: str | Path) -> ControllerFile:
    path = Path(path)
    data = read_mapping(path)
    if data.get("eigengait_controller") not in (None, LEGACY_FORMAT, FORMAT_VERSION):
        raise UserInputError(
            f"unsupported controller version {data.get('eigengait_controller')}",
            file=path,
            field="eigengait_controller",
        )
    return validate(ControllerFile, data, path, "regenerate it with `eigengait optimize`")


def to_parameters(
    controller: ControllerFile, system: GaitSystem, source: str | Path = "controller"
) -> GaitParameters:
    """Check the controller fits the system (character, relax pose, sizes) and return its
    parameters."""
    model = system.world.model
    freqs = system.air_modes.frequencies_hz[:FINGERPRINT_MODES]
    same_pose = controller.relax_pose == system.pose
    same_modes = np.allclose(freqs, controller.air_frequencies_hz, rtol=1e-4)
    if not same_pose:
        raise UserInputError(
            f"this controller was made for character '{controller.character}' at relax pose "
            f"'{controller.relax_pose}', not for '{system.character.name}' at '{system.pose}'",
            file=source,
            field="character / relax_pose",
            fix="load it with its own character and relax pose, or optimize a new one",
        )
    if not same_modes:
        raise UserInputError(
            f"this controller was made for character '{controller.character}' with its lowest air "
            f"modes at {_hz(controller.air_frequencies_hz)} Hz; '{system.character.name}' at relax "
            f"pose '{system.pose}' has them at {_hz(freqs)} Hz (another relax pose, or the "
            "character's masses, joints or stiffness have changed since), so the controller's mode "
            "activations would not mean the motion they were optimized for",
            file=source,
            field="character / relax_pose",
            fix="load it with the character and relax pose it was made for, or optimize a new one",
        )
    for field, values, size in (
        ("initial_qpos", controller.initial_qpos, model.nq),
        ("initial_qvel", controller.initial_qvel, model.nv),
    ):
        if len(values) != size:
            raise UserInputError(
                f"{field} has {len(values)} values; character '{system.character.name}' needs "
                f"{size}",
                file=source,
                field=field,
                fix="regenerate the controller with `eigengait optimize`",
            )
    activations = system.dense_activations(
        lambda foot, phase: controller.activations.get(foot, {}).get(phase, {}), source
    )
    params = GaitParameters(
        period=controller.period,
        air_ratio=controller.air_ratio,
        pulse_air=controller.pulse_air,
        pulse_ground=controller.pulse_ground,
        trigger=controller.trigger,
        activations=activations,
        qpos0=np.array(controller.initial_qpos),
        qvel0=np.array(controller.initial_qvel),
        feedback=controller.feedback.gains(),
    )
    if controller.eigengait_controller == LEGACY_FORMAT:
        return in_canonical_modes(params, system, source)
    return params


def _hz(frequencies) -> str:
    """The first three frequencies as text, e.g. "1.70, 1.77, 2.07"."""
    return ", ".join(f"{f:.2f}" for f in list(frequencies)[:3])
