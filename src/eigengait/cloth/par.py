"""Lenient reader for FLEX3D animation scripts (``.PAR``).

The grammar is the one printed in Nedel (1993), section 5.2, read leniently as the dissertation's
own examples require: accents are optional (``DURAÇÃO`` = ``DURACAO``), ``=``, ``(``, ``)`` and
``,`` are separators, the spellings ``RESTRICÇÕES`` / ``FIM_RESTRICÇÕES`` / ``INL_TRANSL`` are
accepted, ``CONST_CURVATURA`` may be one number or a triple (horizontal, vertical, diagonal),
``TRANSLAÇÃO`` blocks may repeat, a surface name may be empty, and a fixed point may be written
``i j`` or as one row-major index ``i*n + j`` on its own line (the paper example prints ``90`` for
``9 0``). ``#`` starts a comment. One extension: ``GRAVIDADE = <m/s²>`` sets the gravity
acceleration (default 9.81, pointing down).

Further extensions (FLEX3D's §3.2.6 constraints that its script language lacked, and two scene
switches): ``PONTOS_ALVO = <n>`` then n lines ``i j (x y z)`` — point (i, j) is fixed once it
reaches (x, y, z); ``PONTOS_PRESOS = <n>`` then n lines ``i j <surface> k l`` (held to point (k, l)
of that surface) or ``i j <obstacle>`` (held where it is nearest that obstacle's surface), both
inside ``RESTRIÇÕES``; ``PISO = <y>`` adds a floor plane at height y; ``AUTOCOLISAO = 1`` turns
self-collision on.

FLEX3D is y-up; everything returned here is already converted to eigengait's z-up world,
``(x, y, z)_flex3d -> (x, -z, y)``. Numbers are read as SI units (m, kg, s, N).
"""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from eigengait.errors import UserInputError

STANDARD_GRAVITY = 9.81


def yup_to_zup(vector) -> np.ndarray:
    """Convert FLEX3D y-up coordinates (..., 3) to the z-up world: (x, y, z) -> (x, -z, y)."""
    v = np.asarray(vector, dtype=float)
    return np.stack([v[..., 0], -v[..., 2], v[..., 1]], axis=-1)


def zup_to_yup(vector) -> np.ndarray:
    """Inverse of :func:`yup_to_zup`: (x, y, z) -> (x, z, -y)."""
    v = np.asarray(vector, dtype=float)
    return np.stack([v[..., 0], v[..., 2], -v[..., 1]], axis=-1)


# nodes per surface (about 500×500): beyond this a run needs gigabytes and hours
MAX_NODES = 250_000

_WORD = re.compile(r"[A-Za-z0-9_.+-]{1,32}")


def shown(text: str) -> str:
    """A token as it may appear in an error: a short word or number, never a line of some other
    file."""
    return text if _WORD.fullmatch(text) else "(not a FLEX3D word)"


@dataclass(frozen=True)
class Translation:
    """Kinematic motion of a surface's fixed points: ``step`` metres per frame (z-up) from ``start``
    to ``end`` s."""

    step: np.ndarray
    start: float
    end: float


@dataclass(frozen=True)
class Target:
    """Point (i, j) becomes fixed once it reaches ``position`` (z-up, m)."""

    i: int
    j: int
    position: np.ndarray


@dataclass(frozen=True)
class Attachment:
    """Point (i, j) held to point ``point`` of surface ``body``, or (``point`` None) to the obstacle
    ``body``."""

    i: int
    j: int
    body: str
    point: tuple[int, int] | None
    line: int


@dataclass
class SurfaceSpec:
    """One ``SUPERFÍCIE`` block. Vectors are z-up; ``rows`` × ``cols`` mass points ``spacing`` m
    apart."""

    name: str
    rows: int
    cols: int
    spacing: float
    position: np.ndarray
    normal: np.ndarray
    mass: float
    stiffness: tuple[float, float, float]
    bending: tuple[float, float, float]
    fixed: list[tuple[int, int]] = field(default_factory=list)
    translations: list[Translation] = field(default_factory=list)
    line: int = 0
    targets: list[Target] = field(default_factory=list)
    attachments: list[Attachment] = field(default_factory=list)


@dataclass
class Script:
    """A whole ``.PAR`` script. ``external_force`` is in N per mass point, gravity in m/s²
    (z-up)."""

    duration: float
    frames_per_second: float
    time_step: float
    external_force: np.ndarray
    friction: float
    obstacles: list[Path]
    surfaces: list[SurfaceSpec]
    gravity: float = STANDARD_GRAVITY
    floor: float | None = None
    self_collision: bool = False
    path: str = "<script>"
    lines: dict[str, int] = field(default_factory=dict)


_SYNONYMS = {
    "RESTRICCOES": "RESTRICOES",
    "FIM_RESTRICCOES": "FIM_RESTRICOES",
    "INL_TRANSL": "INI_TRANSL",
    "NUM_SUPERFICIE": "NUM_SUPERFICIES",
    "GRAVITY": "GRAVIDADE",
}
_GLOBAL_SCALARS = {
    "DURACAO",
    "QUADROS_SEG",
    "DELTA_T",
    "ATRITO",
    "GRAVIDADE",
    "PISO",
    "AUTOCOLISAO",
}
_SURFACE_KEYWORDS = {
    "MALHA",
    "DENSIDADE",
    "POSIC_NO_SRU",
    "VETOR_NORMAL",
    "MASSA",
    "CONST_ELASTICIDADE",
    "CONST_CURVATURA",
    "RESTRICOES",
    "FIM_SUPERFICIE",
}
_KEYWORDS = (
    _GLOBAL_SCALARS
    | _SURFACE_KEYWORDS
    | {
        "FORCA_EXTERNA",
        "OBJETOS_NA_CENA",
        "NUM_SUPERFICIES",
        "SUPERFICIE",
        "PONTOS_FIXOS",
        "TRANSLACAO",
        "INI_TRANSL",
        "FIM_TRANSL",
        "FIM_RESTRICOES",
        "PONTOS_ALVO",
        "PONTOS_PRESOS",
    }
)
_REQUIRED_GLOBALS = ("DURACAO", "QUADROS_SEG", "DELTA_T")


def normalize_keyword(word: str) -> str:
    """Upper-case ``word``, drop accents and markdown escapes, and map spelling variants to one
    spelling."""
    plain = unicodedata.normalize("NFKD", word.replace("\\", ""))
    plain = "".join(c for c in plain if not unicodedata.combining(c)).upper()
    return _SYNONYMS.get(plain, plain)


@dataclass
class _Token:
    text: str
    line: int

    @property
    def keyword(self) -> str:
        return normalize_keyword(self.text)


def _tokenize(text: str) -> list[_Token]:
    tokens = []
    for number, raw in enumerate(text.splitlines(), start=1):
        content = raw.split("#", 1)[0].replace("\\_", "_")
        for word in re.split(r"[\s=(),;]+", content):
            if word:
                tokens.append(_Token(word, number))
    return tokens


class _Reader:
    def __init__(self, tokens: list[_Token], path: str):
        self.tokens = tokens
        self.pos = 0
        self.path = path

    def error(
        self, message: str, token: _Token | None = None, fix: str | None = None
    ) -> UserInputError:
        token = token or (
            self.tokens[min(self.pos, len(self.tokens) - 1)] if self.tokens else _Token("", 1)
        )
        return UserInputError(
            message, file=self.path, field=f"line {token.line}: {shown(token.text)}", fix=fix
        )

    def peek(self) -> _Token | None:
        return self.tokens[self.pos] if self.pos < len(self.tokens) else None

    def next(self, what: str) -> _Token:
        token = self.peek()
        if token is None:
            last = self.tokens[-1] if self.tokens else _Token("", 1)
            raise UserInputError(
                f"the script ends where {what} was expected.",
                file=self.path,
                field=f"line {last.line}: end of file",
                fix=f"add {what}.",
            )
        self.pos += 1
        return token

    def number(self, keyword: _Token, kind=float):
        token = self.next(f"a number after {keyword.text}")
        try:
            value = kind(token.text)
        except ValueError:
            raise self.error(
                f"{keyword.text} expects {'an integer' if kind is int else 'a number'}, got "
                f"'{shown(token.text)}'.",
                token,
            ) from None
        if not np.isfinite(value):
            raise self.error(f"{keyword.text} must be finite, got '{shown(token.text)}'.", token)
        return value

    def numbers(self, keyword: _Token, count: int, kind=float) -> list:
        return [self.number(keyword, kind) for _ in range(count)]

    def numbers_on_line(self, keyword: _Token, most: int) -> list[float]:
        """Read 1..``most`` numbers that sit on ``keyword``'s line (scalar-or-triple fields)."""
        values = [self.number(keyword)]
        while len(values) < most and self.peek() is not None and self.peek().line == keyword.line:
            values.append(self.number(keyword))
        return values


def parse_par(text: str, path: str | Path = "<script>") -> Script:
    """Parse the text of a ``.PAR`` script; obstacle files are resolved relative to ``path``'s
    folder.

    Raises:
        UserInputError: naming the file and the line of the first problem.
    """
    path = str(path)
    reader = _Reader(_tokenize(text), path)
    values: dict[str, float] = {}
    lines: dict[str, int] = {}
    force = np.zeros(3)
    obstacles: list[Path] = []
    surfaces: list[SurfaceSpec] = []
    expected_surfaces: tuple[int, _Token] | None = None
    base = Path(path).parent
    while (token := reader.peek()) is not None:
        reader.pos += 1
        key = token.keyword
        lines[key] = token.line
        if key in _GLOBAL_SCALARS:
            values[key] = reader.number(token)
        elif key == "FORCA_EXTERNA":
            force = yup_to_zup(reader.numbers(token, 3))
        elif key == "OBJETOS_NA_CENA":
            count = reader.number(token, int)
            obstacles += [
                base / reader.next("an obstacle .OBT file name").text for _ in range(count)
            ]
        elif key == "NUM_SUPERFICIES":
            expected_surfaces = (reader.number(token, int), token)
        elif key == "SUPERFICIE":
            surfaces.append(_parse_surface(reader, token, len(surfaces)))
        else:
            raise reader.error(
                f"unknown keyword '{shown(token.text)}'.",
                token,
                fix="check the spelling against the FLEX3D grammar (docs/cloth.md).",
            )
    for key in _REQUIRED_GLOBALS:
        if key not in values:
            raise UserInputError(
                f"the script has no {key} line.",
                file=path,
                field=key,
                fix=f"add '{key} = <value>' at the top of the script.",
            )
    if expected_surfaces is not None and expected_surfaces[0] != len(surfaces):
        raise reader.error(
            f"NUM_SUPERFICIES says {expected_surfaces[0]} but {len(surfaces)} SUPERFICIE blocks "
            "follow.",
            expected_surfaces[1],
        )
    if not surfaces:
        raise UserInputError(
            "the script defines no surface.",
            file=path,
            field="SUPERFICIE",
            fix="add a SUPERFICIE ... FIM_SUPERFICIE block.",
        )
    for key, low in (("DURACAO", 0.0), ("QUADROS_SEG", 0.0), ("DELTA_T", 0.0)):
        if values[key] <= low:
            raise UserInputError(
                f"{key} must be positive, got {values[key]}.",
                file=path,
                field=f"line {lines[key]}: {key}",
            )
    if values.get("ATRITO", 0.0) < 0:
        raise UserInputError(
            "ATRITO must not be negative.", file=path, field=f"line {lines['ATRITO']}: ATRITO"
        )
    return Script(
        duration=values["DURACAO"],
        frames_per_second=values["QUADROS_SEG"],
        time_step=values["DELTA_T"],
        external_force=force,
        friction=values.get("ATRITO", 0.0),
        obstacles=obstacles,
        surfaces=surfaces,
        gravity=values.get("GRAVIDADE", STANDARD_GRAVITY),
        floor=values.get("PISO"),
        self_collision=bool(values.get("AUTOCOLISAO", 0.0)),
        path=path,
        lines=lines,
    )


def _parse_surface(reader: _Reader, opener: _Token, index: int) -> SurfaceSpec:
    name_token = reader.peek()
    name = ""
    if (
        name_token is not None
        and name_token.line == opener.line
        and name_token.keyword not in _KEYWORDS
    ):
        name = reader.next("a surface name").text
    fields: dict[str, object] = {}
    spec_fixed: list[tuple[int, int]] = []
    translations: list[Translation] = []
    targets: list[Target] = []
    attachments: list[Attachment] = []
    while True:
        token = reader.next("FIM_SUPERFICIE")
        key = token.keyword
        if key == "FIM_SUPERFICIE":
            break
        if key == "MALHA":
            fields[key] = (reader.number(token, int), reader.number(token, int), token)
            nodes = fields[key][0] * fields[key][1]
            if nodes > MAX_NODES:
                raise reader.error(
                    f"a {fields[key][0]}×{fields[key][1]} mesh has {nodes:,} nodes; one surface "
                    f"may have at most {MAX_NODES:,}.",
                    token,
                    fix="use a coarser MALHA (e.g. 300 300).",
                )
        elif key in ("DENSIDADE", "MASSA"):
            fields[key] = reader.number(token)
        elif key in ("POSIC_NO_SRU", "VETOR_NORMAL"):
            fields[key] = yup_to_zup(reader.numbers(token, 3))
        elif key == "CONST_ELASTICIDADE":
            k = reader.numbers_on_line(token, 3)
            fields[key] = tuple(k * 3 if len(k) == 1 else k)
            if len(fields[key]) != 3:
                raise reader.error(
                    "CONST_ELASTICIDADE expects one number or three (kh kv kd).", token
                )
        elif key == "CONST_CURVATURA":
            k = reader.numbers_on_line(token, 3)
            if len(k) == 2:
                raise reader.error("CONST_CURVATURA expects one number or three.", token)
            fields[key] = tuple(k * 3 if len(k) == 1 else k)
        elif key == "RESTRICOES":
            if "MALHA" not in fields:
                raise reader.error(
                    "RESTRICOES comes before MALHA, so fixed points cannot be checked.",
                    token,
                    fix="put MALHA (<m> <n>) first in the surface block.",
                )
            _parse_constraints(reader, fields, spec_fixed, translations, targets, attachments)
        else:
            raise reader.error(
                f"unknown keyword '{shown(token.text)}' inside SUPERFICIE.",
                token,
                fix="check the spelling against the FLEX3D grammar (docs/cloth.md).",
            )
    for key in ("MALHA", "DENSIDADE", "MASSA", "CONST_ELASTICIDADE"):
        if key not in fields:
            raise reader.error(
                f"surface '{name}' has no {key}.", opener, fix=f"add {key} to the surface block."
            )
    rows, cols, grid_token = fields["MALHA"]
    if rows < 1 or cols < 1 or rows * cols < 2:
        raise reader.error(f"MALHA must have at least two points, got ({rows} {cols}).", grid_token)
    for key in ("DENSIDADE", "MASSA"):
        if fields[key] <= 0:
            raise reader.error(f"{key} must be positive in surface '{name}'.", opener)
    normal = fields.get("VETOR_NORMAL", np.array([0.0, -1.0, 0.0]))
    if np.linalg.norm(normal) == 0:
        raise reader.error(f"VETOR_NORMAL of surface '{name}' is the zero vector.", opener)
    return SurfaceSpec(
        name=name or f"SUPERFICIE{index + 1}",
        rows=rows,
        cols=cols,
        spacing=fields["DENSIDADE"],
        position=fields.get("POSIC_NO_SRU", np.zeros(3)),
        normal=normal / np.linalg.norm(normal),
        mass=fields["MASSA"],
        stiffness=fields["CONST_ELASTICIDADE"],
        bending=fields.get("CONST_CURVATURA", (0.0, 0.0, 0.0)),
        fixed=spec_fixed,
        translations=translations,
        line=opener.line,
        targets=targets,
        attachments=attachments,
    )


def _grid_point(
    reader: _Reader, keyword: _Token, rows: int, cols: int, what: str
) -> tuple[int, int, _Token]:
    """An 'i j' pair inside a (rows x cols) grid."""
    first = reader.next(f"the point 'i j' of {keyword.text}")
    try:
        i = int(first.text)
    except ValueError:
        raise reader.error(
            f"{keyword.text} expects 'i j' integers, got '{first.text}'.",
            first,
            fix=f"check that {keyword.text} counts the lines that follow.",
        ) from None
    j = reader.number(keyword, int)
    if not (0 <= i < rows and 0 <= j < cols):
        raise reader.error(
            f"{what} ({i} {j}) is outside the {rows}x{cols} grid.",
            first,
            fix=f"use 0 <= i < {rows} and 0 <= j < {cols}.",
        )
    return i, j, first


def _parse_constraints(
    reader: _Reader, fields: dict, fixed: list, translations: list, targets: list, attachments: list
) -> None:
    rows, cols, _ = fields["MALHA"]
    pending: dict[str, object] = {}

    def close_translation():
        if pending:
            translations.append(
                Translation(
                    step=pending["step"],
                    start=pending.get("INI_TRANSL", 0.0),
                    end=pending.get("FIM_TRANSL", 0.0),
                )
            )
            pending.clear()

    while True:
        token = reader.next("FIM_RESTRICOES")
        key = token.keyword
        if key == "FIM_RESTRICOES":
            close_translation()
            return
        if key == "PONTOS_FIXOS":
            for _ in range(reader.number(token, int)):
                first = reader.next("a fixed point 'i j'")
                second = reader.peek()
                pair = (
                    second is not None
                    and second.line == first.line
                    and second.keyword not in _KEYWORDS
                )
                try:
                    if pair:
                        reader.pos += 1
                        i, j = int(first.text), int(second.text)
                    else:
                        i, j = divmod(int(first.text), cols)
                except ValueError:
                    raise reader.error(
                        f"a fixed point must be 'i j' integers, got '{first.text}'.",
                        first,
                        fix="check that PONTOS_FIXOS counts the points that follow.",
                    ) from None
                if not (0 <= i < rows and 0 <= j < cols):
                    raise reader.error(
                        f"fixed point ({first.text}{' ' + second.text if pair else ''}) is "
                        f"outside the {rows}x{cols} grid.",
                        first,
                        fix=f"use 0 <= i < {rows} and 0 <= j < {cols}.",
                    )
                fixed.append((i, j))
        elif key == "PONTOS_ALVO":
            for _ in range(reader.number(token, int)):
                i, j, _ = _grid_point(reader, token, rows, cols, "target point")
                position = yup_to_zup(reader.numbers(token, 3))
                targets.append(Target(i, j, position))
        elif key == "PONTOS_PRESOS":
            for _ in range(reader.number(token, int)):
                i, j, first = _grid_point(reader, token, rows, cols, "attached point")
                body = reader.next("the name of a surface or obstacle")
                if body.line != first.line or body.keyword in _KEYWORDS:
                    raise reader.error(
                        "an attached point needs 'i j <surface> k l' or 'i j <obstacle>' on one "
                        "line.",
                        first,
                        fix="name the surface or obstacle it is held to.",
                    )
                point = None
                following = reader.peek()
                if (
                    following is not None
                    and following.line == first.line
                    and following.keyword not in _KEYWORDS
                ):
                    point = (reader.number(token, int), reader.number(token, int))
                attachments.append(Attachment(i, j, body.text, point, body.line))
        elif key == "TRANSLACAO":
            close_translation()
            pending["step"] = yup_to_zup(reader.numbers(token, 3))
        elif key in ("INI_TRANSL", "FIM_TRANSL"):
            if "step" not in pending:
                pending["step"] = np.zeros(3)
            if key in pending:
                raise reader.error(
                    f"{token.text} appears twice for one TRANSLACAO.",
                    token,
                    fix="start each motion with its own TRANSLACAO line.",
                )
            pending[key] = reader.number(token)
        else:
            raise reader.error(
                f"unknown keyword '{shown(token.text)}' inside RESTRICOES.",
                token,
                fix=(
                    "only PONTOS_FIXOS, PONTOS_ALVO, PONTOS_PRESOS, TRANSLACAO, INI_TRANSL and "
                    "FIM_TRANSL belong here."
                ),
            )


def read_legacy_text(path: Path, what: str, fix: str) -> str:
    """Text of a FLEX3D-era file, UTF-8 or Latin-1; UserInputError naming `what` if it cannot be
    read."""
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise UserInputError(
            f"cannot read {what}: {exc.strerror}.", file=str(path), fix=fix
        ) from None
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def read_par(path: str | Path) -> Script:
    """Read a ``.PAR`` file (UTF-8 or Latin-1)."""
    path = Path(path)
    text = read_legacy_text(
        path,
        "the script",
        "check the path, or run 'eigengait cloth examples' for the shipped ones.",
    )
    return parse_par(text, path)
