"""The dissertation's six example scenes, shipped as ``.PAR`` scripts (and the table
``mesa.obt``)."""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

from eigengait.errors import UserInputError

#: example name -> (script file, one-line description)
EXAMPLES = {
    "curtain": ("curtain.PAR", "hanging curtain, 20x20, top row fixed (figs. 6.1-6.2)"),
    "paper": ("paper.PAR", "paper torn from a billboard, hanging by a corner (figs. 6.3-6.4)"),
    "wind": ("wind.PAR", "square surface in the wind, three corners fixed (figs. A2.1-A2.2)"),
    "theatre": ("theatre.PAR", "two theatre curtains closing and reopening (figs. A2.3-A2.4)"),
    "cardboard": ("cardboard.PAR", "stiff cardboard torn from a billboard (figs. A2.5-A2.6)"),
    "tablecloth": ("tablecloth.PAR", "tablecloth falling on a table, mesa.obt (figs. A2.7-A2.8)"),
}


def example_path(name: str) -> Path:
    """Path of the shipped script ``name``."""
    if name not in EXAMPLES:
        raise UserInputError(
            f"no shipped example named '{name}'.",
            field="SCRIPT",
            fix=f"use a .PAR path or one of: {', '.join(EXAMPLES)}.",
        )
    return Path(str(files("eigengait.cloth").joinpath("examples", EXAMPLES[name][0])))


def resolve_script(script: str) -> Path:
    """A .PAR path as given, or the shipped example of that name."""
    path = Path(script)
    if path.suffix or path.exists() or script not in EXAMPLES:
        if not path.exists() and script not in EXAMPLES:
            raise UserInputError(
                "the script does not exist and is not a shipped example name.",
                file=script,
                fix=f"give a .PAR path or one of: {', '.join(EXAMPLES)}.",
            )
        return path
    return example_path(script)
