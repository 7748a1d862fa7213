"""The `studio` command: the browser UI for sketching, optimizing and playing gaits."""

from __future__ import annotations

from typing import Optional

import typer


def studio_command(
        target: Optional[str] = typer.Argument(None, help="Built-in character, MJCF file, shipped sketch or sketch "
                                                          "file (default: the folder's autosave, else humanoid)."),
        host: str = typer.Option("127.0.0.1", "--host", help="Address to listen on (0.0.0.0 for the network)."),
        port: int = typer.Option(8080, "--port", min=1, max=65535, help="Port to listen on.")):
    """Open the studio in the browser; it reads and writes files only inside the current folder."""
    from eigengait.studio.app import main
    check_listen_address(host, port)
    main(target, host, port)


def check_listen_address(host: str, port: int) -> None:
    """Refuse a port that is taken or an address that cannot be bound, before the server starts; warn when the
    studio would be reachable from other machines."""
    import ipaddress
    import socket

    from rich.console import Console

    from eigengait.errors import UserInputError
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
        family, _, _, _, address = infos[0]
        with socket.socket(family, socket.SOCK_STREAM) as probe:
            probe.bind(address)
    except (OSError, UnicodeError, ValueError) as exc:
        raise UserInputError(f"cannot listen on {host}:{port} ({getattr(exc, 'strerror', None) or exc})",
                             field="--host/--port", fix="choose a free port, or a local address") from None
    if not ipaddress.ip_address(address[0]).is_loopback:
        Console(stderr=True).print(f"[yellow]warning:[/] the studio listens on {host}, beyond this machine: anyone "
                                   "who can reach it can read and write files in this folder.", highlight=False)


def register(app: typer.Typer) -> None:
    app.command("studio")(studio_command)
