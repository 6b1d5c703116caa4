"""``hosedrogue fly``'s page in a real browser: headless Chromium (Debian's package) driven by
Playwright, against the server in this process.

The page must load from the server alone (any request elsewhere is refused and fails the test)
and draw the first live frame within 2 s; a scripted key sequence must move the probe the way
the keys say (right arrow: +y, right; up arrow: -z, up: S_p has z down); and closing the page
must stop the server, the flight written.

Skipped, with the reason in the summary, where Playwright for Python or Chromium is missing, as
the viewer's browser tests are (``tests/viewer/test_viewer_browser.py``); ``.ci/run`` installs Chromium.
"""

import json
import os
import shutil
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import hosedrogue as hd
from hosedrogue import fly

pytestmark = pytest.mark.browser

CHROMIUM = shutil.which("chromium") or next((p for p in ("/usr/bin/chromium",) if Path(p).exists()), None)

#: The issue's bound on the page's load: from the navigation to the first live frame drawn [ms].
LOAD_BOUND_MS = 2000.0


@pytest.fixture(scope="module")
def browser():
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        pytest.skip("browser tests skipped: Playwright for Python not installed (pip install -e '.[test]')")
    if CHROMIUM is None:
        if os.environ.get("CI") == "true":
            pytest.fail("Chromium not installed in CI: .ci/run must install it (apt-get install chromium)")
        pytest.skip("browser tests skipped: Chromium not installed: apt-get install chromium")
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        yield b
        b.close()


@pytest.fixture
def server(tmp_path):
    """A flight of approach-moderate (20 links) served on a free port, stopping 0.3 s after its
    page goes."""
    sc = hd.load_scenario("approach-moderate").with_overrides(duration_s=6.0)
    flight = fly.LiveFlight(sc, tmp_path / "flights", log=lambda line: None)
    srv = fly.FlyServer(flight, idle_timeout_s=0.3, log=lambda line: None).start()
    yield srv
    srv.stop("the test's end")
    srv.wait(20.0)


def _open(browser, url):
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    requests, errors = [], []

    def route(r):
        requests.append(r.request.url)
        (r.continue_ if r.request.url.startswith(url) or r.request.url.startswith("data:") else r.abort)()

    context.route("**/*", route)
    page = context.new_page()
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.goto(url)
    return context, page, requests, errors


def _until(page, expr: str, timeout_s: float = 10.0):
    """Poll a property of the page (Playwright's wait_for_function would eval text, which the
    page's security policy forbids)."""
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        value = page.evaluate(f"() => {expr}")
        if value:
            return value
        page.wait_for_timeout(20)
    raise AssertionError(f"timeout: {expr}")


def _probe(page):
    return np.array(page.evaluate("() => hdLive.frame.probe"))


def test_the_page_loads_within_2_s_and_the_keys_fly_the_probe(browser, server):
    """First live frame drawn within 2 s of the navigation, nothing loaded from elsewhere; then
    Enter starts the flight, the right arrow held moves the probe right (+y) and not vertically,
    the up arrow held moves it up (-z) and not sideways (the receiver's lag lets it drift on by
    at most v tau = 0.05 m after a key is let go), and the flight's record holds the keyboard's
    half-speed commands (0.5 m/s of the receiver's 1 m/s bound). The replay page (the viewer's,
    from the same server) draws the flight to its last time."""
    context, page, requests, errors = _open(browser, server.url)
    try:
        first = _until(page, "window.hdLive && hdLive.firstFrameMs")
        assert first < LOAD_BOUND_MS, first
        page.keyboard.press("Enter")
        _until(page, "hdLive.status.state === 'flying'")
        p0 = _probe(page)
        page.keyboard.down("ArrowRight")
        page.wait_for_timeout(700)
        page.keyboard.up("ArrowRight")
        page.wait_for_timeout(400)  # the lateral speed decays (tau 0.1 s, 2 m/s^2)
        p1 = _probe(page)
        page.keyboard.down("ArrowUp")
        page.wait_for_timeout(700)
        page.keyboard.up("ArrowUp")
        page.wait_for_timeout(400)
        p2 = _probe(page)
        page.keyboard.press("Escape")  # end the flight: its files are written
        _until(page, "hdLive.status.state === 'ended' && hdLive.status.flights.length === 1")
        flown_s = page.evaluate("() => hdLive.status.flights[0].flown_s")
        page.goto(server.url + "flights/1/view.html")  # the replay: the viewer's page of the flight
        _until(page, "Number(document.documentElement.dataset.hdDrawn || 0) >= 1")
        assert page.evaluate("() => hdViewer.span")[1] == pytest.approx(flown_s, abs=1e-9)
        assert not errors, errors
        assert all(r.startswith(server.url) for r in requests), requests
    finally:
        context.close()
    print(f"first frame {first:.0f} ms; probe moved {p1 - p0} then {p2 - p1} m")
    # 0.7 s at 0.5 m/s less the receiver's lag: about 0.3 m; at least 0.1 m on a loaded machine
    assert p1[1] - p0[1] > 0.1 and abs(p1[2] - p0[2]) < 1e-9, (p0, p1)
    assert p2[2] - p1[2] < -0.1 and abs(p2[1] - p1[1]) < 0.05 + 1e-9, (p1, p2)
    doc = json.loads((server.flight.folders[1] / "run.json").read_text())
    speeds = {tuple(c[2:]) for c in fly.read_commands(doc)}
    assert (0.5, 0.0) in speeds and (0.0, -0.5) in speeds and doc["flight"]["inputs"].get("keyboard", 0) > 0


def test_closing_the_page_stops_the_server(browser, server):
    """The page closed mid-flight: the flight pauses, the server stops after its idle timeout
    and the flight is written (ended: the page was closed)."""
    context, page, _, _ = _open(browser, server.url)
    _until(page, "window.hdLive && hdLive.firstFrameMs")
    page.keyboard.press("Enter")
    _until(page, "hdLive.status.state === 'flying'")
    page.wait_for_timeout(300)
    closed = time.monotonic()
    context.close()
    assert server.wait(15.0)
    took = time.monotonic() - closed
    doc = json.loads((server.flight.folders[1] / "run.json").read_text())
    assert doc["flight"]["ended"] == "the page was closed" and server.flight.closed_reason == "the page was closed"
    assert took >= 0.3  # not before the idle timeout: a reload comes back within it


#: A gamepad for the page (the Gamepad API, faked before the page's script runs): its left
#: stick's x axis set by the test through window.__pad_x.
FAKE_PAD = """(() => {
  window.__pad_x = 0;
  const buttons = Array.from({ length: 17 }, () => ({ pressed: false, value: 0 }));
  navigator.getGamepads = () => [{ connected: true, id: "test pad", axes: [window.__pad_x, 0, 0, 0], buttons }];
})();"""


def test_a_gamepad_stick_flies_the_probe(browser, server):
    """The left stick pushed 80 % right (past the 0.12 dead zone: 0.77 of the 1 m/s bound) moves
    the probe right and not vertically, and the flight records the gamepad as its input."""
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    context.add_init_script(FAKE_PAD)
    page = context.new_page()
    try:
        page.goto(server.url)
        _until(page, "window.hdLive && hdLive.firstFrameMs")
        page.keyboard.press("Enter")
        _until(page, "hdLive.status.state === 'flying'")
        p0 = _probe(page)
        page.evaluate("() => { window.__pad_x = 0.8; }")
        page.wait_for_timeout(600)
        page.evaluate("() => { window.__pad_x = 0; }")
        page.wait_for_timeout(300)
        p1 = _probe(page)
        page.keyboard.press("Escape")
        _until(page, "hdLive.status.state === 'ended' && hdLive.status.flights.length === 1")
    finally:
        context.close()
    assert p1[1] - p0[1] > 0.1 and abs(p1[2] - p0[2]) < 1e-9, (p0, p1)
    doc = json.loads((server.flight.folders[1] / "run.json").read_text())
    vy = {round(c[2], 6) for c in fly.read_commands(doc)}
    assert round((0.8 - 0.12) / (1 - 0.12), 6) in vy and doc["flight"]["inputs"].get("gamepad", 0) > 0
