"""The command line's words for library errors: a parameter named in an `EigengaitError` becomes its
flag.

Library functions name their own Python parameters: `field="robustness"`,
`fix="pass stiffness='auto'"`. A user of the command line typed flags, so before printing an error
the CLI rewrites, through `FLAGS`:

- the field, when the error concerns no file (a field of a file is that file's key, not a
  parameter), including fields naming several parameters at once (`"width/height"`
  → `"--width/--height"`);
- keyword arguments written in the message or the fix: `name='text'` → `--flag text`, `name=3`
  → `--flag 3`, `name=True` → `--flag`.
"""

from __future__ import annotations

import copy
import re

from eigengait.errors import EigengaitError

#: library parameter → the flag that sets it, for every parameter a library error may name
FLAGS = {
    "activation_time": "--activation-time",
    "base_hz": "--base-hz",
    "bvh_units": "--bvh-units",
    "count": "--modes",  # render.palette's number of modes
    "evaluator": "--evaluator",
    "force": "--force",
    "fps": "--fps",
    "height": "--height",
    "host": "--host",
    "integrator": "--integrator",
    "mapping": "--mapping",
    "method": "--method",
    "mix": "--mix",
    "phase": "--phase",
    "port": "--port",
    "push": "--push",
    "relax": "--relax",
    "resume": "--resume",
    "robustness": "--robustness",
    "seed": "--seed",
    "seconds": "--seconds",
    "speed": "--speed",
    "start_frame": "--start-frame",
    "stiffness": "--stiffness",
    "time_step": "--time-step",
    "tolerance": "--tolerance",
    "width": "--width",
}

_KEYWORD = re.compile(
    r"(?<![\w.-])(" + "|".join(FLAGS) + r")=(?:'([^']*)'|(True)\b|([-+]?\d[\w.]*))"
)


def keywords_as_flags(text: str | None) -> str | None:
    """`name='v'`, `name=3` and `name=True` of known parameters written as flags."""
    if not text:
        return text

    def flag(match: re.Match) -> str:
        name, quoted, true, number = match.groups()
        return FLAGS[name] if true else f"{FLAGS[name]} {quoted if quoted is not None else number}"

    return _KEYWORD.sub(flag, text)


def _field(field: str | None) -> str | None:
    """The flag(s) of a field naming parameters ("a" or "a/b"), else the field unchanged."""
    if not field:
        return field
    names = field.split("/")
    return "/".join(FLAGS[n] for n in names) if all(n in FLAGS for n in names) else field


def for_command_line(error: EigengaitError) -> EigengaitError:
    """The same error (same type) in the command line's words; the original is left unchanged."""
    shown = copy.copy(error)
    if error.file is None:
        shown.field = _field(error.field)
    shown.message = keywords_as_flags(error.message)
    shown.fix = keywords_as_flags(error.fix)
    shown.args = (str(shown),)
    return shown


__all__ = ["FLAGS", "for_command_line", "keywords_as_flags"]
