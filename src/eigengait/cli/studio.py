"""The `studio` command: the browser UI for sketching, optimizing and playing gaits."""

from __future__ import annotations

from typing import Optional

import typer


def studio_command(
    target: Optional[str] = typer.Argument(
        None,
        help="Built-in character, MJCF file, shipped sketch or sketch "
        "file (default: the folder's autosave, else humanoid).",
    ),
    host: str = typer.Option(
        "127.0.0.1", "--host", help="Address to listen on (0.0.0.0 for the network)."
    ),
    port: int = typer.Option(8080, "--port", help="Port to listen on (1-65535)."),
):
    """Open the studio in the browser (the printed address carries its access token); it reads and
    writes files only inside the current folder."""
    from eigengait.studio.app import main

    main(target, host, port)


def register(app: typer.Typer) -> None:
    app.command("studio")(studio_command)
