"""Who may talk to the studio: its own page, on its own host and port, holding the access token.

Every HTTP request and WebSocket handshake passes `AccessGate.refusal` before viser sees it, and is
answered 403 otherwise:
- the Host header names the studio's port and a loopback name (localhost, 127.0.0.1, [::1]) or the
  bound address; bound to all interfaces (0.0.0.0, ::), also any IP address or this machine's name.
  A DNS-rebound name is refused.
- an Origin header, when the browser sends one, is the page's own (`http://` + Host): no other
  site's page may open the studio's WebSocket.
- the access token comes in the URL (`?token=…`, as the studio prints it) or in the cookie set by
  the first request that carried it, so the page's assets and its WebSocket need nothing more.
"""

from __future__ import annotations

import contextlib
import hmac
import http
import inspect
import ipaddress
import secrets
import socket
from collections.abc import Callable, Iterator
from urllib.parse import parse_qs, urlsplit

import websockets.asyncio.server
from websockets.http11 import Request, Response

LOOPBACK_NAMES = ("localhost", "127.0.0.1", "::1")
ALL_INTERFACES = ("0.0.0.0", "::", "")
ProcessRequest = Callable[..., object] | None


class AccessGate:
    def __init__(self, host: str, port: int, token: str | None = None):
        self.port = port
        self.token = token or secrets.token_urlsafe(32)
        self.cookie = f"eigengait-studio-{port}"
        self.bound = host.strip("[]").lower()
        self.names = {*LOOPBACK_NAMES, self.bound}
        if self.all_interfaces:
            self.names |= {socket.gethostname().lower(), socket.getfqdn().lower()}

    @property
    def all_interfaces(self) -> bool:
        return self.bound in ALL_INTERFACES

    def refusal(self, request: Request) -> str | None:
        """Why the request is refused, or None when it may pass."""
        host = request.headers.get("Host", "")
        if not self._is_own(host):
            return f"the host '{host}' is not this studio's"
        origin = request.headers.get("Origin")
        if origin is not None and not _same_origin(origin, host):
            return f"requests from the page '{origin}' are not accepted"
        if not self._has_token(request):
            return "open the studio with the address it printed (it carries ?token=…)"
        return None

    def _is_own(self, host: str) -> bool:
        name, port = _address(f"//{host}")
        return (
            bool(name)
            and port == self.port
            and (name in self.names or (self.all_interfaces and _is_ip(name)))
        )

    def _has_token(self, request: Request) -> bool:
        return any(
            hmac.compare_digest(t.encode(), self.token.encode())
            for t in [*_url_tokens(request), *self._cookie_tokens(request)]
        )

    def _cookie_tokens(self, request: Request) -> list[str]:
        pairs = (
            p.strip().partition("=")
            for h in request.headers.get_all("Cookie")
            for p in h.split(";")
        )
        return [value for key, _, value in pairs if key == self.cookie]

    def guard(self, process_request: ProcessRequest) -> Callable:
        """A websockets `process_request` hook: refuse with 403, else run viser's own and hand out
        the cookie."""

        async def guarded(connection: websockets.asyncio.server.ServerConnection, request: Request):
            reason = self.refusal(request)
            if reason is not None:
                return connection.respond(http.HTTPStatus.FORBIDDEN, f"Forbidden: {reason}.\n")
            response = process_request(connection, request) if process_request else None
            if inspect.isawaitable(response):
                response = await response
            if isinstance(response, Response) and _url_tokens(request):
                response.headers["Set-Cookie"] = (
                    f"{self.cookie}={self.token}; Path=/; HttpOnly; SameSite=Strict"
                )
            return response

        return guarded


@contextlib.contextmanager
def guarded_serving(gate: AccessGate) -> Iterator[list[int]]:
    """While viser starts its server, every `websockets.asyncio.server.serve` gets the gate as its
    request hook.

    Yields the ports served so far: empty afterwards means the gate was never installed.
    """
    original = websockets.asyncio.server.serve
    ports: list[int] = []

    def serve(handler, host, port, *args, process_request: ProcessRequest = None, **kwargs):
        ports.append(port)
        return original(
            handler, host, port, *args, process_request=gate.guard(process_request), **kwargs
        )

    websockets.asyncio.server.serve = serve
    try:
        yield ports
    finally:
        websockets.asyncio.server.serve = original


def _address(url: str) -> tuple[str, int | None]:
    """(lower-case host name without brackets, port) of a URL; an unreadable port counts as none."""
    parts = urlsplit(url)
    try:
        port = parts.port or 80
    except ValueError:
        port = None
    return (parts.hostname or "", port)


def _same_origin(origin: str, host: str) -> bool:
    """Whether an Origin header names the page served from `host` (the studio speaks plain http)."""
    return origin.startswith("http://") and _address(origin) == _address(f"//{host}")


def _url_tokens(request: Request) -> list[str]:
    return parse_qs(urlsplit(request.path).query).get("token", [])


def _is_ip(name: str) -> bool:
    try:
        ipaddress.ip_address(name)
    except ValueError:
        return False
    return True
