"""Only the studio's own page gets in: Host, Origin and token on HTTP and WebSocket; the port is
exactly the one asked."""

import http.client
import socket

import pytest
import viser
import websockets.exceptions
import websockets.sync.client
from conftest import free_port
from websockets.datastructures import Headers
from websockets.http11 import Request

from eigengait.errors import UserInputError
from eigengait.studio.access import AccessGate
from eigengait.studio.app import start_server
from eigengait.studio.listen import check_listen_address


@pytest.fixture(scope="module")
def served():
    """A guarded viser server (no character: the gate is all that is tested here)."""
    gate = AccessGate("127.0.0.1", free_port())
    server = start_server(gate, "127.0.0.1", gate.port)
    yield gate, server
    server.stop()


def get(gate, path="/", **headers):
    connection = http.client.HTTPConnection("127.0.0.1", gate.port, timeout=10)
    try:
        connection.putrequest("GET", path, skip_host="Host" in headers)
        for key, value in headers.items():
            connection.putheader(key, value)
        connection.endheaders()
        response = connection.getresponse()
        return response.status, response.getheader("Set-Cookie"), response.read()
    finally:
        connection.close()


def test_the_printed_address_opens_the_page_and_hands_out_the_cookie(served):
    gate, _ = served
    status, cookie, body = get(gate, f"/?token={gate.token}")
    assert status == 200 and b"<html" in body.lower()
    assert (
        cookie.startswith(f"{gate.cookie}={gate.token};")
        and "HttpOnly" in cookie
        and "SameSite=Strict" in cookie
    )
    assert get(gate, "/", Cookie=f"other=1; {gate.cookie}={gate.token}")[0] == 200


@pytest.mark.parametrize(
    "path, headers",
    [
        ("/", {}),
        ("/?token=wrong", {}),
        ("/", {"Cookie": "eigengait-studio-1=x"}),
        ("/?token={token}", {"Origin": "http://evil.example.com"}),
        ("/?token={token}", {"Origin": "null"}),
        ("/?token={token}", {"Origin": "https://127.0.0.1:{port}"}),
        ("/?token={token}", {"Host": "evil.example.com:{port}"}),
        ("/?token={token}", {"Host": "127.0.0.1:1"}),
        ("/?token={token}", {"Host": "localhost:{port}", "Origin": "http://127.0.0.1:{port}"}),
    ],
)
def test_http_without_own_host_origin_and_token_is_refused(served, path, headers):
    gate, _ = served
    values = {"token": gate.token, "port": gate.port}
    status, cookie, body = get(
        gate, path.format(**values), **{k: v.format(**values) for k, v in headers.items()}
    )
    assert status == 403 and cookie is None and body.startswith(b"Forbidden")


@pytest.mark.parametrize("host", ["localhost", "127.0.0.1", "[::1]", "LocalHost"])
def test_loopback_names_and_the_page_own_origin_are_accepted(served, host):
    gate, _ = served
    own = f"{host}:{gate.port}"
    assert get(gate, f"/?token={gate.token}", Host=own, Origin=f"http://{own}")[0] == 200


def connect(gate, origin, token):
    return websockets.sync.client.connect(
        f"ws://127.0.0.1:{gate.port}",
        origin=origin,
        open_timeout=10,
        subprotocols=[f"viser-v{viser.__version__}"],
        additional_headers={"Cookie": f"{gate.cookie}={token}"} if token else None,
    )


@pytest.mark.parametrize(
    "origin, token",
    [
        ("http://evil.example.com", "right"),
        ("http://127.0.0.1:{port}", None),
        ("http://127.0.0.1:{port}", "wrong"),
    ],
)
def test_websocket_handshakes_from_elsewhere_or_without_the_token_are_refused(
    served, origin, token
):
    gate, server = served
    with pytest.raises(websockets.exceptions.InvalidStatus) as refused:
        connect(gate, origin.format(port=gate.port), gate.token if token == "right" else token)
    assert refused.value.response.status_code == 403
    assert not server.get_clients(), "a refused handshake never becomes a client"


def test_the_page_own_websocket_is_accepted(served):
    gate, _ = served
    with connect(gate, f"http://127.0.0.1:{gate.port}", gate.token) as ws:
        assert ws.recv(timeout=10)


def test_bound_to_all_interfaces_any_ip_address_is_the_studio_but_a_name_is_not():
    gate = AccessGate("0.0.0.0", 8080, token="t")
    request = lambda host: Request("/?token=t", Headers(Host=host))  # noqa: E731
    assert gate.refusal(request("192.168.1.20:8080")) is None
    assert gate.refusal(request(f"{socket.gethostname()}:8080")) is None
    assert "evil.example.com" in gate.refusal(request("evil.example.com:8080"))
    assert AccessGate("127.0.0.1", 8080, token="t").refusal(request("192.168.1.20:8080"))


def test_a_port_taken_since_the_check_is_an_error_not_another_port():
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        with pytest.raises(UserInputError, match=f"port {port} .*already in use"):
            start_server(AccessGate("127.0.0.1", port), "127.0.0.1", port)


def test_listening_beyond_loopback_warns_that_the_token_is_required(capsys):
    check_listen_address("0.0.0.0", free_port())
    warning = capsys.readouterr().err
    assert "reachable from the network" in warning and "token" in warning
    check_listen_address("127.0.0.1", free_port())
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("port", ["99999", "busy"])
def test_a_bad_or_busy_port_exits_2_with_one_message(tmp_path, eigengait_cli, port):
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        number = str(busy.getsockname()[1]) if port == "busy" else port
        result = eigengait_cli("studio", "--port", number, cwd=tmp_path, timeout=60)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert (
        "'--port'" in result.stderr
        and f"port {number}" in result.stderr
        and "Fix:" in result.stderr
    )
    assert "eigengait studio: http" not in result.stdout
