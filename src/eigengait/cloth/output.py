"""Writing a run's frame set: ``<NAME>_<frame>.OBT`` (as FLEX3D), ``obj/<NAME>_<frame>.obj``, PNGs,
a video and ``run.json``, all in one output folder that belongs to the run.

The set is written into a staging folder beside the output folder and swapped in only once the whole
run (simulation and rendering) has succeeded, replacing any earlier set as a whole; a failed or
interrupted run removes the staging folder, so the output folder always holds exactly one complete
run.
"""

from __future__ import annotations

import json
import os
import secrets
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from eigengait.cloth.model import ClothModel
from eigengait.cloth.obt import Mesh, write_obj, write_obt
from eigengait.errors import UserInputError

#: the file that marks a folder as a frame set written by ``cloth run``
MANIFEST = "run.json"
_MATERIAL = {0: (0.8, 0.2, 0.2, 0.8, 0.2, 0.2)}


def surface_meshes(model: ClothModel, positions: np.ndarray) -> list[Mesh]:
    """One triangulated :class:`Mesh` per surface at ``positions`` (N, 3)."""
    meshes = []
    for layout in model.surfaces:
        triangles = (layout.triangles - layout.start).tolist()
        meshes.append(
            Mesh(layout.name, positions[layout.indices], triangles, [0] * len(triangles), _MATERIAL)
        )
    return meshes


def write_frame(model: ClothModel, positions: np.ndarray, index: int, folder: Path) -> None:
    """``folder/<NAME>_<index>.OBT`` and ``folder/obj/<NAME>_<index>.obj`` for every surface."""
    (folder / "obj").mkdir(parents=True, exist_ok=True)
    for mesh in surface_meshes(model, positions):
        write_obt(mesh, folder / f"{mesh.name}_{index}.OBT")
        write_obj(mesh, folder / "obj" / f"{mesh.name}_{index}.obj")


def write_manifest(folder: Path, summary: dict) -> None:
    """``folder/run.json``: the run's settings, frame rates and durations."""
    (folder / MANIFEST).write_text(json.dumps(summary, indent=2) + "\n")


def check_replaceable(directory: Path, force: bool) -> None:
    """Raise unless ``directory`` is missing, empty, or (with ``force``) an earlier frame set."""
    if not directory.exists():
        return
    if not directory.is_dir():
        raise UserInputError(
            "the output path is a file, not a folder.",
            file=directory,
            fix="name a new folder for the frames.",
        )
    if not any(directory.iterdir()):
        return
    if not (directory / MANIFEST).is_file():
        raise UserInputError(
            f"the output folder holds files that are not a frame set (no {MANIFEST}); it was left "
            "untouched.",
            file=directory,
            fix="name a new or empty folder for the frames.",
        )
    if not force:
        raise UserInputError(
            "the output folder holds an earlier run's frames; it was left untouched.",
            file=directory,
            fix="pass force=True to replace that run, or name another folder.",
        )


@contextmanager
def staged_output(directory: Path, force: bool = False):
    """Yield a staging folder beside ``directory``; on success it replaces ``directory`` as a whole.

    Raises:
        UserInputError: ``directory`` holds an earlier frame set and ``force`` is off, or holds
            other files.
    """
    directory = directory.resolve()
    check_replaceable(directory, force)
    directory.parent.mkdir(parents=True, exist_ok=True)
    staging = directory.parent / f".{directory.name}.incomplete-{secrets.token_hex(4)}"
    staging.mkdir()
    try:
        yield staging
        swap_in(staging, directory)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def swap_in(staging: Path, directory: Path) -> None:
    """Rename ``staging`` to ``directory``; an earlier non-empty ``directory`` is renamed aside
    first, then deleted."""
    old = None
    if directory.exists() and any(directory.iterdir()):
        old = directory.parent / f".{directory.name}.old-{secrets.token_hex(4)}"
        os.rename(directory, old)
    os.replace(staging, directory)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


@contextmanager
def staged_file(path: Path):
    """Yield a temporary path beside ``path``; on success it is renamed to ``path``, on failure
    deleted."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    try:
        yield Path(name)
        os.replace(name, path)
    finally:
        Path(name).unlink(missing_ok=True)
