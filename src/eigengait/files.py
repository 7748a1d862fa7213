"""Versioned, validated files: JSON or YAML by extension, one clear error naming the file and field."""

from __future__ import annotations

import json
from pathlib import Path

import yaml
from pydantic import BaseModel, ValidationError

from eigengait import json_text
from eigengait.errors import UserInputError
from eigengait.inputs import read_text
from eigengait.outputs import write_atomically


def read_mapping(path: Path) -> dict:
    """Parse a JSON or YAML file into a dict, or raise UserInputError."""
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
    if not isinstance(data, dict):
        raise UserInputError("expected a mapping at the top level", file=path)
    return data


def validate(model: type[BaseModel], data: dict, path: Path | str, fix: str) -> BaseModel:
    try:
        return model.model_validate(data)
    except ValidationError as err:
        e = err.errors()[0]
        field = ".".join(str(p) for p in e["loc"]) or "(top level)"
        raise UserInputError(e["msg"], file=path, field=field, fix=fix) from None


def dump(model: BaseModel, path: Path) -> None:
    data = model.model_dump(mode="json")
    text = json_text.dumps(data, indent=2) if path.suffix.lower() == ".json" else yaml.safe_dump(data, sort_keys=False)
    write_atomically(path, text)
