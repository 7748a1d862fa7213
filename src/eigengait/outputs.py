"""Output files the user asked for: never overwrite one silently."""

from __future__ import annotations

from pathlib import Path

from eigengait.errors import UserInputError


def refuse_existing(paths: list[Path | None], force: bool) -> None:
    """Raise if any given output path exists and `force` is not set."""
    for path in paths:
        if path is not None and path.exists() and not force:
            raise UserInputError("the output file exists and was left untouched", file=path,
                                 fix="choose another name or pass --force")
