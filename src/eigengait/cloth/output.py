"""Writing a run's frames: ``<NAME>_<frame>.OBT`` (as FLEX3D), ``obj/<NAME>_<frame>.obj``, PNGs and a video.

Everything is written into a staging folder ``DIR/.incomplete/`` and moved into ``DIR`` only once the whole
run (simulation and rendering) has succeeded; a failed or interrupted run removes the staging folder, so files
in ``DIR`` always come from a complete run.
"""

from __future__ import annotations

import os
import shutil
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from eigengait.cloth.model import ClothModel
from eigengait.cloth.obt import Mesh, write_obj, write_obt

STAGING = ".incomplete"
_MATERIAL = {0: (0.8, 0.2, 0.2, 0.8, 0.2, 0.2)}


def surface_meshes(model: ClothModel, positions: np.ndarray) -> list[Mesh]:
    """One triangulated :class:`Mesh` per surface at ``positions`` (N, 3)."""
    meshes = []
    for layout in model.surfaces:
        triangles = (layout.triangles - layout.start).tolist()
        meshes.append(Mesh(layout.name, positions[layout.indices], triangles, [0] * len(triangles), _MATERIAL))
    return meshes


def write_frame(model: ClothModel, positions: np.ndarray, index: int, folder: Path) -> None:
    """``folder/<NAME>_<index>.OBT`` and ``folder/obj/<NAME>_<index>.obj`` for every surface."""
    (folder / "obj").mkdir(parents=True, exist_ok=True)
    for mesh in surface_meshes(model, positions):
        write_obt(mesh, folder / f"{mesh.name}_{index}.OBT")
        write_obj(mesh, folder / "obj" / f"{mesh.name}_{index}.obj")


@contextmanager
def staged_output(directory: Path):
    """Yield a staging folder inside ``directory``; on success move its contents into ``directory``."""
    directory.mkdir(parents=True, exist_ok=True)
    staging = directory / STAGING
    shutil.rmtree(staging, ignore_errors=True)
    staging.mkdir()
    try:
        yield staging
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    for root, _, names in os.walk(staging):
        target = directory / Path(root).relative_to(staging)
        target.mkdir(parents=True, exist_ok=True)
        for name in names:
            os.replace(Path(root) / name, target / name)
    shutil.rmtree(staging, ignore_errors=True)
