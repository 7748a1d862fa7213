"""Shipped sketch presets and optimized gaits (package data), found by name."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from eigengait.errors import UserInputError


def _data(kind: str) -> Path:
    return Path(str(resources.files("eigengait") / "data" / kind))


def preset_names() -> list[str]:
    return sorted(p.stem for p in _data("sketches").glob("*.yaml"))


def gait_names() -> list[str]:
    return sorted(p.stem for p in _data("gaits").glob("*.json"))


def resolve(kind: str, name_or_path: str) -> Path:
    """A shipped preset/gait by name, or a user file path."""
    folder, suffix, names = (
        (_data("sketches"), ".yaml", preset_names())
        if kind == "sketch"
        else (_data("gaits"), ".json", gait_names())
    )
    if name_or_path in names:
        return folder / f"{name_or_path}{suffix}"
    path = Path(name_or_path)
    if path.is_file():
        return path
    raise UserInputError(
        f"no {kind} file or shipped {kind} named '{name_or_path}'",
        file=name_or_path,
        fix=f"give a file path or one of: {', '.join(names)}",
    )
