"""The studio's file sandbox: every path typed in the page is resolved inside one root folder, or
refused."""

from __future__ import annotations

from pathlib import Path

from eigengait.errors import UserInputError


class Sandbox:
    """Resolves user-typed paths against `root`; anything landing outside it (`..`, absolute,
    symlinks) is refused."""

    def __init__(self, root: str | Path):
        self.root = Path(root).resolve()

    def resolve(self, text: str, suffixes: tuple[str, ...] = (), must_exist: bool = False) -> Path:
        """The absolute path of `text` inside the root, checked for suffix and (optionally)
        existence."""
        text = text.strip()
        if not text:
            raise UserInputError(
                "no file name given", fix="type a file name relative to the studio folder"
            )
        if not text.isprintable():
            raise UserInputError(
                "the file name holds a control character (e.g. a NUL byte)",
                file=repr(text),
                fix="type a plain file name relative to the studio folder",
            )
        path = (self.root / text).resolve()
        if not path.is_relative_to(self.root):
            raise UserInputError(
                f"'{text}' is outside the studio folder and was refused",
                file=text,
                fix=f"use a path inside {self.root}",
            )
        if suffixes and path.suffix.lower() not in suffixes:
            raise UserInputError(f"'{text}' must end with {' or '.join(suffixes)}", file=text)
        if must_exist and not path.is_file():
            raise UserInputError("file not found in the studio folder", file=text)
        return path

    def contains(self, path: str | Path) -> bool:
        """Whether a path (relative to the root, or absolute) lies inside the root."""
        return (self.root / path).resolve().is_relative_to(self.root)

    def relative(self, path: Path) -> str:
        """How the page shows a path inside the root."""
        return str(Path(path).resolve().relative_to(self.root))

    def files(self, pattern: str) -> list[str]:
        """Files inside the root matching a glob pattern (e.g. `**/*.xml`), as relative paths,
        sorted."""
        return sorted(
            self.relative(p)
            for p in self.root.glob(pattern)
            if p.is_file() and p.resolve().is_relative_to(self.root)
        )
