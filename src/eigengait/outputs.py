"""Output files the user asked for: checked before any work starts, never overwritten silently,
written atomically.

Every file is written under a temporary name in its own folder (`.NAME.XXXXXXXX.part.SUFFIX`) and
renamed onto its final name only when complete, so an interrupted or failed write never leaves a
half file under the final name.
"""

from __future__ import annotations

import os
import secrets
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from eigengait.errors import UserInputError


def check_output(path: Path, force: bool) -> None:
    """Raise unless `path` can be written: not a folder, not existing (unless `force`), its folder
    created and writable."""
    if "\0" in str(path):
        raise UserInputError(
            "the output path contains a NUL byte", file=repr(str(path)), fix="choose another name"
        )
    try:
        _check_target(path, force)
    except OSError as exc:
        raise UserInputError(
            f"unusable output path ({exc.strerror or exc.__class__.__name__})",
            file=path,
            fix="choose another name",
        ) from None
    _check_writable(path.parent)


def _check_writable(folder: Path) -> None:
    """Create the folder if needed and try a file in it."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except (FileExistsError, NotADirectoryError):
        raise UserInputError(
            "the output's folder cannot be created: a file of that name is in the way",
            file=folder,
            fix="choose another location",
        ) from None
    except OSError as exc:
        raise UserInputError(
            f"cannot write in the output's folder ({exc.strerror or exc.__class__.__name__})",
            file=folder,
            fix="choose a writable location",
        ) from None


def _check_target(path: Path, force: bool) -> None:
    if path.is_dir():
        raise UserInputError(
            "the output path is a folder, not a file (force=True does not replace folders)",
            file=path,
            fix="name a file inside it",
        )
    if path.exists() and not force:
        raise UserInputError(
            "the output file exists and was left untouched",
            file=path,
            fix="pass force=True to replace it, or choose another name",
        )


def require_suffix(path: Path | None, suffixes: tuple[str, ...], option: str) -> None:
    """Raise unless `path` is None or ends in one of `suffixes` (lower case, with the dot)."""
    if path is not None and path.suffix.lower() not in suffixes:
        raise UserInputError(
            f"cannot write '{path.suffix or 'no extension'}' files",
            file=path,
            field=option,
            fix=f"name the file with one of: {', '.join(suffixes)}",
        )


def refuse_existing(paths: list[Path | None], force: bool) -> None:
    """Check every given output path with `check_output` (None entries are skipped)."""
    for path in paths:
        if path is not None:
            check_output(path, force)


def check_folder(folder: Path) -> None:
    """Raise unless `folder` is, or can be created as, a writable folder."""
    if folder.exists() and not folder.is_dir():
        raise UserInputError(
            "the output is a file, not a folder", file=folder, fix="choose a folder name"
        )
    _check_writable(folder)


@contextmanager
def replacing(path: Path | str) -> Iterator[Path]:
    """A temporary path beside `path`, with the same suffix, to write the whole file to; renamed
    onto `path` when the block completes, removed if it fails."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.name}.{secrets.token_hex(4)}.part{path.suffix}")
    try:
        yield temporary
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def write_atomically(path: Path | str, text: str) -> None:
    """Write UTF-8 text through a temporary file and a rename."""
    with replacing(path) as temporary:
        temporary.write_text(text, encoding="utf-8")


def keep_mujoco_log_out_of_the_folder() -> None:
    """Print MuJoCo's warnings on standard error instead of appending them to MUJOCO_LOG.TXT in the
    current folder."""
    import mujoco

    mujoco.set_mju_user_warning(_print_mujoco_warning)


def _print_mujoco_warning(message: str) -> None:
    print(f"MuJoCo warning: {message}", file=sys.stderr)
