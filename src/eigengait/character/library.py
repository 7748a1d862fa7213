"""The built-in creature library: MJCF + sidecar files shipped in `eigengait/data/characters/`."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from eigengait.errors import UserInputError


def library_dir() -> Path:
    return Path(str(resources.files("eigengait") / "data" / "characters"))


def builtin_names() -> list[str]:
    """Names of the built-in characters, sorted."""
    return sorted(p.stem for p in library_dir().glob("*.xml"))


def resolve_character(name_or_path: str | Path) -> Path:
    """The MJCF path of a built-in name or a user file; UserInputError if neither exists."""
    text = str(name_or_path)
    if text in builtin_names():
        return library_dir() / f"{text}.xml"
    path = Path(text)
    if path.suffix.lower() in (".xml", ".yaml") or path.exists():
        if not path.is_file():
            raise UserInputError(
                "file not found", file=path, fix="give a path to an MJCF .xml file or a NAME.eigengait.yaml sidecar"
            )
        return path
    raise UserInputError(
        f"unknown character '{text}'",
        field="CHARACTER",
        fix=f"use a built-in name ({', '.join(builtin_names())}) or a path to an MJCF file",
    )
