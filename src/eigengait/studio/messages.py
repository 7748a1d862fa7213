"""Messages to the animator: a status line every tab sees, plus a notification in the tab that
acted.

`guarded` wraps GUI callbacks so bad input or a blow-up (an EigengaitError) becomes a red message
instead of a server error; `write_asking` asks the tab before a save or export replaces an existing
file.
"""

from __future__ import annotations

import functools
import traceback
from collections.abc import Callable
from pathlib import Path

import viser

from eigengait.errors import EigengaitError


class Messages:
    def __init__(self, server: viser.ViserServer):
        self.server = server
        self.status = server.gui.add_markdown("Ready.", order=0.5)

    def info(self, text: str, client: viser.ClientHandle | None = None) -> None:
        self.status.content = text
        if client is not None:
            client.add_notification("eigengait", text, auto_close_seconds=4.0, color="blue")

    def error(self, text: str, client: viser.ClientHandle | None = None) -> None:
        self.status.content = f"Refused: {text}"
        targets = [client] if client is not None else list(self.server.get_clients().values())
        for c in targets:
            c.add_notification("Refused", text, auto_close_seconds=8.0, color="red")

    def guarded(
        self, callback: Callable[[viser.GuiEvent], None]
    ) -> Callable[[viser.GuiEvent], None]:
        """A GUI callback that reports an EigengaitError (and unexpected errors) instead of
        raising."""

        @functools.wraps(callback)
        def run(event: viser.GuiEvent) -> None:
            try:
                callback(event)
            except EigengaitError as err:
                self.error(str(err), event.client)
            except Exception as exc:  # the server must survive any single action
                traceback.print_exc()
                self.error(f"unexpected error: {exc.__class__.__name__}: {exc}", event.client)

        return run

    def write_asking(
        self, client: viser.ClientHandle, path: Path, shown: str, write: Callable[[], None]
    ) -> None:
        """Write a new file at once; an existing one only after the tab confirms in a dialog."""
        if not path.exists():
            write()
            return
        with client.gui.add_modal("Replace the file?") as modal:
            client.gui.add_markdown(f"`{shown}` already exists in the studio folder.")
            replace = client.gui.add_button("Overwrite", color="red")
            keep = client.gui.add_button("Keep the file")

        def on_replace(event: viser.GuiEvent) -> None:
            modal.close()
            write()

        def on_keep(event: viser.GuiEvent) -> None:
            modal.close()
            self.info(f"Kept `{shown}`: nothing was written.", client)

        replace.on_click(self.guarded(on_replace))
        keep.on_click(self.guarded(on_keep))
