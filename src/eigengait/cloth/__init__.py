"""Deformable surfaces by particle dynamics: a rebuild of Nedel's FLEX3D (1993).

Read a ``.PAR`` script, build the mass–spring model, integrate it with one of four integrators,
collide with ``.OBT`` obstacles, write ``.OBT``/``.OBJ`` frames and a video, and analyse the
surface's vibration modes. See docs/cloth.md.
"""

from eigengait.cloth.library import EXAMPLES, example_path, resolve_script
from eigengait.cloth.model import ClothModel, script_model, surface_model
from eigengait.cloth.obt import Mesh, read_obt, write_obt
from eigengait.cloth.par import Script, SurfaceSpec, parse_par, read_par
from eigengait.cloth.simulate import Frame, Simulation, run_frames
from eigengait.cloth.stability import StepSizeWarning, stable_step

__all__ = [
    "EXAMPLES",
    "ClothModel",
    "Frame",
    "Mesh",
    "Script",
    "Simulation",
    "StepSizeWarning",
    "SurfaceSpec",
    "example_path",
    "parse_par",
    "read_obt",
    "read_par",
    "resolve_script",
    "run_frames",
    "script_model",
    "stable_step",
    "surface_model",
    "write_obt",
]
