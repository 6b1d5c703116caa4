"""Flying the probe live: ``hosedrogue fly SCENARIO`` serves a page on 127.0.0.1 that shows the
scenario's engagement in 3D as it runs in real time, while the person at the keyboard or gamepad
commands the probe tip's velocity (docs/fly.md).

* :mod:`.frame` - the state streamed to the page, the HUD's straight-on miss;
* :mod:`.session` - :class:`LiveFlight`: the scenario's engagement stepper driven with the person
  as its receiver controller (:class:`LivePilot`), on a wall-clock schedule (:mod:`.clock`);
* :mod:`.server` - :class:`FlyServer`: the HTTP server (the page, a Server-Sent Events stream of
  the state, the person's commands), its port, and stopping on Ctrl-C or a closed page;
* :mod:`.record` and :mod:`.files` - each flight's folder, like a ``simulate`` run's, with the
  commands and ``flight.toml`` that runs it again (the replaying controller :func:`replay`).

Quick start (Python)::

    from hosedrogue import fly, load_scenario

    server = fly.FlyServer(fly.LiveFlight(load_scenario("approach-moderate"), "out/fly"))
    server.start()
    print(server.url)          # open it in a browser; Enter starts the flight
    server.wait()              # until the page is closed (or server.stop("..."))
"""

from .clock import Pace, RealTimeClock
from .files import FLIGHT_FILE, read_commands, replay_scenario, write_flight
from .record import REPLAY_ENTRY, CommandRecord, Replay, replay, scenario_toml
from .server import FlyServer, bind_server
from .frame import frame_document, straight_on_miss
from .session import DEFAULT_SAMPLE_TIME_S, LiveFlight, LivePilot, flight_scenario

__all__ = ["LiveFlight", "LivePilot", "flight_scenario", "FlyServer", "bind_server", "CommandRecord", "Replay",
           "replay", "REPLAY_ENTRY", "scenario_toml", "write_flight", "read_commands", "replay_scenario",
           "FLIGHT_FILE", "Pace", "RealTimeClock", "DEFAULT_SAMPLE_TIME_S", "straight_on_miss", "frame_document"]
