"""Every file a character file makes MuJoCo read must lie in the studio folder, or the character is
refused.

A character's MJCF may name other files: `<include file>`, `<model file>`, meshes, textures (`file`,
`fileright`, …), height fields, skins, and folders for them
(`<compiler meshdir texturedir assetdir>`); its sidecar `NAME.eigengait.yaml` may stand beside it.
MuJoCo reads a name relative to the model's folder or to one of those folders, so each name is
checked against all of them: every reading has to stay inside the studio folder.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from eigengait.character.metadata import is_sidecar, load_metadata, sidecar_path
from eigengait.errors import UserInputError
from eigengait.studio.sandbox import Sandbox

FOLDER_ATTRIBUTES = ("assetdir", "meshdir", "texturedir")
MODEL_ELEMENTS = ("include", "model")  # elements whose file is itself MJCF, read in turn
FIX = "copy the file into the studio folder and name it by a path relative to the model"


def confine_character(sandbox: Sandbox, path: Path) -> None:
    """Refuse a character file (an MJCF, or a sidecar naming one) that is, or makes MuJoCo read,
    anything outside the studio folder."""
    mjcf = _model_of(sandbox, Path(path))
    side = sidecar_path(mjcf)
    if side.exists() and not sandbox.contains(side):
        raise UserInputError(
            "the character's sidecar leads outside the studio folder and was refused",
            file=side,
            fix=FIX,
        )
    references = _references(sandbox, mjcf)
    bases = _bases(references, mjcf)
    for source, element, name in references:
        _check(sandbox, source, element, name, bases)


def _model_of(sandbox: Sandbox, path: Path) -> Path:
    """The MJCF file a character file stands for: itself, or the model its sidecar names."""
    if not sandbox.contains(path):
        raise UserInputError(
            "the character is outside the studio folder and was refused", file=path, fix=FIX
        )
    if not is_sidecar(path):
        return sandbox.root / path
    model = load_metadata(sandbox.root / path).model
    if not model:
        raise UserInputError(
            "this sidecar does not name its model",
            file=path,
            field="model",
            fix="load the character's MJCF file instead",
        )
    mjcf = sandbox.root / Path(path).parent / model
    if not sandbox.contains(mjcf):
        raise UserInputError(
            "the sidecar's model is outside the studio folder and was refused",
            file=path,
            field="model",
            fix=FIX,
        )
    return mjcf


def _references(sandbox: Sandbox, mjcf: Path) -> list[tuple[Path, ET.Element, str]]:
    """(XML file, element, attribute) of every file or folder name in the model and the MJCF it
    includes."""
    found, pending, read = [], [mjcf], set()
    while pending:
        source = pending.pop()
        if source in read:
            continue
        read.add(source)
        for element in _parse(sandbox, source).iter():
            for name in element.attrib:
                if name.startswith("file") or name in FOLDER_ATTRIBUTES:
                    found.append((source, element, name))
                    if element.tag in MODEL_ELEMENTS and name == "file":
                        included = _check(sandbox, source, element, name, _bases(found, mjcf))
                        pending += [p for p in included if p.is_file()]
    return found


def _bases(references: list[tuple[Path, ET.Element, str]], mjcf: Path) -> set[Path]:
    """The folders a file name may be read from: each MJCF file's, and the model's asset folders."""
    files = {mjcf, *(source for source, _, _ in references)}
    folders = {element.get(name) for _, element, name in references if name in FOLDER_ATTRIBUTES}
    return {f.parent / d for f in files for d in folders | {""}}


def _check(
    sandbox: Sandbox, source: Path, element: ET.Element, name: str, bases: set[Path]
) -> list[Path]:
    """Every reading of one file name, refused if any lands outside the studio folder."""
    value = element.get(name)
    readings = [(base / value).resolve() for base in bases]
    if not all(sandbox.contains(p) for p in readings):
        raise UserInputError(
            f"<{element.tag} {name}=\"{value}\"> reads outside the studio folder and was refused",
            file=sandbox.relative(source),
            fix=FIX,
        )
    return readings


def _parse(sandbox: Sandbox, path: Path) -> ET.Element:
    try:
        return ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise UserInputError(
            f"malformed MJCF: {exc}",
            file=sandbox.relative(path),
            fix="fix the XML so MuJoCo can load it",
        ) from None
