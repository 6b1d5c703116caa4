"""``hosedrogue fly`` without a browser: a flight flown through :class:`LiveFlight` in real time
is saved like a ``simulate`` run and runs again from its ``flight.toml`` to the same metres; the
schedule counts lateness and pauses; the server refuses bad input with one line, stops on Ctrl-C
and when its page goes, and answers only as itself. The page in a real browser:
``tests/fly/test_fly_browser.py``.

The flights here are short (0.6 to 1 s of simulated time, flown in real time) at the shipped
``approach-moderate`` (the converged preset at its 20 links).
"""

import http.client
import json
import math
import os
import signal
import socket
import subprocess
import sys
import threading
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest

import hosedrogue as hd
from hosedrogue import fly
from hosedrogue.cli import main
from hosedrogue.errors import ParameterError

#: The replay must give the flight's metres: the issue's bound. Both are the same arithmetic on
#: the same commands, so anything above rounding (1e-12 m at 20 m) means a command was recorded
#: at the wrong sample or the live display changed the state.
REPLAY_TOL_M = 1e-9


def fly_scripted(tmp_path, duration_s, script, **kw):
    """Fly ``approach-moderate`` for ``duration_s`` [s] in real time, ``script(flight)`` acting as
    the person (in this thread) once the flight has started; return the flight and its result."""
    sc = hd.load_scenario("approach-moderate").with_overrides(duration_s=duration_s)
    flight = fly.LiveFlight(sc, tmp_path / "flights", log=lambda line: None, **kw)
    sim = threading.Thread(target=flight.run_flights, daemon=True)
    sim.start()
    assert flight.start() or _until(lambda: flight.start())
    script(flight)
    assert _until(lambda: flight.state == "ended", 30.0), flight.state
    flight.close("the test's end")
    sim.join(10.0)
    assert not sim.is_alive()
    return flight, flight.results[1]


def _until(test, timeout_s=10.0):
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        if test():
            return True
        time.sleep(0.01)
    return False


def _compare(a, b):
    """Largest difference of the two runs' positions [m]: drogue, probe and every joint."""
    assert a.t_s.shape == b.t_s.shape and np.array_equal(a.t_s, b.t_s)
    ca, ja = a.hose_shapes()
    cb, jb = b.hose_shapes()
    assert np.array_equal(ca, cb)
    return max(np.abs(a.drogue_position_m - b.drogue_position_m).max(),
               np.abs(a.probe_position_m - b.probe_position_m).max(), np.abs(ja - jb).max())


def test_a_flight_runs_again_from_its_record_to_the_metre(tmp_path):
    """A flight whose person changes the command five times and pauses once, ended by the person
    before its end: its ``flight.toml`` (the receiver replaying the recorded commands), run by
    ``hosedrogue simulate``, gives the flight's drogue, probe and hose positions within 1e-9 m at
    every output time, and the record holds the commands given, in order, from sample 0."""
    given = [(1.0, 0.6, 0.0), (1.0, 0.6, -0.4), (1.5, 0.0, -0.4), (0.5, -0.8, 0.3), (1.0, 0.0, 0.0)]

    def person(flight):
        for v in given[:3]:
            time.sleep(0.12)
            flight.set_command(v)
        assert flight.pause()
        time.sleep(0.3)  # paused: the simulation waits, the pause is not counted as late
        assert flight.resume()
        for v in given[3:]:
            time.sleep(0.12)
            flight.set_command(v)
        time.sleep(0.1)
        assert flight.end()

    flight, result = fly_scripted(tmp_path, 3.0, person)
    folder = flight.folders[1]
    doc = json.loads((folder / "run.json").read_text())
    # paused for 0.3 s of the person's time: counted from the simulation's next sample (a period
    # later, more on a loaded machine), so at least a third of it
    assert doc["flight"]["ended"] == "the pilot ended it" and doc["flight"]["real_time"]["paused_s"] > 0.1
    commands = fly.read_commands(doc)
    assert commands[0][0] == 0 and [tuple(c[1:]) for c in commands[1:]] == given
    t_end = float(result.t_s[-1])
    assert 0.5 < t_end < 3.0 and not result.completed  # ended by the person, so incomplete

    again = hd.run(fly.replay_scenario(folder))
    assert again.completed and again.meta["receiver"]["entry"] == fly.REPLAY_ENTRY
    assert _compare(result, again) <= REPLAY_TOL_M
    # the probe went where it was told: right once v_y > 0 (the receiver's lag, 0.1 s, and its
    # 2 m/s^2 take it 5 mm in the first 0.07 s), nowhere vertically before v_z changed
    p = result.probe_position_m
    i_right, i_up = (np.searchsorted(result.t_s, c[0] * flight.period - 1e-9) for c in commands[1:3])
    assert p[i_up, 1] - p[i_right, 1] > 0.003 and np.all(p[:i_up + 1, 2] == p[0, 2])
    assert np.all(p[: i_right + 1, 1] == p[0, 1]) and p[i_up + 10, 2] < p[i_up, 2]

    out = tmp_path / "replayed"
    assert main(["simulate", str(folder / fly.FLIGHT_FILE), "--out", str(out)]) == 0
    flown = np.genfromtxt(folder / "timeseries.csv", delimiter=",", names=True)
    replayed = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    for name in ("drogue_x_m", "drogue_y_m", "drogue_z_m", "probe_x_m", "probe_y_m", "probe_z_m"):
        assert np.abs(flown[name] - replayed[name]).max() <= REPLAY_TOL_M, name


def test_a_flight_to_its_end_is_recorded_like_a_simulate_run(tmp_path):
    """Flown to its end: the folder holds what ``simulate`` writes (time series, run.json with the
    scenario and the outcome, hose.npz, the figure), the replay page and flight.toml; the record
    counts every receiver sample of the run, and the flight kept to real time on average."""
    flight, result = fly_scripted(tmp_path, 0.6, lambda f: f.set_command((1.2, 0.0, 0.3)))
    folder = flight.folders[1]
    assert {p.name for p in folder.iterdir()} >= {"timeseries.csv", "run.json", "hose.npz", "engagement.png",
                                                   "view.html", "flight.toml"}
    doc = json.loads((folder / "run.json").read_text())
    assert result.completed and doc["completed"] and doc["flight"]["ended"] == "the run's end"
    assert doc["scenario"] == "approach-moderate-flight-001" and doc["engagement"]["result"] == "no contact"
    samples = round(0.6 / flight.period)
    assert doc["flight"]["samples"] == samples  # samples 0 .. N-1 each gave a command
    pace = doc["flight"]["real_time"]
    # simulated seconds per wall second: 1 on schedule; the first sample (compiling the output
    # kernel) may come one period late and slip the schedule by at most a tenth of a second
    assert pace["real_time_ratio"] == pytest.approx(1.0, abs=0.25) and pace["capacity"] > 1.0
    assert _compare(result, hd.run(fly.replay_scenario(folder))) <= REPLAY_TOL_M


def test_the_schedule_counts_lateness_and_not_pauses():
    """With a wall clock the test moves: samples on time are not late; one 0.05 s late (2.5
    periods) is counted and the schedule slips by it (the next on time again); a pause of 10 s
    is not counted as late nor as flying time."""
    now = [100.0]
    clock = fly.RealTimeClock(0.02, now=lambda: now[0])
    clock.start(0.0)
    for k in range(1, 6):
        now[0] += 0.02
        assert clock.reached(0.02 * k) == pytest.approx(0.0, abs=1e-12)
    now[0] += 0.07
    assert clock.reached(0.12) == pytest.approx(0.05)
    now[0] += 0.02
    assert clock.reached(0.14) == pytest.approx(0.0, abs=1e-12)
    clock.pause()
    now[0] += 10.0
    clock.resume(0.14)
    now[0] += 0.02
    clock.reached(0.16)
    pace = clock.pace
    assert pace.late_samples == 1 and pace.lost_s == pytest.approx(0.05) and pace.late_at_s == [0.12]
    assert pace.paused_s == pytest.approx(10.0) and pace.wall_s == pytest.approx(0.21)
    assert pace.ratio == pytest.approx(0.16 / 0.21)


def test_the_record_is_a_step_function_replayed_to_the_bit():
    """The record keeps the changes only; the replaying controller gives the command of every
    sample as it was held; the scenario file writes floats that read back to the same bits; a bad
    record is one line naming the entry."""
    rec = fly.CommandRecord((1.0, 0.0, 0.0))
    held = [(1.0, 0.0, 0.0)] * 3 + [(1.0, 0.1 + 0.2, -1 / 3)] * 4 + [(2.0, 1e-300, -0.0)] * 2
    for k, v in enumerate(held):
        rec.add(k, v)
    assert [c[0] for c in rec.changes] == [0, 3, 7]
    ctl = fly.replay(rec.changes)
    ctl.reset(None)
    out = [ctl(0.02 * k, None) for k in range(len(held) + 2)]
    assert out == held + [held[-1]] * 2
    text = fly.scenario_toml({"receiver": {"entry": fly.REPLAY_ENTRY, "options": {"commands": rec.changes}}})
    back = tomllib.loads(text)["receiver"]["options"]["commands"]
    assert back == rec.changes and math.copysign(1.0, back[2][3]) == -1.0
    for bad in ([], [[1, 0.0, 0.0, 0.0]], [[0, 1.0, 0.0]], [[0, 1.0, 0.0, 0.0], [0, 1.0, 0.0, 0.0]],
                [[0, 1.0, float("nan"), 0.0]], [[0.0, 1.0, 0.0, 0.0]]):
        with pytest.raises(ParameterError) as info:
            fly.replay(bad)
        assert "commands" in str(info.value) and "\n" not in str(info.value)


# --- the command line ------------------------------------------------------------------------------
def _one_line_error(capsys, argv, *words):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("hosedrogue: error:"), err
    for w in words:
        assert w in err, err
    return err


def test_bad_input_is_one_line_and_exit_2_with_nothing_written(capsys, tmp_path):
    """An unknown scenario, a fixed-length one (no probe), a command interval that is not a whole
    number of integration steps, a port given that is in use (it names a free one to use, which
    is free): one line, exit status 2, no folder written."""
    out = tmp_path / "flights"
    _one_line_error(capsys, ["fly", "no-such-scenario", "--out", str(out)], "no-such-scenario")
    _one_line_error(capsys, ["fly", "swing-release", "--out", str(out)], "no probe")
    _one_line_error(capsys, ["fly", "approach-moderate", "--sample-time", "0.013", "--out", str(out)],
                    "receiver.sample_time_s = 0.013", "numerics.step_s")
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        err = _one_line_error(capsys, ["fly", "approach-moderate", "--port", str(port), "--out", str(out)],
                              f"--port = {port}", "in use")
        free = int(err.split("(--port ")[1].split(")")[0])
        with socket.socket() as s:
            s.bind(("127.0.0.1", free))  # the port it names is free
        server, note = fly.bind_server("127.0.0.1", port)  # the Python API: another port, saying so
        assert server.server_address[1] != port and str(port) in note
        server.server_close()
    assert not out.exists()


#: The command line as its console script runs it.
ENTRY = "import sys; from hosedrogue.cli import main; sys.exit(main())"


def _start_fly(tmp_path, *args):
    """``hosedrogue fly approach-moderate`` in a process of its own; returns it and its URL."""
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen([sys.executable, "-c", ENTRY, "fly", "approach-moderate", "--out",
                             str(tmp_path / "flights"), *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env)
    lines = []
    for line in proc.stdout:
        lines.append(line)
        if " on http://" in line:
            url = line.split(" on ", 1)[1].split()[0]
            return proc, url, lines
    proc.wait(5)
    raise AssertionError("no URL printed: " + "".join(lines) + proc.stderr.read())


def _request(url, method, path, body=None, headers=None):
    host, port = url.removeprefix("http://").rstrip("/").rsplit(":", 1)
    conn = http.client.HTTPConnection(host, int(port), timeout=5)
    data = None if body is None else json.dumps(body)
    conn.request(method, path, body=data, headers={"Content-Type": "application/json", **(headers or {})})
    resp = conn.getresponse()
    return resp.status, resp.read(), conn


def _finish(proc, timeout_s=20.0):
    out, err = proc.communicate(timeout=timeout_s)
    assert "Traceback" not in err, err
    return out, err


@pytest.mark.subprocess
@pytest.mark.parametrize("sig, why", [(signal.SIGINT, "Ctrl-C"), (signal.SIGTERM, "SIGTERM")])
def test_ctrl_c_stops_the_server_and_writes_the_flight(tmp_path, capsys, sig, why):
    """Ctrl-C (or SIGTERM) while flying: the flight in progress is written (ended by it, the time
    flown), the process ends with status 0 and no traceback, and --json lists the flight. While
    it runs, a second ``fly`` on its port is refused, naming another; the server answers only as
    itself (a page of another host name pointed at 127.0.0.1 gets 403) and takes a command only
    from its own page's origin."""
    proc, url, _ = _start_fly(tmp_path, "--json")
    try:
        port = int(url.rstrip("/").rsplit(":", 1)[1])
        _one_line_error(capsys, ["fly", "approach-moderate", "--port", str(port), "--out", str(tmp_path / "b")],
                        f"--port = {port}", "in use", "is free")
        status, page, _ = _request(url, "GET", "/")
        assert status == 200 and b"hosedrogue fly" in page
        assert _request(url, "GET", "/", headers={"Host": f"evil.example:{port}"})[0] == 403
        assert _request(url, "POST", "/control", {"action": "start"}, {"Origin": "http://evil.example"})[0] == 403
        assert _request(url, "GET", "/etc/passwd")[0] == 404
        status, body, _ = _request(url, "POST", "/control", {"action": "start"})
        assert status == 200 and json.loads(body)["ok"]
        assert _request(url, "POST", "/input", {"v": [1.0, 0.5, 0.0], "source": "keyboard"})[0] == 200
        time.sleep(0.6)
        proc.send_signal(sig)
        out, _ = _finish(proc)
    finally:
        proc.kill()
    assert proc.returncode == 0, out
    doc = json.loads((tmp_path / "flights" / "flight-001" / "run.json").read_text())
    assert doc["flight"]["ended"] == why and doc["flight"]["samples"] > 10
    listed = json.loads(out[out.index("\n{") + 1:])
    assert listed["stopped"] == why and [f["folder"] for f in listed["flights"]] == [
        str(tmp_path / "flights" / "flight-001")]


@pytest.mark.subprocess
def test_a_closed_page_stops_the_server(tmp_path):
    """A page (here its event stream) connects, starts a flight and goes away: the flight pauses
    at once, and the server stops after --idle-timeout, writing it (ended: the page was closed)."""
    proc, url, _ = _start_fly(tmp_path, "--idle-timeout", "0.3")
    try:
        host, port = url.removeprefix("http://").rstrip("/").rsplit(":", 1)
        stream = socket.create_connection((host, int(port)), timeout=5)
        stream.sendall(f"GET /events HTTP/1.1\r\nHost: {host}:{port}\r\n\r\n".encode())
        assert stream.recv(4096).startswith(b"HTTP/1.0 200")
        assert _request(url, "POST", "/control", {"action": "start"})[0] == 200
        time.sleep(0.5)
        stream.close()
        out, _ = _finish(proc)
    finally:
        proc.kill()
    assert proc.returncode == 0, out
    doc = json.loads((tmp_path / "flights" / "flight-001" / "run.json").read_text())
    assert doc["flight"]["ended"] == "the page was closed" and doc["flight"]["samples"] > 10


def test_slow_motion_and_flat_out_schedules():
    """At half speed a sample 0.02 s of simulated time on is due 0.04 s of wall time on (0.03 s
    in is early, not late); flat out nothing waits and nothing is late."""
    now = [0.0]
    slow = fly.RealTimeClock(0.02, now=lambda: now[0], speed=0.5)
    slow.start(0.0)
    now[0] = 0.03
    assert slow.wait_s(0.02) == pytest.approx(0.01)
    now[0] = 0.04
    assert slow.reached(0.02) == pytest.approx(0.0, abs=1e-12) and slow.pace.ratio == pytest.approx(0.5)
    fast = fly.RealTimeClock(0.02, now=lambda: now[0], speed=math.inf)
    fast.start(0.0)
    now[0] = 5.0
    assert fast.wait_s(100.0) < 0 and fast.reached(100.0) == 0.0 and fast.pace.late_samples == 0


def test_the_huds_miss_is_where_a_straight_path_meets_the_coupler_plane():
    """A drogue on a hose hanging 15 degrees (its last link aft and down): a tip 3 m aft of it
    at its height and side meets the plane at the drogue (miss 0, where the distance from the
    axis is 3 sin 15 = 0.78 m); 0.2 m to its right, 0.2 m; level with a tilted plane, the
    crossing moves along x by (n . offset) / n_x, found by a second route: the crossing point on
    the plane, its distance from the drogue."""
    a = math.radians(15.0)
    drogue = np.array([-10.0, 0.0, 3.0])
    joints = np.array([drogue - 1.0 * np.array([-math.cos(a), 0.0, -math.sin(a)]), drogue])
    assert fly.straight_on_miss(joints, drogue + [-3.0, 0.0, 0.0]) == pytest.approx(0.0, abs=1e-12)
    assert fly.straight_on_miss(joints, drogue + [-3.0, 0.2, 0.0]) == pytest.approx(0.2, abs=1e-12)
    tip = drogue + [-3.0, 0.1, -0.3]
    n = (joints[1] - joints[0]) / np.linalg.norm(joints[1] - joints[0])
    s = np.linspace(0.0, 6.0, 600001)  # the path, sampled: the crossing within 1e-5 m
    path = tip + s[:, None] * [1.0, 0.0, 0.0]
    cross = path[np.argmin(np.abs((path - drogue) @ n))]
    assert fly.straight_on_miss(joints, tip) == pytest.approx(np.linalg.norm(cross - drogue), abs=2e-5)


def test_the_next_flight_starts_from_the_same_state(tmp_path):
    """Two flights of one session, each flown with the scenario's own closing command: the second
    (after "again") is the first again, to the bit - the stepper's reset restores the balance
    position and the same gusts - and each has its folder, numbered on."""
    sc = hd.load_scenario("approach-moderate").with_overrides(duration_s=0.4)
    flight = fly.LiveFlight(sc, tmp_path / "flights", log=lambda line: None)
    sim = threading.Thread(target=flight.run_flights, daemon=True)
    sim.start()
    for n in (1, 2):
        assert _until(lambda: flight.start())
        assert _until(lambda: flight.state == "ended" and n in flight.results, 30.0)
        if n == 1:
            assert flight.again()
    flight.close("the test's end")
    sim.join(10.0)
    a, b = flight.results[1], flight.results[2]
    assert [p.name for p in sorted((tmp_path / "flights").iterdir())] == ["flight-001", "flight-002"]
    assert np.array_equal(a.probe_position_m, b.probe_position_m) and np.array_equal(a.drogue_position_m,
                                                                                     b.drogue_position_m)
    assert np.array_equal(a.hose_shapes()[1], b.hose_shapes()[1])
