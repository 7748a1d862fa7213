"""A sketch or a controller file bound to its character: the gait system (world, mode bases per
phase and foot, pulse controller)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from eigengait.character import load_character
from eigengait.control.gait import GaitSystem
from eigengait.control.sketch import Sketch, check_modes
from eigengait.sim.world import WorldOptions

if TYPE_CHECKING:
    from eigengait.control.controller import ControllerFile


def gait_system(
    spec: Sketch | ControllerFile, gravity: bool = True, source: str | Path | None = None
) -> GaitSystem:
    """The gait system a sketch or a controller file names (one modal analysis per phase and foot),
    mode numbers not yet checked; a sketch that names no feet takes the character's gait order. An
    error in the feet names `source`."""
    character = load_character(spec.character)
    feet = (spec.feet or character.meta.gait_order) if isinstance(spec, Sketch) else spec.feet
    return GaitSystem(
        character,
        spec.relax_pose,
        feet,
        spec.symmetric,
        spec.basis,
        spec.torque_limit,
        WorldOptions(gravity=gravity, activation_time=spec.activation_time),
        source,
        spec.swing_servo,
        spec.stance_partners,
        spec.simbicon,
    )


def mode_counts(system: GaitSystem) -> dict[str, int]:
    return {"air": system.mode_count("air"), "ground": system.mode_count("ground")}


def bind_sketch(
    sketch: Sketch, source: str | Path | None = None, gravity: bool = True
) -> GaitSystem:
    """The sketch's gait system; every mode number the sketch names must exist (error names
    `source`)."""
    system = gait_system(sketch, gravity, source)
    check_modes(sketch, mode_counts(system), source)
    return system
