"""The live flight's web server: Python's ``http.server`` (``ThreadingHTTPServer``), on 127.0.0.1
by default.

Routes: ``GET /`` the page; ``GET /events`` a Server-Sent Events stream of the state (``status``
and ``frame`` events, ``bye`` when the server stops); ``POST /input`` the person's command
``{"v": [v_x, v_y, v_z], "source": "keyboard"}``; ``POST /control`` ``{"action": "start" | "pause"
| "resume" | "end" | "again"}``; ``POST /bye`` the page is leaving; ``GET /status``; ``GET
/flights/N/view.html`` the viewer's page of flight N (the replay). Nothing else is served: no
file of the machine is reachable but the flights' pages.

Requests must name the server itself as their ``Host`` (a guard against a web page that points
a domain of its own at 127.0.0.1) and a POST from a page must come from the server's own origin.

The server stops (writing the flight in progress first) on :meth:`FlyServer.stop` - the command
line calls it on Ctrl-C - and when no page has been connected for ``idle_timeout_s`` after one
was: a flight in progress is paused as soon as the last page goes.
"""

from __future__ import annotations

import errno
import http.server
import ipaddress
import json
import re
import socket
import threading
import time
from pathlib import Path

from ..errors import ParameterError
from .session import LiveFlight

__all__ = ["FlyServer", "bind_server", "PORT_TRIES", "LOOPBACK"]

#: Ports tried after a given busy one (then any free port) unless the port is strict.
PORT_TRIES = 20
#: The host names that stay on this machine.
LOOPBACK = ("127.0.0.1", "localhost", "::1")
#: The largest request body read [bytes] (a command is tens of bytes).
MAX_BODY = 4096


def is_loopback(host: str) -> bool:
    """Whether ``host`` names this machine only (127.0.0.0/8, ::1, localhost).

    Parameters
    ----------
    host : str
        A host name or address.

    Returns
    -------
    bool
    """
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


#: A client that went away while it was answered: a line in the log, not an error.
GONE = (BrokenPipeError, ConnectionResetError, ConnectionAbortedError, TimeoutError)


def _server_class(family: int):
    class Server(http.server.ThreadingHTTPServer):
        address_family = family
        daemon_threads = True
        allow_reuse_address = True  # a port left in TIME_WAIT is free; one with a listener is not

        def handle_error(self, request, client_address):
            """One line for what a request's handler did not catch (socketserver prints a traceback)."""
            import sys

            exc = sys.exc_info()[1]
            log = getattr(getattr(self, "fly", None), "log", print)
            if isinstance(exc, GONE):
                log(f"fly: a page at {client_address[0]} left before its answer ({type(exc).__name__})")
            else:
                log(f"fly: a request from {client_address[0]} failed ({type(exc).__name__}: {exc})")

    return Server


def bind_server(host: str, port: int, strict: bool = False, handler=None) -> tuple[http.server.ThreadingHTTPServer, str | None]:
    """Bind the server: ``port`` (0: a free one); a busy port is refused (``strict``) or another
    is picked: the next :data:`PORT_TRIES` ports, then any free one.

    Parameters
    ----------
    host : str
        Address or name to listen on.
    port : int
        Port [-], 0 for a free one.
    strict : bool
        Refuse a busy port instead of picking another.
    handler : type, optional
        The request handler class (default: the flight's routes).

    Returns
    -------
    server : http.server.ThreadingHTTPServer
    note : str or None
        Why the port differs from the one asked for.

    Raises
    ------
    ParameterError
        One line: a host that is not this machine's, a busy port with ``strict``, a port not allowed.
    """
    try:
        family = socket.getaddrinfo(host, port or None, type=socket.SOCK_STREAM)[0][0]
    except (socket.gaierror, UnicodeError) as exc:
        raise ParameterError(f"--host = {host!r}: not a host name or address of this machine ({exc})") from None
    handler = handler or _Handler
    tries = [port] if port == 0 or strict else [port, *range(port + 1, min(port + 1 + PORT_TRIES, 65536)), 0]
    for p in tries:
        try:
            server = _server_class(family)((host, p), handler)
        except OSError as exc:
            if exc.errno == errno.EADDRINUSE:
                if strict:
                    free = _free_port(host, family, port)
                    use = f"port {free} is free (--port {free}), or" if free else "give another port or"
                    raise ParameterError(
                        f"--port = {port}: in use on {host} (another program, or another hosedrogue fly); {use} "
                        "leave out --port for any free one") from None
                continue
            if exc.errno == errno.EADDRNOTAVAIL:
                raise ParameterError(f"--host = {host!r}: not an address of this machine") from None
            if exc.errno == errno.EACCES:
                raise ParameterError(f"--port = {port}: not allowed to listen there (below 1024 needs privileges); "
                                     "give a port above 1023, or --port 0 for a free one") from None
            raise ParameterError(f"--host {host} --port {p}: cannot listen there: {exc.strerror}") from None
        note = None
        if p != port:
            note = (f"port {port} is in use on {host}; serving on port {server.server_address[1]} instead "
                    "(strict=True refuses a busy port)")
        return server, note
    raise ParameterError(f"--port = {port}: no free port found")  # pragma: no cover - port 0 always binds


def _free_port(host: str, family: int, after: int) -> int | None:
    """The first of the :data:`PORT_TRIES` ports after ``after`` that is free on ``host`` now (None
    if none is): what the message of a busy port suggests."""
    for p in range(after + 1, min(after + 1 + PORT_TRIES, 65536)):
        with socket.socket(family, socket.SOCK_STREAM) as probe:
            try:
                probe.bind((host, p))
            except OSError:
                continue
            return p
    return None


class _Handler(http.server.BaseHTTPRequestHandler):
    """The routes of the module docstring; ``self.server.fly`` is the :class:`FlyServer`."""

    server_version = "hosedrogue-fly"

    def log_message(self, format, *args):  # noqa: A002 - the base class's name
        pass  # quiet: the command prints what matters

    def log_error(self, format, *args):  # noqa: A002 - the base class's name
        """One line for a request http.server refuses itself (a malformed request line or header)."""
        self._log(f"{self.address_string()}: " + (format % args))

    def _log(self, line: str) -> None:
        getattr(getattr(self.server, "fly", None), "log", print)(f"fly: {line}"[:300])

    def _refuse(self, code: int, why: str) -> None:
        """Answer ``code`` with ``why`` and log it in one line."""
        self._log(f"{self.command} {self.path[:80]}: {code} ({why})")
        self._send(code, {"error": why})

    # --- guards ----------------------------------------------------------------------------------
    def _allowed(self) -> bool:
        fly = self.server.fly
        host = self.headers.get("Host", "")
        if fly.check_host and host not in fly.hosts:
            self._refuse(403, f"Host {host!r}: this server answers only as {sorted(fly.hosts)[0]}")
            return False
        origin = self.headers.get("Origin")
        if self.command == "POST" and origin is not None and origin != f"http://{host}":
            self._refuse(403, f"Origin {origin!r}: requests come from the server's own page only")
            return False
        return True

    def _send(self, code: int, body, content_type: str = "application/json") -> None:
        data = body if isinstance(body, bytes) else json.dumps(body).encode()
        self.send_response(code)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.end_headers()
        if self.command != "HEAD":
            self.wfile.write(data)

    def _body(self):
        try:
            size = int(self.headers.get("Content-Length", "0"))
        except ValueError:
            size = -1
        if not 0 <= size <= MAX_BODY:
            raise ParameterError(f"request body of {size} bytes: at most {MAX_BODY}")
        try:
            body = json.loads(self.rfile.read(size) or b"{}")
        except ValueError:
            raise ParameterError("request body: not JSON") from None
        except RecursionError:  # the parser's stack: arrays nested thousands deep
            raise ParameterError("request body: JSON nested too deeply") from None
        if not isinstance(body, dict):
            raise ParameterError(f"request body: a JSON {type(body).__name__}, expected an object")
        return body

    # --- routes ------------------------------------------------------------------------------------
    def do_GET(self):  # noqa: N802 - the base class's name
        if not self._allowed():
            return
        fly = self.server.fly
        path = self.path.split("?", 1)[0]
        if path in ("/", "/index.html"):
            self._send(200, fly.page, "text/html; charset=utf-8")
        elif path == "/events":
            self._events()
        elif path == "/status":
            self._send(200, fly.status())
        elif (m := re.fullmatch(r"/flights/(\d+)/view\.html", path)) and int(m.group(1)) in fly.flight.folders:
            page = Path(fly.flight.folders[int(m.group(1))]) / "view.html"
            self._send(200, page.read_bytes(), "text/html; charset=utf-8")
        elif path == "/favicon.ico":  # browsers ask for it unbidden: not worth a line
            self._send(404, {"error": f"{path}: not found"})
        else:
            self._refuse(404, f"{path[:80]}: not found")

    def do_POST(self):  # noqa: N802 - the base class's name
        if not self._allowed():
            return
        fly, path = self.server.fly, self.path.split("?", 1)[0]
        try:
            body = self._body()
            if path == "/input":
                fly.flight.set_command(body.get("v"), body.get("source", "keyboard"), body.get("seq"))
                self._send(200, {"ok": True})
            elif path == "/control":
                action = body.get("action")
                act = {"start": fly.flight.start, "pause": fly.flight.pause, "resume": fly.flight.resume,
                       "end": fly.flight.end, "again": fly.flight.again}.get(action) if isinstance(action, str) else None
                if act is None:
                    raise ParameterError(f"action = {action!r}: must be start, pause, resume, end or again")
                self._send(200, {"ok": act(), "state": fly.flight.state})
            elif path == "/bye":
                fly.page_left()
                self._send(200, {"ok": True})
            else:
                self._refuse(404, f"{path[:80]}: not found")
        except ParameterError as exc:
            self._refuse(400, str(exc))

    def _events(self):
        """The Server-Sent Events stream: the latest status and frame whenever they change, a
        comment every half second otherwise (so a closed page is noticed), ``bye`` at the end."""
        fly = self.server.fly
        self.send_response(200)
        self.send_header("Content-Type", "text/event-stream")
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        fly.page_joined()
        seq, sent_frame, sent_status = 0, None, None
        try:
            while True:
                seq, frame, status = fly.flight.wait_update(seq, 0.5)
                chunk = []
                if status is not None and status is not sent_status:
                    chunk.append(f"event: status\ndata: {status}\n\n")
                    sent_status = status
                if frame is not None and frame is not sent_frame:
                    chunk.append(f"event: frame\ndata: {frame}\n\n")
                    sent_frame = frame
                closing = fly.flight.state == "closed"
                if closing:
                    chunk.append("event: bye\ndata: {}\n\n")
                self.wfile.write(("".join(chunk) or ": ping\n\n").encode())
                self.wfile.flush()
                if closing:
                    break
        except (BrokenPipeError, ConnectionResetError, ConnectionAbortedError, TimeoutError, OSError):
            pass
        finally:
            fly.page_left(stream=True)
            self.close_connection = True


class FlyServer:
    """``hosedrogue fly``'s server around a :class:`~hosedrogue.fly.session.LiveFlight`.

    Parameters
    ----------
    flight : LiveFlight
        The session to serve.
    host : str
        Address to listen on (127.0.0.1; another exposes the flight to whoever reaches it).
    port : int
        Port [-], 0 for a free one (:func:`bind_server`).
    strict_port : bool
        Refuse a busy port instead of picking another.
    idle_timeout_s : float
        Stop this long after the last page went [s] (a reload comes back well within it).
    log : callable
        Gets the server's one-line messages.
    bound : (http.server.ThreadingHTTPServer, str or None), optional
        A server :func:`bind_server` bound already, and its note (the command line binds before it
        prepares the flight, so a busy port is refused at once); ``host``, ``port`` and
        ``strict_port`` are then not used.
    """

    def __init__(self, flight: LiveFlight, *, host: str = "127.0.0.1", port: int = 0, strict_port: bool = False,
                 idle_timeout_s: float = 5.0, log=print, bound=None):
        from ..viewer.live import live_html

        self.flight, self.host, self.port, self.strict = flight, host, int(port), bool(strict_port)
        self.idle_timeout_s = float(idle_timeout_s)
        self.log = log
        self.page = live_html(flight.facts()).encode()
        self._lock = threading.Lock()
        self._streams = 0
        self._ever = False
        self._gone_at = None
        self._threads: list[threading.Thread] = []
        self.httpd = None
        self.check_host = is_loopback(host)
        self.stopped = threading.Event()
        self._bound = bound

    @property
    def url(self) -> str:
        """The page's address (after :meth:`start`)."""
        host, port = self.httpd.server_address[:2]
        host = f"[{host}]" if ":" in host else host
        return f"http://{host}:{port}/"

    def start(self) -> "FlyServer":
        """Bind (one line of :class:`ParameterError` if it cannot), then serve and simulate in
        threads of their own.

        Returns
        -------
        FlyServer
            Itself.
        """
        self.httpd, note = self._bound or bind_server(self.host, self.port, self.strict)
        self.httpd.fly = self
        port = self.httpd.server_address[1]
        self.hosts = {f"{h}:{port}" for h in ("127.0.0.1", "localhost", "[::1]", self.host)}
        if note:
            self.log(note)
        for target in (self.httpd.serve_forever, self.flight.run_flights, self._watch):
            thread = threading.Thread(target=target, daemon=True, name=f"hosedrogue-fly-{target.__name__}")
            thread.start()
            self._threads.append(thread)
        return self

    def status(self) -> dict:
        """The session as ``GET /status`` gives it: the flight's status and the pages connected."""
        _, _, status = self.flight.wait_update(-1, 0.0)
        return {"url": self.url, "pages": self._streams, "status": json.loads(status) if status else None}

    def page_joined(self) -> None:
        """A page opened its event stream."""
        with self._lock:
            self._streams += 1
            self._ever = True
            self._gone_at = None

    def page_left(self, stream: bool = False) -> None:
        """A page closed its event stream (``stream``) or said it is leaving (the beacon): with no
        page left, the flight in progress pauses and the idle timeout starts."""
        with self._lock:
            if stream:
                self._streams = max(0, self._streams - 1)
            if self._streams == 0 or not stream:
                self._gone_at = time.monotonic() if self._gone_at is None else self._gone_at
                self.flight.pause()

    def _watch(self) -> None:
        """Stop once no page has been connected for the idle timeout (after one was)."""
        while not self.stopped.is_set() and self.flight.state != "closed":
            with self._lock:
                gone = self._ever and self._streams == 0 and self._gone_at is not None
                idle = gone and time.monotonic() - self._gone_at > self.idle_timeout_s
            if idle:
                self.stop("the page was closed")
                break
            self.stopped.wait(0.1)

    def stop(self, reason: str) -> None:
        """End the flight in progress (its files are written) and stop serving.

        Parameters
        ----------
        reason : str
            Recorded as how the flight ended ("Ctrl-C", "the page was closed").
        """
        self.flight.close(reason)

    def wait(self, timeout_s: float | None = None) -> bool:
        """Wait until the session has stopped (its last flight written), then stop serving.

        Parameters
        ----------
        timeout_s : float, optional
            Longest wait [s] (default: until it stops).

        Returns
        -------
        bool
            True if it stopped.
        """
        end = None if timeout_s is None else time.monotonic() + timeout_s
        while not self.flight.finished.wait(0.2):
            if end is not None and time.monotonic() > end:
                return False
        if not self.stopped.is_set():
            self.stopped.set()
            time.sleep(0.3)  # the event streams, woken by the state "closed", send their "bye"
            self.httpd.shutdown()
            self.httpd.server_close()
        return True
