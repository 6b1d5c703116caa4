"""A live flight: a scenario's engagement run in real time, its probe flown by a person.

The person is the run's receiver controller (docs/controllers.md): :class:`LivePilot` is built
like any docking controller and driven by :func:`hosedrogue.simulation.drive.drive` on the
scenario's :class:`~hosedrogue.engagement.EngagementStepper` (its other controllers - a reel law,
a drogue controller - run as in ``hosedrogue simulate``). At each receiver sample it waits for
the wall clock (:class:`~hosedrogue.fly.clock.RealTimeClock`), publishes the state (the hose's
joints, the probe, the HUD's figures) for the page, and returns the person's latest command,
which it records (:class:`~hosedrogue.fly.record.CommandRecord`). :class:`LiveFlight` holds the
flights of one session and writes each like a ``simulate`` run.
"""

from __future__ import annotations

import dataclasses
import json
import math
import threading
import time
from pathlib import Path

import numpy as np

from ..controllers.sampled import SampledController
from ..engagement.simulate import sampled_controllers, sampled_stepper
from ..errors import ParameterError
from ..scenarios import Scenario
from ..scenarios.runner import engagement_arguments
from ..spec.sections import Receiver
from ..simulation.drive import drive
from ..simulation.simulate import sampled_controller
from .clock import RealTimeClock
from .frame import frame_document, plain
from .record import REPLAY_ENTRY, CommandRecord

__all__ = ["flight_scenario", "LiveFlight", "LivePilot", "DEFAULT_SAMPLE_TIME_S", "STATES"]

#: The person's command interval when the scenario has no ``[receiver]`` [s] (50 Hz).
DEFAULT_SAMPLE_TIME_S = 0.02
#: A flight's states: waiting for the start, flying, paused, ended (its files written), closed.
STATES = ("ready", "flying", "paused", "ended", "closed")
#: Largest frame rate streamed to the page [1/s] (a frame is at most one per receiver sample).
MAX_FRAME_RATE_HZ = 60.0


def flight_scenario(scenario: Scenario, sample_time_s: float | None = None) -> Scenario:
    """The scenario as a person flies it: its probe flown by velocity commands through the
    receiver's response (the scenario's ``[receiver]`` limits, or the defaults), the pilot model
    and any docking controller replaced by the person.

    Parameters
    ----------
    scenario : Scenario
        An engagement with an enabled ``[probe]``.
    sample_time_s : float, optional
        The person's command interval [s] (default: the scenario's ``[receiver]``, else
        :data:`DEFAULT_SAMPLE_TIME_S`), a whole multiple of ``numerics.step_s``.

    Returns
    -------
    Scenario
        Its ``engagement.receiver`` has no entry yet (:class:`LiveFlight` gives it the pilot).

    Raises
    ------
    ParameterError
        A fixed-length scenario, or an engagement without a probe.
    """
    e = scenario.engagement
    if e is None:
        raise ParameterError(f"scenario {scenario.name!r}: the fixed-length hose has no probe to fly; give an "
                             "engagement scenario with a [probe] section (e.g. approach-moderate)")
    if e.probe is None or not e.probe.enabled:
        raise ParameterError(f"scenario {scenario.name!r}: its engagement has no probe to fly (probe.enabled = "
                             "false or no [probe] section); give one with a [probe] section (e.g. approach-moderate)")
    receiver = e.receiver if e.receiver is not None else Receiver(sample_time_s=DEFAULT_SAMPLE_TIME_S)
    if sample_time_s is not None:
        receiver = dataclasses.replace(receiver, sample_time_s=float(sample_time_s))
    receiver = dataclasses.replace(receiver, entry="", options={})
    return dataclasses.replace(scenario, engagement=dataclasses.replace(e, pilot=None, receiver=receiver))


class LivePilot:
    """The receiver's controller of a live flight: waits for the wall clock at every sample,
    publishes the state and returns the person's latest command (see the module docstring).

    Parameters
    ----------
    flight : LiveFlight
        The session it flies in (its stepper, input, schedule and published frames).
    """

    def __init__(self, flight: "LiveFlight"):
        self.flight = flight
        self.k = 0

    def reset(self, m) -> None:
        """Start a flight at sample 0.

        Parameters
        ----------
        m : hosedrogue.controllers.sampled.Measurement
            The first measurement (unused: the person sees the state itself).
        """
        self.k = 0

    def __call__(self, t, m):
        """The command of the sample at ``t`` [s], given in real time.

        Parameters
        ----------
        t : float
            The sample's time [s].
        m : hosedrogue.controllers.sampled.Measurement
            The measurement (unused).

        Returns
        -------
        tuple of 3 float
            (v_x, v_y, v_z) [m/s].
        """
        command = self.flight._sample(self.k, t)
        self.k += 1
        return command


class LiveFlight:
    """The flights of one session of ``hosedrogue fly``: set up once, flown one after another.

    The simulation runs in one thread (:meth:`run_flights`); the server's threads call
    :meth:`set_command`, :meth:`start`, :meth:`pause`, :meth:`resume`, :meth:`end`,
    :meth:`again` and :meth:`close`, and read :meth:`wait_update` (the latest frame and status).

    Parameters
    ----------
    scenario : Scenario
        The scenario (:func:`flight_scenario` is applied).
    out_dir : str or pathlib.Path
        Folder of the flights: ``OUT/flight-001``, ``flight-002``, ... (the next free numbers).
    sample_time_s : float, optional
        The person's command interval [s] (:func:`flight_scenario`).
    frame_rate_hz : float
        Frames streamed per second at most [1/s] (one per receiver sample at most).
    speed : float
        Simulated seconds per wall second [-]: 1 real time (default), below 1 slow motion (to
        learn), ``inf`` as fast as it computes (benchmarks/fly.py).
    log : callable
        Gets one line per written flight.
    now : callable
        Wall clock [s] (tests give another).
    """

    def __init__(self, scenario: Scenario, out_dir, *, sample_time_s: float | None = None,
                 frame_rate_hz: float = 50.0, speed: float = 1.0, log=print, now=time.monotonic):
        self.scenario = flight_scenario(scenario, sample_time_s)
        self.out_dir = Path(out_dir)
        self.log, self.now = log, now
        if not speed > 0:
            raise ParameterError(f"speed = {speed!r}: must be > 0 (1 real time, 0.5 half speed)")
        self.speed = float(speed)
        self.pilot = LivePilot(self)
        e = self.scenario.engagement
        self.receiver = e.receiver
        flown = dataclasses.replace(self.scenario, engagement=dataclasses.replace(
            e, receiver=dataclasses.replace(e.receiver, entry=self._pilot_factory)))
        kw = engagement_arguments(flown)
        control, sample = kw.pop("control"), kw.pop("sample_time_s")
        surfaces = kw["drogue_actuator"]
        controllers = sampled_controllers(kw["reel"], kw["receiver"], control, sample, surfaces)
        if surfaces is not None and not isinstance(sampled_controller(control), SampledController):
            surfaces.check_force_command()  # as simulate_engagement: a built-in controller commands a force
        self.stepper, self.controllers, self.built = sampled_stepper(flown.params, flown.duration_s, controllers,
                                                                     control=control, **kw)
        self.period = self.receiver.sample_time_s
        # a few samples now, so the first of a flight does not wait for the kernels' loading
        # (0.1 s: five samples late); run_flights resets the stepper before each flight
        self.stepper.reset()
        self.stepper.step(receiver=(float(e.probe.closure_speed_m_s), 0.0, 0.0), samples=3)
        self.stepper.outputs()
        self.frame_every = max(1, math.ceil(1.0 / (min(frame_rate_hz, MAX_FRAME_RATE_HZ) * self.period) - 1e-9))
        self.initial_command = (float(e.probe.closure_speed_m_s), 0.0, 0.0)  # the stepper's command at t = 0
        self._cv = threading.Condition()
        self._seq = 0
        self._frame = self._status = None
        self.state = "ready"
        self.number = 0
        self.folders: dict[int, Path] = {}
        self.results: dict[int, object] = {}
        self._command, self._source = self.initial_command, "none"
        self._end_reason = None
        self._again = self._started = False
        self._sources = {}
        self._input_seq = -1
        self.closed_reason = None
        #: set once :meth:`run_flights` has returned (its last flight written): what the server
        #: waits for (an Event, not ``Thread.join``, which Ctrl-C can leave saying "not alive"
        #: while the thread still writes)
        self.finished = threading.Event()
        self.error = None  #: one line when the session stopped on an error (its flight's files unwritable)

    def _pilot_factory(self):
        return self.pilot

    def facts(self) -> dict:
        """What the page needs to know of the session besides the frames (JSON-ready).

        Returns
        -------
        dict
            Scenario name, description, duration [s], the receiver's sample time [s], speed [m/s]
            and acceleration [m/s^2] bounds and time constant [s], the probe's closure speed [m/s],
            capture radius [m] and closure window [m/s], hose and drogue diameters [m], links.
        """
        sc = self.scenario
        e, p, r = sc.engagement, sc.params, self.receiver
        return {"scenario": sc.name, "description": sc.description, "source": sc.source,
                "duration_s": sc.duration_s, "sample_time_s": self.period,
                "max_speed_m_s": list(r.max_speed_m_s), "max_acceleration_m_s2": list(r.max_acceleration_m_s2),
                "velocity_time_constant_s": r.velocity_time_constant_s,
                "closure_speed_m_s": e.probe.closure_speed_m_s, "capture_radius_m": e.probe.capture_radius_m,
                "closure_window_m_s": [e.probe.min_closure_speed_m_s, e.probe.max_closure_speed_m_s],
                "hose_diameter_m": p.hose.outer_diameter_m, "drogue_diameter_m": p.drogue.diameter_m,
                "links": p.hose.links, "out_dir": str(self.out_dir)}

    # --- the page's side (server threads) ----------------------------------------------------------
    def set_command(self, v, source: str = "keyboard", seq: int | None = None) -> None:
        """Hold the person's command from the next sample on.

        Parameters
        ----------
        v : sequence of 3 float
            Probe-tip velocity (v_x, v_y, v_z) [m/s] in the tanker frame (the receiver's response
            bounds it).
        source : str
            What gave it ("keyboard", "gamepad"), for the record.
        seq : int, optional
            The page's number of the command [-]: one older than the last held is ignored (two
            requests may arrive in either order).

        Raises
        ------
        ParameterError
            Not three finite numbers.
        """
        try:
            vx, vy, vz = (float(x) for x in v)
        except (TypeError, ValueError, OverflowError):
            raise ParameterError(f"command = {repr(v)[:60]}: must be three numbers (v_x, v_y, v_z) [m/s]") from None
        if not all(math.isfinite(x) for x in (vx, vy, vz)):
            raise ParameterError(f"command = {v!r}: must be finite [m/s]")
        with self._cv:
            if seq is not None:
                if not isinstance(seq, int) or seq < self._input_seq:
                    return
                self._input_seq = seq
            self._command, self._source = (vx, vy, vz), str(source)[:20]

    def _control(self, allowed: tuple, change) -> bool:
        with self._cv:
            if self.state not in allowed:
                return False
            change()
            self._publish_status()
            self._cv.notify_all()
            return True

    def start(self) -> bool:
        """Start the flight that is ready (True if it was)."""
        return self._control(("ready",), lambda: setattr(self, "state", "flying"))

    def pause(self) -> bool:
        """Pause the flight (True if it was flying)."""
        return self._control(("flying",), lambda: setattr(self, "state", "paused"))

    def resume(self) -> bool:
        """Resume a paused flight (True if it was paused)."""
        return self._control(("paused",), lambda: setattr(self, "state", "flying"))

    def end(self, reason: str = "the pilot ended it") -> bool:
        """End the flight now (its files are written); True if one was flying or paused."""
        return self._control(("flying", "paused"), lambda: setattr(self, "_end_reason", reason))

    def again(self) -> bool:
        """Get the next flight ready after one ended (True if one had)."""
        return self._control(("ended",), lambda: setattr(self, "_again", True))

    def close(self, reason: str) -> None:
        """End everything: the flight in progress is ended (and written), none other starts.

        Parameters
        ----------
        reason : str
            Why ("the page was closed", "Ctrl-C"), recorded in the flight's ``run.json``.
        """
        with self._cv:
            if self.closed_reason is None:
                self.closed_reason = reason
                if self._end_reason is None:
                    self._end_reason = reason
            self._cv.notify_all()

    def wait_update(self, seq: int, timeout_s: float):
        """Wait for a frame or status newer than ``seq``.

        Parameters
        ----------
        seq : int
            The last update seen (0 at first).
        timeout_s : float
            Longest wait [s].

        Returns
        -------
        (int, str or None, str or None)
            The latest update number, frame JSON and status JSON (None where nothing new, or after
            the timeout).
        """
        with self._cv:
            self._cv.wait_for(lambda: self._seq != seq or self.state == "closed", timeout_s)
            if self._seq == seq:
                return seq, None, None
            return self._seq, self._frame, self._status

    # --- the simulation's side ---------------------------------------------------------------------
    def run_flights(self) -> None:
        """Fly until :meth:`close`: each flight waits for :meth:`start`, runs in real time, is written,
        then waits for :meth:`again`. Runs in the simulation's thread."""
        try:
            while True:
                with self._cv:
                    if self.closed_reason is not None:
                        break
                    self.number = self._next_number()
                    self.state, self._end_reason, self._again, self._started = "ready", None, False, False
                    self._sources: dict[str, int] = {}
                    self._command, self._source = self.initial_command, "none"
                    self.record = CommandRecord(self.initial_command)
                    self.clock = RealTimeClock(self.period, self.now, self.speed)
                    self._publish_status()
                self.stepper.reset()
                self._publish_frame(self.initial_command, "none")
                result = drive(self.stepper, self.controllers, self.built)
                if not self._started:
                    break  # closed before it started: nothing flown, nothing written
                self._publish_frame(self._command, self._source)  # the run's last state and outcome
                self._write(result)
                with self._cv:
                    self.state = "ended"
                    self._publish_status()
                    self._cv.wait_for(lambda: self._again or self.closed_reason is not None)
                    if self.closed_reason is not None:
                        break
        except Exception as exc:  # a flight's files that cannot be written, a failure of this code
            self.error = f"flight {self.number} stopped: {type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
            self.log(self.error)
            with self._cv:
                self.closed_reason = self.closed_reason or "an error"
        finally:
            with self._cv:
                self.state = "closed"
                self._publish_status()
                self._cv.notify_all()
            self.finished.set()

    def _next_number(self) -> int:
        n = max(self.folders, default=0) + 1
        while (self.out_dir / f"flight-{n:03d}").exists():
            n += 1
        return n

    def _sample(self, k: int, t: float):
        """The pilot's call at sample ``k``, time ``t`` [s]: wait for the start or the wall clock,
        publish the frame, return and record the person's command."""
        clock = self.clock
        clock.arrive()
        with self._cv:
            if k == 0:
                self._cv.wait_for(lambda: self.state != "ready" or self._end_reason is not None)
                self._started = self.state != "ready"
                clock.start(t)
            while self._end_reason is None:
                if self.state == "paused":
                    clock.pause()
                    self._cv.wait_for(lambda: self.state != "paused" or self._end_reason is not None)
                    clock.resume(t)
                    continue
                wait = clock.wait_s(t)
                if wait <= 0:
                    break
                self._cv.wait(wait)
            if self._end_reason is not None:
                self.stepper.stop(f"the flight was ended ({self._end_reason})")
            command, source = self._command, self._source
        late = clock.reached(t)
        self.record.add(k, command)
        self._sources[source] = self._sources.get(source, 0) + 1
        busy = 0.0
        if k % self.frame_every == 0 or late > 0:
            start = self.now()
            self._publish_frame(command, source)
            busy = self.now() - start
        clock.returned(busy)
        return command

    def _publish_frame(self, command, source: str) -> None:
        """The state now as the page draws it (JSON), published to the waiting streams."""
        o = self.stepper.outputs()
        joints, probe = o["joints_m"], o["probe_position_m"]
        if not (np.all(np.isfinite(joints)) and np.all(np.isfinite(probe))):
            return  # a failed state: the run's end says why
        frame = frame_document({**o, "outcome": dict(self.stepper.outcome)}, command, source, self.clock.pace)
        with self._cv:
            self._frame = frame
            self._seq += 1
            self._cv.notify_all()

    def _publish_status(self) -> None:
        """The session's state as the page shows it (call with the lock held)."""
        status = {"state": self.state, "flight": self.number, "closed": self.closed_reason,
                  "flights": [self._flight_summary(n) for n in sorted(self.results)]}
        self._status = json.dumps(plain(status), separators=(",", ":"), allow_nan=False)
        self._seq += 1

    def written(self) -> list[dict]:
        """The flights written so far, as the page lists them.

        Returns
        -------
        list of dict
            Per flight: number, folder, replay page, outcome (result, miss [m], contact time [s],
            closure speed [m/s]), completed, message, how it ended, time flown [s], real time.
        """
        with self._cv:
            return [self._flight_summary(n) for n in sorted(self.results)]

    def _flight_summary(self, number: int) -> dict:
        """A written flight as the page lists it: folder, replay page, outcome, real time."""
        result = self.results[number]
        o = result.outcome
        flight = result.meta["flight"]
        return {"number": number, "folder": str(self.folders[number]), "replay": f"/flights/{number}/view.html",
                "result": o.get("result"), "miss_distance_m": o.get("miss_distance_m"),
                "contact_time_s": o.get("contact_time_s"), "closure_speed_m_s": o.get("closure_speed_m_s"),
                "completed": bool(result.completed), "message": result.message, "ended": flight["ended"],
                "flown_s": float(result.t_s[-1]), "real_time": flight["real_time"]}

    # --- the flight's files ------------------------------------------------------------------------
    def _replay_scenario(self, result) -> Scenario:
        """The scenario that runs this flight again: the receiver replaying its commands, for the
        time flown when the person (or a closed page, Ctrl-C) ended it early - so the replay ends
        where the flight did, completed - and for the whole duration otherwise (a run that failed
        fails again at the same time)."""
        e = self.scenario.engagement
        receiver = dataclasses.replace(e.receiver, entry=REPLAY_ENTRY, options={"commands": self.record.changes})
        duration = self.scenario.duration_s
        if self._end_reason is not None and result.t_s.size and result.t_s[-1] > 0:
            duration = float(result.t_s[-1])
        return dataclasses.replace(self.scenario, name=f"{self.scenario.name}-flight-{self.number:03d}",
                                   duration_s=duration, engagement=dataclasses.replace(e, receiver=receiver))

    def _write(self, result) -> None:
        from .files import write_flight

        folder = self.out_dir / f"flight-{self.number:03d}"
        ended = self._end_reason or ("the run's end" if result.completed else result.message)
        result = write_flight(result, folder, self._replay_scenario(result), self.record, self.clock.pace,
                              number=self.number, ended=ended, sources=dict(self._sources))
        with self._cv:
            self.folders[self.number] = folder
            self.results[self.number] = result
        o = result.outcome
        what = str(o.get("result", ""))
        if o.get("contact_time_s") is not None:
            what += f" at {o['contact_time_s']:.2f} s, miss {o['miss_distance_m']:.3f} m"
        self.log(f"wrote {folder} (flight {self.number}: {what}; {result.t_s[-1]:.2f} s flown; ended: {ended})")
