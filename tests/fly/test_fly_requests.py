"""``fly``'s request handlers against malformed requests and clients that leave: every one gets a
4xx and one line in the server's log, never a traceback, and the server goes on serving.
"""

import http.client
import json
import socket
import struct
import time

import pytest

import hosedrogue as hd
from hosedrogue import fly


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    sc = hd.load_scenario("approach-moderate").with_overrides(duration_s=0.6)
    lines = []
    flight = fly.LiveFlight(sc, tmp_path_factory.mktemp("flights"), log=lines.append)
    srv = fly.FlyServer(flight, idle_timeout_s=60.0, log=lines.append).start()
    yield srv, lines
    srv.stop("the test's end")


def request(srv, method, path, body: bytes | None = None, headers=None):
    host, port = srv.httpd.server_address[:2]
    conn = http.client.HTTPConnection(host, port, timeout=10)
    conn.request(method, path, body=body, headers={"Content-Type": "application/json", **(headers or {})})
    resp = conn.getresponse()
    data = resp.read()
    conn.close()
    return resp.status, data


def new_lines(lines, before):
    time.sleep(0.05)  # the handler's thread logs before it answers; a margin for the scheduler
    return lines[before:]


MALFORMED = {
    "action not a string": ("/control", json.dumps({"action": ["start"]}).encode(), "action = ['start']"),
    "2000-deep array": ("/input", b"[" * 2000 + b"]" * 2000, "nested too deeply"),
    "2000-deep array in v": ("/input", b'{"v": ' + b"[" * 2000 + b"]" * 2000 + b"}", "nested too deeply"),
    "body not an object": ("/control", b'["start"]', "expected an object"),
    "not JSON": ("/input", b"{v: 1", "not JSON"),
    "a number past float": ("/input", b'{"v": [1' + b"0" * 400 + b', 0, 0]}', "must be three numbers"),
    "v not numbers": ("/input", json.dumps({"v": {"a": 1}}).encode(), "must be three numbers"),
    "unknown route": ("/nowhere", b"{}", "not found"),
}


@pytest.mark.parametrize("case", list(MALFORMED))
def test_a_malformed_request_is_a_4xx_and_one_log_line(server, capsys, case):
    srv, lines = server
    path, body, words = MALFORMED[case]
    before = len(lines)
    status, data = request(srv, "POST", path, body)
    assert 400 <= status < 500, (status, data)
    assert words in json.loads(data)["error"]
    logged = new_lines(lines, before)
    assert len(logged) == 1 and words in logged[0] and "\n" not in logged[0], logged
    assert "Traceback" not in capsys.readouterr().err
    assert request(srv, "GET", "/status")[0] == 200  # the server goes on


def test_a_malformed_request_line_is_one_log_line(server, capsys):
    srv, lines = server
    before = len(lines)
    with socket.create_connection(srv.httpd.server_address[:2], timeout=10) as s:
        s.sendall(b"GARBAGE\r\n\r\n")
        answer = s.recv(200)
    assert b"Error code: 400" in answer, answer  # an HTTP/0.9 request line: the answer has no status line
    logged = new_lines(lines, before)
    assert len(logged) == 1 and "400" in logged[0], logged
    assert "Traceback" not in capsys.readouterr().err


def test_a_client_that_leaves_early_is_one_line(server, capsys):
    """A command whose body never comes: the client resets the connection (SO_LINGER 0) after the
    headers, so the server's read of the body fails, which is one line."""
    srv, lines = server
    host, port = srv.httpd.server_address[:2]
    for _ in range(3):
        before = len(lines)
        s = socket.create_connection((host, port), timeout=10)
        s.sendall(f"POST /input HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Length: 100\r\n\r\n".encode())
        time.sleep(0.1)  # the handler is waiting for the body
        s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        s.close()
        time.sleep(0.3)
        logged = lines[before:]
        assert len(logged) == 1 and "left before its answer" in logged[0], logged
    assert "Traceback" not in capsys.readouterr().err
    assert request(srv, "GET", "/status")[0] == 200
