"""The UFRGS ``.OBT`` polygon format (Nedel 1993, annex A-1): reader and writer.

Files are y-up like FLEX3D; :class:`Mesh` holds z-up coordinates (converted here, once). Faces may
be any polygon; :attr:`Mesh.triangles` fans them into triangles for collision. Colours are kept for
rendering.
"""

from __future__ import annotations

import unicodedata
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from eigengait.cloth.par import read_legacy_text, yup_to_zup, zup_to_yup
from eigengait.errors import UserInputError


@dataclass
class Mesh:
    """A named polygon mesh. ``vertices`` (V, 3) m, z-up; ``faces`` polygons of vertex indices;
    ``face_material`` one index per face into ``materials`` (R, G, B, diffuse, specular,
    ambient)."""

    name: str
    vertices: np.ndarray
    faces: list[list[int]]
    face_material: list[int] = field(default_factory=list)
    materials: dict[int, tuple[float, ...]] = field(default_factory=dict)

    @property
    def triangles(self) -> np.ndarray:
        """(T, 3) vertex indices: each polygon fanned from its first vertex."""
        tris = [(f[0], f[k], f[k + 1]) for f in self.faces for k in range(1, len(f) - 1)]
        return np.array(tris, dtype=np.int64).reshape(-1, 3)

    @property
    def center(self) -> np.ndarray:
        return 0.5 * (self.vertices.min(axis=0) + self.vertices.max(axis=0))

    @property
    def radius(self) -> float:
        return (
            float(np.linalg.norm(self.vertices - self.center, axis=1).max())
            if len(self.vertices)
            else 0.0
        )


def _plain(word: str) -> str:
    text = unicodedata.normalize("NFKD", word)
    return "".join(c for c in text if not unicodedata.combining(c)).upper()


def read_obt(path: str | Path) -> Mesh:
    """Read one object from an ``.OBT`` file.

    Raises:
        UserInputError: a missing file or a malformed section, naming the line.
    """
    path = Path(path)
    text = read_legacy_text(
        path,
        "the obstacle file",
        "put the .OBT file next to the script or fix its name in OBJETOS_NA_CENA.",
    )
    rows = [(n, line.split()) for n, line in enumerate(text.splitlines(), start=1) if line.split()]
    cursor = 0

    def fail(message: str, n: int, fix: str | None = None) -> UserInputError:
        return UserInputError(message, file=str(path), field=f"line {n}", fix=fix)

    def section(name: str) -> tuple[int, list[str]]:
        nonlocal cursor
        if cursor >= len(rows):
            last = rows[-1][0] if rows else 1
            raise fail(
                f"the file ends where ${name} was expected.", last, fix=f"add the ${name} section."
            )
        n, words = rows[cursor]
        if _plain(words[0]) != "$" + name:
            raise fail(f"expected ${name}, found '{words[0]}'.", n)
        cursor += 1
        return n, words

    def numbers(words: list[str], n: int, kind=float) -> list:
        try:
            return [kind(w) for w in words]
        except ValueError:
            raise fail(f"expected numbers, found '{' '.join(words)}'.", n) from None

    n, words = section("OBJETO")
    name = words[1] if len(words) > 1 else path.stem
    n, words = section("VERTICES")
    count = numbers(words[1:2], n, int)[0] if len(words) > 1 else 0
    vertices = []
    for _ in range(count):
        if cursor >= len(rows):
            raise fail(f"$VERTICES announces {count} vertices but the file ends.", n)
        vn, vwords = rows[cursor]
        coords = numbers(vwords[:3], vn)
        if len(coords) != 3:
            raise fail("a vertex needs three coordinates.", vn)
        vertices.append(coords)
        cursor += 1
    n, words = section("FACES")
    count = numbers(words[1:2], n, int)[0] if len(words) > 1 else 0
    faces, face_material = [], []
    for _ in range(count):
        if cursor >= len(rows):
            raise fail(f"$FACES announces {count} faces but the file ends.", n)
        fn, fwords = rows[cursor]
        ints = numbers(fwords, fn, int)
        nv = ints[0] if ints else 0
        if nv < 3 or len(ints) < nv + 1:
            raise fail("a face is '<nv> <v1> ... <vn> <material>' with nv >= 3.", fn)
        polygon = ints[1 : nv + 1]
        if min(polygon) < 0 or max(polygon) >= len(vertices):
            raise fail(
                f"a face uses vertex {max(polygon)} but there are {len(vertices)} vertices "
                "(0-based).",
                fn,
            )
        faces.append(polygon)
        face_material.append(ints[nv + 1] if len(ints) > nv + 1 else 0)
        cursor += 1
    materials: dict[int, tuple[float, ...]] = {}
    if cursor < len(rows) and _plain(rows[cursor][1][0]) == "$DESCRICAO":
        cursor += 1
        while cursor < len(rows) and rows[cursor][1][0].startswith("#"):
            mn, mwords = rows[cursor]
            index = numbers([mwords[0][1:]], mn, int)[0]
            materials[index] = tuple(numbers(mwords[1:7], mn))
            cursor += 1
    section("END_OBJ")
    verts = yup_to_zup(np.array(vertices, dtype=float).reshape(-1, 3))
    return Mesh(
        name=name, vertices=verts, faces=faces, face_material=face_material, materials=materials
    )


def _rows(template: str, columns: np.ndarray) -> list[str]:
    """One formatted line per row of ``columns`` (formatting Python numbers, far faster than NumPy
    scalars)."""
    return list(map(template.format, *np.asarray(columns).T.tolist()))


def _face_rows(mesh: Mesh, prefix_count: bool, offset: int) -> list[str]:
    """Face lines: triangles as one vectorized block, other polygons one by one."""
    materials = mesh.face_material or [0] * len(mesh.faces)
    if mesh.faces and all(len(f) == 3 for f in mesh.faces):
        tri = np.asarray(mesh.faces) + offset
        if prefix_count:
            return _rows("3 {} {} {} {}", np.column_stack([tri, materials]))
        return _rows("f {} {} {}", tri)
    if prefix_count:
        return [
            " ".join(map(str, [len(f), *(i + offset for i in f), m]))
            for f, m in zip(mesh.faces, materials)
        ]
    return ["f " + " ".join(str(i + offset) for i in f) for f in mesh.faces]


def format_obt(mesh: Mesh) -> str:
    """The ``.OBT`` text of ``mesh`` (written y-up, as FLEX3D did)."""
    c = zup_to_yup(mesh.center)
    out = [
        f"$OBJETO {mesh.name} {c[0]:.6f} {c[1]:.6f} {c[2]:.6f} {mesh.radius:.6f}",
        f"$VERTICES {len(mesh.vertices)}",
    ]
    out += _rows("{:.6f} {:.6f} {:.6f}", zup_to_yup(mesh.vertices))
    out.append(f"$FACES {len(mesh.faces)}")
    out += _face_rows(mesh, prefix_count=True, offset=0)
    out.append("$DESCRICAO")
    out += [
        f"#{k} " + " ".join(f"{v:g}" for v in values)
        for k, values in sorted(mesh.materials.items())
    ]
    out.append("$END_OBJ")
    return "\n".join(out) + "\n"


def write_obt(mesh: Mesh, path: str | Path) -> None:
    Path(path).write_text(format_obt(mesh), encoding="utf-8")


def write_obj(mesh: Mesh, path: str | Path) -> None:
    """Wavefront OBJ of ``mesh`` in the z-up world (1-based indices)."""
    lines = [f"o {mesh.name}"] + _rows("v {:.6f} {:.6f} {:.6f}", mesh.vertices)
    lines += _face_rows(mesh, prefix_count=False, offset=1)
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
