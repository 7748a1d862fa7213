"""The sketch: what an animator chooses before optimizing (thesis §4.3, §5.2).

```yaml
eigengait_sketch: 2
character: humanoid          # built-in name, MJCF path or character sidecar (NAME.eigengait.yaml)
relax_pose: default          # preset name or {joint: [rx, ry, rz] degrees}
feet: [left, right]          # stance order (default: the character's gait_order)
stance_partners: {}          # foot -> feet also on the floor in its ground state (a trot: its
                             # diagonal partner), pinned with it in its ground modes
symmetric: true              # second foot mirrors the first
basis: modal                 # or canonical (one torque per joint dof: the thesis's comparison)
air:    {priority: {2: 30, 10: -20, 11: 20}, allowed: [1, 3, 4], excluded: [5]}
ground: {priority: {2: 40, 3: 60, 4: 10, 9: 15}, allowed: [1, 5, 6]}
timing: {period: 0.8, air_ratio: 0.4, pulse_air: 0.1, pulse_ground: 0.12}   # s, -, s, s
initial: {speed: 1.5, height: 0.0}                                          # m/s forward, m
```
Mode numbers start at 1 (lowest non-rigid mode). Priority activations ψ are in N·m (unit-norm torque
basis). `allowed` omitted: every mode not excluded may be used. Modes neither priority nor allowed
get ψ = 0.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from eigengait.control.legacy_modes import mode_signs
from eigengait.control.simbicon import SimbiconSettings
from eigengait.control.swing_servo import ServoSettings
from eigengait.files import read_mapping, validate
from eigengait.errors import UserInputError
from eigengait.sim.world import MAX_ACTIVATION_TIME

# format 2 signs the priority activations for the canonical mode bases; format 1 files are
# re-signed on reading (control/legacy_modes.py)
FORMAT_VERSION = 2
LEGACY_FORMAT = 1


class PhaseSketch(BaseModel):
    model_config = ConfigDict(extra="forbid")
    priority: dict[int, float] = Field(default_factory=dict)
    allowed: list[int] | None = None
    excluded: list[int] = Field(default_factory=list)

    @model_validator(mode="after")
    def _disjoint(self):
        for m in self.priority:
            if m in self.excluded:
                raise ValueError(f"mode {m} is both priority and excluded")
            if self.priority[m] == 0:
                raise ValueError(f"priority mode {m} needs a non-zero activation")
        for m in self.allowed or []:
            if m in self.excluded:
                raise ValueError(f"mode {m} is both allowed and excluded")
        for m in [*self.priority, *(self.allowed or []), *self.excluded]:
            if m < 1:
                raise ValueError(f"mode numbers start at 1, got {m}")
        return self

    def optimized_modes(self, count: int) -> list[int]:
        """Priority + allowed mode numbers (1-based), sorted."""
        allowed = (
            self.allowed
            if self.allowed is not None
            else [m for m in range(1, count + 1) if m not in self.excluded]
        )
        return sorted(set(self.priority) | set(allowed))


class Timing(BaseModel):
    model_config = ConfigDict(extra="forbid")
    period: float = Field(0.8, gt=0, description="cycle period T (s)")
    air_ratio: float = Field(0.5, ge=0, le=1, description="air share α of each foot's time")
    pulse_air: float = Field(0.1, gt=0, description="air pulse duration δa (s)")
    pulse_ground: float = Field(0.1, gt=0, description="ground pulse duration δc (s)")
    trigger: Literal["clock", "touchdown"] = Field(
        "clock", description="what starts a ground state: the fixed clock, or the foot's touchdown"
    )


class Initial(BaseModel):
    model_config = ConfigDict(extra="forbid")
    speed: float = Field(1.0, description="initial forward root speed (m/s)")
    height: float = Field(0.0, description="initial root height above the standing height (m)")
    modes: int = Field(
        12, ge=0, description="lowest air modes spanning the optimized initial pose and velocity"
    )


class Targets(BaseModel):
    """Soft-constraint thresholds (thesis Eqs. 4.11–4.14 values by default)."""

    model_config = ConfigDict(extra="forbid")
    min_speed: float = 0.5  # m/s, COM forward speed at every sample
    mean_speed: float = 2.0  # m/s, mean forward COM speed
    lateral_speed: float = 0.25  # m/s, |mean lateral COM speed|
    vertical_speed: float = 0.25  # m/s, |mean vertical COM speed|
    joint_speed: float = 20.0  # rad/s, every joint dof at every sample
    energy: float = 5e5  # (N·m)², mean squared active torque
    # m per stance (`play`'s stance_slip_m rule); None: not charged
    stance_slip: float | None = Field(None, gt=0)
    # feet that touch the ground together (a trot's diagonal pairs); charged per cycle in which
    # one foot of a pair is down while the other is not for more than `pair_tolerance` of it
    paired_feet: list[tuple[str, str]] = Field(default_factory=list)
    pair_tolerance: float = Field(0.1, gt=0, lt=1)
    # max |φᵢ| accepted as cyclic (rad, m; velocities × 0.1 s)
    cycle_tolerance: float = Field(0.2, gt=0)


class Feedback(BaseModel):
    """Balance feedback optimized with the pulses (see control/feedback.py) and the optimization
    horizon."""

    model_config = ConfigDict(extra="forbid")
    mechanisms: list[Literal["hip", "modal"]] = Field(
        default_factory=lambda: ["hip"], description="feedback mechanisms; [] for open loop"
    )
    horizon_cycles: int = Field(
        5, ge=1, le=20, description="cycles simulated per candidate, no reset"
    )


class Sketch(BaseModel):
    model_config = ConfigDict(extra="forbid")
    eigengait_sketch: int = FORMAT_VERSION
    description: str = ""
    character: str
    relax_pose: str | dict[str, list[float] | float] = "default"
    feet: list[str] | None = None
    symmetric: bool = True
    basis: Literal["modal", "canonical"] = "modal"
    air: PhaseSketch = Field(default_factory=PhaseSketch)
    ground: PhaseSketch = Field(default_factory=PhaseSketch)
    timing: Timing = Field(default_factory=Timing)
    initial: Initial = Field(default_factory=Initial)
    targets: Targets = Field(default_factory=Targets)
    feedback: Feedback = Field(default_factory=Feedback)
    torque_limit: float = Field(400.0, gt=0, description="N·m per dof")
    activation_time: float | None = Field(
        None,
        gt=0,
        le=MAX_ACTIVATION_TIME,
        description="s: each torque follows its command through a first-order lag (none: at once)",
    )
    swing_servo: ServoSettings | None = Field(
        None,
        description="a swing-foot servo in every simulation of the gait (control/swing_servo.py)",
    )
    simbicon: SimbiconSettings | None = Field(
        None,
        description="SIMBICON's balance layer in every simulation (control/simbicon.py)",
    )
    stance_partners: dict[str, list[str]] = Field(
        default_factory=dict,
        description=(
            "foot -> feet on the floor with it in its ground state, pinned with it in its ground "
            "modes (a trot's diagonal partner)"
        ),
    )

    @model_validator(mode="after")
    def _version(self):
        if self.eigengait_sketch not in (LEGACY_FORMAT, FORMAT_VERSION):
            raise ValueError(f"unsupported sketch version {self.eigengait_sketch}")
        return self

    def phase(self, name: str) -> PhaseSketch:
        return self.air if name == "air" else self.ground


def load_sketch(path: str | Path) -> Sketch:
    """Read a sketch file (JSON or YAML); a relative character path is taken relative to the
    file."""
    path = Path(path)
    sketch = validate(
        Sketch, read_mapping(path), path, "see the sketch format in the README (Sketches)"
    )
    if sketch.character.endswith((".xml", ".yaml")) and not Path(sketch.character).is_absolute():
        sketch.character = str((path.parent / sketch.character).resolve())
    if sketch.eigengait_sketch == LEGACY_FORMAT:
        return _in_canonical_modes(sketch, path)
    return sketch


def _in_canonical_modes(sketch: Sketch, path: Path) -> Sketch:
    """A format-1 sketch as format 2: each priority activation on a mode whose sign the canonical
    bases flipped (on this machine) negated, so it asks for the torques it asked for."""
    update: dict = {"eigengait_sketch": FORMAT_VERSION}
    if sketch.basis == "modal":
        signs = mode_signs(
            sketch.character,
            sketch.relax_pose,
            sketch.feet,
            sketch.symmetric,
            sketch.stance_partners,
            path,
        )
        for phase, sign in signs.items():
            old = sketch.phase(phase)
            priority = {
                m: v * (float(sign[m - 1]) if m <= len(sign) else 1.0)
                for m, v in old.priority.items()
            }
            update[phase] = old.model_copy(update={"priority": priority})
    return sketch.model_copy(update=update)


def check_modes(sketch: Sketch, counts: dict[str, int], path: str | Path | None = None) -> None:
    """Every mode number must exist in its phase."""
    for phase, count in counts.items():
        p = sketch.phase(phase)
        for m in [*p.priority, *(p.allowed or []), *p.excluded]:
            if m > count:
                raise UserInputError(
                    f"mode {m} does not exist: the {phase} phase has {count} modes",
                    file=path,
                    field=f"{phase}",
                    fix=f"use mode numbers 1..{count}",
                )
