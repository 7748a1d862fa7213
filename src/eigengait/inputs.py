"""Text files the user gives: read as UTF-8, else Latin-1; an unreadable file is a
`UserInputError`."""

from __future__ import annotations

import math
from pathlib import Path

from eigengait.errors import UserInputError


def read_text(path: Path) -> str:
    """The file's text, decoded as UTF-8 or, failing that, Latin-1 (which decodes any bytes)."""
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise UserInputError(
            f"cannot read the file ({exc.strerror or exc.__class__.__name__})", file=path
        ) from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("latin-1")


def check_range(
    value: float | None,
    option: str,
    low: float,
    high: float = math.inf,
    unit: str = "",
    fix: str | None = None,
) -> None:
    """One clear error unless `value` (None: not given) is finite and within [low, high]; `fix`
    replaces the generic advice when the range has a meaning worth stating."""
    if value is None:
        return
    if not (math.isfinite(value) and low <= value <= high):
        span = f"at least {low:g}" if high == math.inf else f"between {low:g} and {high:g}"
        raise UserInputError(
            f"{option} {value} is out of range",
            field=option,
            fix=fix or f"use a finite value {span}{(' ' + unit) if unit else ''}",
        )


def check_choice(value: str, choices: tuple[str, ...] | list[str], what: str, field: str) -> None:
    """One clear error, naming `field` and the choices, unless `value` is one of `choices`; `what`
    names the kind of thing in the message ("integrator": "unknown integrator 'x'.")."""
    if value not in choices:
        raise UserInputError(
            f"unknown {what} '{value}'.", field=field, fix=f"use one of: {', '.join(choices)}."
        )
