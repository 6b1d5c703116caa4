"""Real-time margin of ``hosedrogue fly``, printed as figures (never asserted).

A live flight must keep to real time: every receiver sample (20 ms) the simulation integrates
the engagement to the next sample, builds the page's frame (the joints, the HUD's figures, as
JSON) and takes the person's command. The margin is how many simulated seconds it computes per
wall second of that work (``run.json`` ``flight.real_time.capacity``): above 1 it keeps to real
time, and what is left over is the page's (the browser draws on the same machine).

* the flight's own loop flat out (``speed = inf``: no waiting), the person's commands scripted,
  at the shipped ``approach-moderate`` (the converged preset at its 20 links, RK4 at 5 ms: the
  link count docs/convergence.md settles on) and with more links, the step scaled with the link
  length as the shipped scenarios do (40 links at 2.5 ms ... 160 at 0.625 ms, engage-response's);
* the same run by ``simulate_engagement`` (no person, no frames): what the live layer costs;
* a real-time flight at 20 links (10 s): its real-time ratio and late samples;
* the same with its page open in headless Chromium (software WebGL) on the same machine: the
  page's frame rate and the flight's pace.

Run:  .venv/bin/python benchmarks/fly.py   (one core: NUMBA_NUM_THREADS=1 is set here)
Target: margin >= 2 at the converged link count (room for the page and a loaded machine).
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import dataclasses  # noqa: E402
import math  # noqa: E402
import tempfile  # noqa: E402
import threading  # noqa: E402
import time  # noqa: E402

import hosedrogue as hd  # noqa: E402
from hosedrogue import fly  # noqa: E402

#: The person: (wall time after the start [s], command (v_x, v_y, v_z) [m/s]).
SCRIPT = ((0.3, (1.0, 0.5, 0.0)), (0.8, (1.0, 0.0, -0.3)), (1.5, (1.2, -0.4, 0.2)), (2.5, (1.0, 0.0, 0.0)))


def flight(scenario, speed: float, out: str):
    """Fly ``scenario`` once at ``speed``, the person following :data:`SCRIPT`; its pace."""
    live = fly.LiveFlight(scenario, out, speed=speed, log=lambda line: None)
    sim = threading.Thread(target=live.run_flights, daemon=True)
    sim.start()
    while not live.start():
        time.sleep(0.01)
    t0 = time.monotonic()
    for at, v in SCRIPT:
        while time.monotonic() - t0 < at and live.state == "flying":
            time.sleep(0.005)
        live.set_command(v)
    while live.state != "ended":
        time.sleep(0.01)
    live.close("the benchmark's end")
    sim.join()
    return live.clock.pace


def case(name: str, links: int | None = None):
    """The shipped scenario ``name`` for 4.5 s, with ``links`` links and its step scaled with the
    link length [s]."""
    sc = hd.load_scenario(name).with_overrides(duration_s=4.5)
    if links is None:
        return sc
    step = sc.params.numerics.step_s * sc.params.hose.links / links
    return dataclasses.replace(sc, params=sc.params.replace(hose={"links": links}, numerics={"step_s": step}))


#: (label, scenario): the converged link count first; engage-response is the 160-link whip model
#: (no turbulence, no bow wave: approach-moderate's turbulence and bow wave at 0.1 m links stop
#: at 8 ms, a link's yaw at the angles' singular limit)
CASES = (("approach-moderate", ("approach-moderate", None)), ("approach-moderate", ("approach-moderate", 40)),
         ("approach-moderate", ("approach-moderate", 80)), ("engage-response", ("engage-response", None)))


def main():
    out = tempfile.mkdtemp(prefix="hosedrogue-fly-bench-")
    print("hosedrogue fly: real-time margin (simulated s per wall s of the flight's computation), "
          "4.5 s flights")
    print("target: >= 2 at the converged link count (20)")
    for label, args in CASES:
        sc = case(*args)
        for _ in range(2):  # compile, warm the caches
            flight(sc.with_overrides(duration_s=0.3), math.inf, out)
            hd.run(sc.with_overrides(duration_s=0.3))
        pace = flight(sc, math.inf, out)
        t0 = time.perf_counter()
        plain = hd.run(sc)
        plain_rate = sc.duration_s / (time.perf_counter() - t0)
        assert plain.completed, plain.message
        print(f"  {label}, {sc.params.hose.links:3d} links, h = {sc.params.numerics.step_s * 1e3:.3g} ms: "
              f"margin {pace.capacity:6.1f} (flat out {pace.ratio:5.1f} x real time with the frames' JSON; "
              f"simulate with its prescribed probe {plain_rate:5.1f} x)")
    sc = case("approach-moderate").with_overrides(duration_s=10.0)
    pace = flight(sc, 1.0, out)
    print(f"  real time, 20 links, 10 s: ratio {pace.ratio:.4f}, margin {pace.capacity:.1f}, "
          f"late samples {pace.late_samples} (lost {pace.lost_s:.3f} s, worst {pace.max_late_s * 1e3:.1f} ms late)")
    with_browser()


def with_browser(seconds: float = 6.0):
    """A real-time flight at 20 links with its page open in headless Chromium on the same machine
    (software WebGL): the page's frames drawn per second and the flight's pace."""
    import shutil

    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        print("  with the page open: skipped (Playwright not installed)")
        return
    chromium = shutil.which("chromium")
    if chromium is None:
        print("  with the page open: skipped (no Chromium)")
        return
    sc = case("approach-moderate").with_overrides(duration_s=seconds)
    live = fly.LiveFlight(sc, tempfile.mkdtemp(prefix="hosedrogue-fly-bench-"), log=lambda line: None)
    server = fly.FlyServer(live, log=lambda line: None).start()
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1280, "height": 800})
        page.goto(server.url)
        page.wait_for_timeout(1000)
        page.keyboard.press("Enter")
        page.wait_for_timeout(1000)
        n0, t0 = page.evaluate("() => [hdLive.drawn, performance.now()]")
        page.keyboard.down("ArrowRight")
        page.wait_for_timeout(2000)
        page.keyboard.up("ArrowRight")
        n1, t1 = page.evaluate("() => [hdLive.drawn, performance.now()]")
        while live.state != "ended":
            page.wait_for_timeout(100)
        browser.close()
    pace = live.clock.pace
    server.stop("the benchmark's end")
    server.wait(30.0)
    print(f"  real time with the page open (headless Chromium, 1280 x 800), 20 links, {seconds:g} s: page "
          f"{(n1 - n0) / (t1 - t0) * 1e3:.0f} frames/s; ratio {pace.ratio:.4f}, margin {pace.capacity:.1f}, "
          f"late samples {pace.late_samples} (lost {pace.lost_s:.3f} s)")


if __name__ == "__main__":
    main()
