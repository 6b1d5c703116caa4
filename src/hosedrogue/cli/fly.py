"""``hosedrogue fly``: fly a scenario's probe live in the browser, each flight recorded like a run."""

from __future__ import annotations

import os
import signal
import sys
from pathlib import Path

from ..errors import ParameterError
from ..jsonio import dumps
from .options import EXIT_INCOMPLETE, bounded_int, finite_float, prepare_out

NAME = "fly"


#: Signals that end a session: Ctrl-C, a service manager's stop, a closed terminal. SIGINT is
#: handled here too, not left to Python: a process started in the background by a shell without
#: job control inherits SIGINT ignored, and Python then never raises KeyboardInterrupt.
_TERMINATING = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


def _terminated(signum, frame):
    """A terminating signal: stop, saying which signal it was ("Ctrl-C" for SIGINT)."""
    raise KeyboardInterrupt("Ctrl-C" if signum == signal.SIGINT else signal.Signals(signum).name)


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(
        NAME, help="fly the probe live in the browser (a local web server; each flight recorded like a run)",
        description=(
            "Serve a page on this machine (http://127.0.0.1 and a free port, printed) that runs SCENARIO's "
            "engagement in real time and shows it in 3D: you fly the receiver's probe with the keyboard (arrows or "
            "WASD sideways and up/down, E/Q the closure speed, Enter start, P pause, Esc end) or a gamepad, with a "
            "head-up display of the range, closure speed and miss distance. Each flight is written to "
            "OUT/flight-NNN like a 'hosedrogue simulate' run (timeseries.csv, run.json with the commands, "
            "hose.npz, engagement.png), with view.html (its replay in the viewer) and flight.toml (the scenario "
            "that runs it again: 'hosedrogue simulate OUT/flight-001/flight.toml'). The server stops on Ctrl-C "
            "or when the page has been closed for --idle-timeout seconds, writing the flight in progress first (SIGTERM and SIGHUP too)."))
    s.add_argument("scenario", metavar="SCENARIO", help="an engagement scenario with a [probe] (name or TOML file), "
                                                        "e.g. approach-moderate")
    s.add_argument("--duration", metavar="S", type=finite_float("--duration", 1e-9, 86400, "s"),
                   help="simulated time of a flight [s] (overrides the file)")
    s.add_argument("--seed", metavar="N", type=bounded_int("--seed", 0, 2**63 - 1),
                   help="turbulence seed [-] (overrides the file; every flight of the session has it)")
    s.add_argument("--out", metavar="DIR", default="out/fly",
                   help="folder of the flights (default out/fly): DIR/flight-001, flight-002, ... (next free numbers)")
    s.add_argument("--host", metavar="ADDR", default="127.0.0.1",
                   help="address to listen on (default 127.0.0.1: this machine only). Another address exposes the "
                        "simulator to whoever reaches it (it warns)")
    s.add_argument("--port", metavar="N", type=bounded_int("--port", 0, 65535),
                   help="port to listen on (default: a free one, printed with the URL; 0 the same). A port given "
                        "that is in use is refused with one line naming a free one (exit status 2)")
    s.add_argument("--sample-time", metavar="S", type=finite_float("--sample-time", 1e-6, 10, "s"),
                   help="interval of your commands [s] (default: the scenario's [receiver] sample_time_s, else "
                        "0.02), a whole multiple of the scenario's numerics.step_s")
    s.add_argument("--speed", metavar="X", type=finite_float("--speed", 0.05, 4.0, "-"), default=1.0,
                   help="simulated seconds per wall second (default 1: real time; 0.5 half speed, to learn); "
                        "the flight is the same run at any speed, recorded in run.json")
    s.add_argument("--idle-timeout", metavar="S", type=finite_float("--idle-timeout", 0.1, 86400, "s"), default=5.0,
                   help="stop this long after the page was closed [s] (default 5; a reload comes back within it)")
    s.add_argument("--open", action="store_true", help="open the page in this machine's default browser")
    s.add_argument("--json", action="store_true",
                   help="when the server stops, print the flights written as JSON (folders, outcomes, real time)")
    s.set_defaults(func=run)


def run(args) -> int:
    """Check the input (one line and exit 2 if bad), bind, prepare the flight, serve until
    Ctrl-C or the page is closed.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`): 0 once the server has stopped and written its
        flights; 3 if a flight could not be written (one line on stderr, what was written kept).
    """
    from ..fly import FlyServer, LiveFlight, bind_server, flight_scenario
    from ..fly.server import is_loopback
    from ..scenarios import load_scenario

    def log(line: str) -> None:
        print(line, flush=True)

    scenario = load_scenario(args.scenario).with_overrides(duration_s=args.duration, seed=args.seed)
    flight_scenario(scenario, args.sample_time)  # a scenario without a probe: one line before anything
    out = Path(args.out)
    prepare_out(out)
    parent = next((p for p in (out, *out.parents) if p.exists()), Path("."))
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ParameterError(f"--out = {str(out)!r}: {str(parent)!r} is not writable, so no flight could be saved")
    bound = bind_server(args.host, args.port or 0, strict=bool(args.port))  # a port given: that one or none
    if not is_loopback(args.host):
        print(f"hosedrogue: warning: --host {args.host} exposes the simulator to every machine that reaches this "
              f"one: anyone there can fly it and have flights written to {out}", file=sys.stderr, flush=True)
    log(f"preparing {scenario.name} (balance position, compiled kernels) ...")
    flight = LiveFlight(scenario, out, sample_time_s=args.sample_time, speed=args.speed, log=log)
    server = FlyServer(flight, host=args.host, idle_timeout_s=args.idle_timeout, log=log, bound=bound).start()
    log(f"hosedrogue fly: {scenario.name} on {server.url} (open it in a browser; Enter starts a flight; "
        f"Ctrl-C stops; flights go to {out})")
    if args.open:
        import webbrowser

        webbrowser.open(server.url)
    previous = {sig: signal.signal(sig, _terminated) for sig in _TERMINATING}
    try:
        server.wait()
    except KeyboardInterrupt as exc:
        why = str(exc) or "Ctrl-C"
        log(f"{why}: ending the flight in progress and writing its files")
        server.stop(why)
        server.wait()
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
    flights = flight.written()
    if flight.error is not None:
        print(f"hosedrogue: {flight.error}", file=sys.stderr, flush=True)
        return EXIT_INCOMPLETE
    if args.json:
        print(dumps({"url": server.url, "stopped": flight.closed_reason, "flights": flights}, indent=2))
    else:
        log(f"stopped ({flight.closed_reason}); {len(flights)} flight{'s' if len(flights) != 1 else ''} written")
    return 0
