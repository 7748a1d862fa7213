"""Where the studio listens: the port and address are checked before the server starts, with one
clear error."""

from __future__ import annotations

import errno
import ipaddress
import socket
import sys

from eigengait.errors import UserInputError

PORT_FIX = "choose a free port between 1 and 65535, e.g. port=8090"


def check_listen_address(host: str, port: int) -> None:
    """Refuse a port out of range or taken, or an address that cannot be bound; warn when the studio
    would be reachable from other machines."""
    if not 1 <= port <= 65535:
        raise UserInputError(f"port {port} is out of range", field="port", fix=PORT_FIX)
    family, address = _resolve(host, port)
    try:
        with socket.socket(family, socket.SOCK_STREAM) as probe:
            # as the server itself binds
            probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            probe.bind(address)
    except OSError as exc:
        raise _bind_error(host, port, exc) from None
    if not ipaddress.ip_address(address[0]).is_loopback:
        print(
            f"warning: the studio listens on {host} and is reachable from the network; only a "
            "browser opening the printed address with its token can use it, and it reads and "
            "writes files in this folder.",
            file=sys.stderr,
            flush=True,
        )


def port_taken(host: str, port: int) -> UserInputError:
    return UserInputError(f"port {port} on {host} is already in use", field="port", fix=PORT_FIX)


def _resolve(host: str, port: int) -> tuple[int, tuple]:
    try:
        family, _, _, _, address = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)[0]
    except (OSError, UnicodeError) as exc:
        raise UserInputError(
            f"cannot listen on '{host}' ({getattr(exc, 'strerror', None) or exc})",
            field="host",
            fix="use a local address such as 127.0.0.1 or 0.0.0.0",
        ) from None
    return family, address


def _bind_error(host: str, port: int, exc: OSError) -> UserInputError:
    if exc.errno == errno.EADDRINUSE:
        return port_taken(host, port)
    if exc.errno == errno.EACCES:
        return UserInputError(
            f"port {port} needs special rights",
            field="port",
            fix="choose a port above 1023, e.g. port=8090",
        )
    return UserInputError(
        f"cannot listen on {host}:{port} ({exc.strerror or exc})",
        field="host",
        fix="use a local address such as 127.0.0.1 or 0.0.0.0",
    )
