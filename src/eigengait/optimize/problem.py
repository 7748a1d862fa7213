"""A sketch bound to its character: the gait system and the parameter space to optimize."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from eigengait.character import load_character
from eigengait.control.gait import GaitSystem
from eigengait.control.sketch import Sketch, check_modes
from eigengait.optimize.parameters import ParameterSpace


@dataclass
class Problem:
    sketch: Sketch
    system: GaitSystem
    space: ParameterSpace

    @classmethod
    def from_sketch(cls, sketch: Sketch, source: str | Path | None = None, gravity: bool = True) -> "Problem":
        from eigengait.sim.world import WorldOptions
        character = load_character(sketch.character)
        feet = sketch.feet or character.meta.gait_order
        system = GaitSystem(character, sketch.relax_pose, feet, sketch.symmetric, sketch.basis, sketch.torque_limit,
                            WorldOptions(gravity=gravity))
        check_modes(sketch, {"air": system.mode_count("air"), "ground": system.mode_count("ground")}, source)
        return cls(sketch=sketch, system=system, space=ParameterSpace(system, sketch))
