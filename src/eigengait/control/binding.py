"""A sketch bound to its character: the gait system (world, mode bases per phase and foot, pulse controller)."""

from __future__ import annotations

from pathlib import Path

from eigengait.character import load_character
from eigengait.control.gait import GaitSystem
from eigengait.control.sketch import Sketch, check_modes
from eigengait.sim.world import WorldOptions


def sketch_system(sketch: Sketch, gravity: bool = True, source: str | Path | None = None) -> GaitSystem:
    """The sketch's gait system (one modal analysis per phase and foot), mode numbers not yet checked; an error in
    the sketch's feet names `source`."""
    character = load_character(sketch.character)
    feet = sketch.feet or character.meta.gait_order
    return GaitSystem(
        character,
        sketch.relax_pose,
        feet,
        sketch.symmetric,
        sketch.basis,
        sketch.torque_limit,
        WorldOptions(gravity=gravity),
        source,
    )


def mode_counts(system: GaitSystem) -> dict[str, int]:
    return {"air": system.mode_count("air"), "ground": system.mode_count("ground")}


def bind_sketch(sketch: Sketch, source: str | Path | None = None, gravity: bool = True) -> GaitSystem:
    """The sketch's gait system; every mode number the sketch names must exist (error names `source`)."""
    system = sketch_system(sketch, gravity, source)
    check_modes(sketch, mode_counts(system), source)
    return system
