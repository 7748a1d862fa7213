"""A sketch bound to its character (`control.binding`) plus the parameter space to optimize."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from eigengait.control.binding import bind_sketch
from eigengait.control.gait import GaitSystem
from eigengait.control.sketch import Sketch
from eigengait.optimize.parameters import ParameterSpace


@dataclass
class Problem:
    sketch: Sketch
    system: GaitSystem
    space: ParameterSpace

    @classmethod
    def from_sketch(
        cls, sketch: Sketch, source: str | Path | None = None, gravity: bool = True
    ) -> "Problem":
        system = bind_sketch(sketch, source, gravity)
        return cls(sketch=sketch, system=system, space=ParameterSpace(system, sketch))
