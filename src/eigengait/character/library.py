"""The built-in creature library shipped in `eigengait/data/characters/`.

A built-in is either `NAME.xml` (with its sidecar `NAME.eigengait.yaml` beside it) or, for a model
kept as its authors ship it in a subfolder, a standalone sidecar `NAME.eigengait.yaml` whose
`model:` names that file.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from eigengait.character.metadata import SIDECAR_SUFFIX
from eigengait.errors import UserInputError


def library_dir() -> Path:
    return Path(str(resources.files("eigengait") / "data" / "characters"))


def _builtin_paths() -> dict[str, Path]:
    """Built-in name -> what to load: its MJCF, or the standalone sidecar of a model kept in a
    subfolder."""
    folder = library_dir()
    found = {p.stem: p for p in folder.glob("*.xml")}
    for side in folder.glob("*" + SIDECAR_SUFFIX):
        found.setdefault(side.name[: -len(SIDECAR_SUFFIX)], side)
    return found


def builtin_names() -> list[str]:
    """Names of the built-in characters, sorted."""
    return sorted(_builtin_paths())


def resolve_character(name_or_path: str | Path) -> Path:
    """The MJCF path of a built-in name or a user file; UserInputError if neither exists."""
    text = str(name_or_path)
    builtin = _builtin_paths()
    if text in builtin:
        return builtin[text]
    path = Path(text)
    if path.suffix.lower() in (".xml", ".yaml") or path.exists():
        if not path.is_file():
            raise UserInputError(
                "file not found",
                file=path,
                fix="give a path to an MJCF .xml file or a NAME.eigengait.yaml sidecar",
            )
        return path
    raise UserInputError(
        f"unknown character '{text}'",
        field="CHARACTER",
        fix=f"use a built-in name ({', '.join(sorted(builtin))}) or a path to an MJCF file",
    )
