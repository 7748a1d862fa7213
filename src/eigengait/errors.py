"""The errors users see: each names the file, the field and the fix.

Every module raises :class:`UserInputError` for bad input (a malformed file, an unknown name, an
impossible parameter) and :class:`SimulationBlowUp` when the physics diverges. Both are
:class:`EigengaitError`, which the CLI prints as one message before exiting with status 2.
"""

from __future__ import annotations


class EigengaitError(Exception):
    """An error reported to the user without a traceback.

    Args:
        message: what is wrong, in one sentence.
        file: the file concerned (path or built-in name), if any.
        field: the field, keyword, line or element concerned, if any.
        fix: what the user should do about it, if known.
    """

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        field: str | None = None,
        fix: str | None = None,
    ):
        self.message = message
        self.file = None if file is None else str(file)
        self.field = field
        self.fix = fix
        super().__init__(self.__str__())

    def __str__(self) -> str:
        where = ", ".join(
            p
            for p in (self.file and f"file '{self.file}'", self.field and f"field '{self.field}'")
            if p
        )
        text = f"{where}: {self.message}" if where else self.message
        if self.fix:
            text += f" Fix: {self.fix}"
        return text


class UserInputError(EigengaitError):
    """Bad input from the user: a file, a name or a parameter the library cannot use."""


class SimulationBlowUp(EigengaitError):
    """The physics diverged (NaN or runaway energy); the message names the time and the body."""
