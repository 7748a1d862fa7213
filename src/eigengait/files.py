"""Versioned, validated files: JSON or YAML by extension, one clear error naming the file and
field."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TypeVar

import yaml
from pydantic import BaseModel, ValidationError

from eigengait import json_text
from eigengait.errors import UserInputError
from eigengait.inputs import read_text
from eigengait.outputs import write_atomically

M = TypeVar("M", bound=BaseModel)


def read_mapping(path: Path, allow_empty: bool = False) -> dict:
    """Parse a JSON or YAML file into a dict, or raise UserInputError; with `allow_empty` an empty
    file reads as {}."""
    if not path.is_file():
        raise UserInputError("file not found", file=path)
    text = read_text(path)
    try:
        data = json.loads(text) if path.suffix.lower() == ".json" else yaml.safe_load(text)
    except (json.JSONDecodeError, yaml.YAMLError) as exc:
        raise UserInputError(
            f"cannot parse the file ({exc.__class__.__name__}: {exc})".replace("\n", " "),
            file=path,
            fix="check the JSON/YAML syntax",
        ) from None
    if data is None and allow_empty:
        return {}
    if not isinstance(data, dict):
        raise UserInputError(
            "expected a mapping at the top level",
            file=path,
            fix="write the file's fields as `name: value` lines (YAML) or as one JSON object",
        )
    return data


def validate(model: type[M], data: dict, path: Path | str, fix: str) -> M:
    """`data` as a `model`, or one UserInputError naming the file, the first invalid field and
    `fix`."""
    try:
        return model.model_validate(data)
    except ValidationError as err:
        e = err.errors()[0]
        field = ".".join(str(p) for p in e["loc"]) or "(top level)"
        raise UserInputError(e["msg"], file=path, field=field, fix=fix) from None


def load_model(model: type[M], path: Path | str, fix: str, allow_empty: bool = False) -> M:
    """A JSON or YAML file read and validated as a `model` (`read_mapping`, then `validate`)."""
    return validate(model, read_mapping(Path(path), allow_empty), path, fix)


def dump(model: BaseModel, path: Path) -> None:
    data = model.model_dump(mode="json")
    text = (
        json_text.dumps(data, indent=2)
        if path.suffix.lower() == ".json"
        else yaml.safe_dump(data, sort_keys=False)
    )
    write_atomically(path, text)
