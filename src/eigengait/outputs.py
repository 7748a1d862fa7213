"""Output files the user asked for: checked before any work starts, never overwritten silently."""

from __future__ import annotations

from pathlib import Path

from eigengait.errors import UserInputError


def check_output(path: Path, force: bool) -> None:
    """Raise unless `path` can be written: not a folder, not existing (unless `force`), its folder created."""
    if "\0" in str(path):
        raise UserInputError("the output path contains a NUL byte", file=repr(str(path)), fix="choose another name")
    if path.is_dir():
        raise UserInputError("the output path is a folder, not a file", file=path, fix="name a file inside it")
    if path.exists() and not force:
        raise UserInputError("the output file exists and was left untouched", file=path,
                             fix="choose another name or pass --force")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UserInputError(f"cannot create the output's folder ({exc.strerror or exc.__class__.__name__})",
                             file=path.parent, fix="choose a writable location") from None


def refuse_existing(paths: list[Path | None], force: bool) -> None:
    """Check every given output path with `check_output` (None entries are skipped)."""
    for path in paths:
        if path is not None:
            check_output(path, force)
