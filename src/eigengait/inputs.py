"""Text files the user gives: read as UTF-8, else Latin-1; an unreadable file is a `UserInputError`."""

from __future__ import annotations

from pathlib import Path

from eigengait.errors import UserInputError


def read_text(path: Path) -> str:
    """The file's text, decoded as UTF-8 or, failing that, Latin-1 (which decodes any bytes)."""
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise UserInputError(f"cannot read the file ({exc.strerror or exc.__class__.__name__})", file=path) from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("latin-1")
