"""The viewer's page in a real browser: headless Chromium (Debian's package) driven by Playwright.

The page must load with no request leaving the file (every request is recorded, and any that is
not the page's own file is refused and fails the test), draw the hose on its canvas, show a
different picture at a different time, and keep the charts' cursor at the 3D view's time.

Skipped, with the reason in the summary (pytest -rs, the project's default), where Playwright for
Python or Chromium is missing; ``.ci/run`` installs Chromium so CI always runs them (with
``CI=true`` a missing Chromium fails them instead).
"""

import io
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

import hosedrogue as hd
from hosedrogue import viewer
from viewer_cases import ENGAGE

pytestmark = pytest.mark.browser

#: Debian's Chromium (apt-get install chromium); never a browser downloaded by Playwright.
CHROMIUM = shutil.which("chromium") or next((p for p in ("/usr/bin/chromium",) if Path(p).exists()), None)

#: The page's 3D background colour (viewer.js) [0-255 RGB].
BACKGROUND = np.array([0xDF, 0xE7, 0xF0])


@pytest.fixture(scope="module")
def browser():
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        pytest.skip("browser tests skipped: Playwright for Python not installed (pip install -e '.[test]')")
    if CHROMIUM is None:
        if os.environ.get("CI") == "true":  # .ci/run installs it: a CI without it is broken, not skipped
            pytest.fail("Chromium not installed in CI: .ci/run must install it (apt-get install chromium)")
        pytest.skip("browser tests skipped: Chromium not installed: apt-get install chromium")
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        yield b
        b.close()


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    """A swinging fixed-length hose (released 15 deg / 10 deg off its balance position: metres of
    motion in 2 s) and a short engagement with two merges, each written as a run folder and viewed."""
    root = tmp_path_factory.mktemp("viewer")
    swing = hd.run(hd.load_scenario("swing-release").with_overrides(duration_s=2.0))
    path = root / "engage20.toml"
    path.write_text(ENGAGE)
    engaged = hd.run(hd.load_scenario(str(path)))
    hd.write(swing, root / "swing", plot=False)
    hd.write(engaged, root / "engaged", plot=False)
    out = {"swing": viewer.write_view([viewer.read_run(root / "swing")], root / "swing.html"),
           "engaged": viewer.write_view([viewer.read_run(root / "engaged")], root / "engaged.html"),
           "both": viewer.write_view([viewer.read_run(root / "swing"), viewer.read_run(root / "engaged")],
                                     root / "both.html")}
    return out


class Page:
    """One viewer page in its own browser context, with every request and page error recorded."""

    def __init__(self, browser, path: Path):
        self.url = path.resolve().as_uri()
        self.context = browser.new_context(viewport={"width": 1280, "height": 800})
        self.requests, self.errors = [], []
        self.context.route("**/*", self._route)
        self.page = self.context.new_page()
        self.page.on("request", lambda r: self.requests.append(r.url))
        self.page.on("pageerror", lambda e: self.errors.append(str(e)))
        self.page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)
        self.page.goto(self.url)
        self._until("Number(document.documentElement.dataset.hdDrawn || 0) >= 1")

    def _until(self, condition: str):
        """Wait (animation frame by frame, at most 10 s) until ``condition`` holds. Not Playwright's
        wait_for_function: it evaluates text, which the page's security policy forbids."""
        assert self.page.evaluate("""(cond) => new Promise((ok, fail) => {
            const test = window[cond];
            const end = performance.now() + 10000;
            const f = () => (test() ? ok(true) : performance.now() > end ? fail(new Error('timeout: ' + cond))
                                                                          : requestAnimationFrame(f));
            f(); })""", self._predicate(condition))

    def _predicate(self, condition: str) -> str:
        """A global function of the page returning ``condition`` (defined through the protocol, not eval)."""
        name = f"__hd_wait_{abs(hash(condition))}"
        self.page.evaluate(f"() => {{ window.{name} = () => ({condition}); }}")
        return name

    def _route(self, route):
        url = route.request.url
        self.requests.append(url)
        if url == self.url or url.startswith(("data:", "blob:")):
            route.continue_()
        else:
            route.abort()

    def js(self, expr: str):
        return self.page.evaluate(expr)

    def draw(self, expr: str):
        """Run ``expr`` and wait until the page has drawn after it."""
        n = self.js("hdViewer.drawCount")
        self.js(expr)
        self._until(f"hdViewer.drawCount > {n}")

    def canvas(self) -> np.ndarray:
        from PIL import Image

        return np.asarray(Image.open(io.BytesIO(self.page.locator("#view3d").screenshot())).convert("RGB")).astype(int)

    def close(self):
        self.context.close()


@pytest.fixture
def open_page(browser):
    opened = []

    def open_(path):
        opened.append(Page(browser, path))
        return opened[-1]

    yield open_
    for p in opened:
        p.close()


def hose_pixels(img: np.ndarray) -> np.ndarray:
    """Mask of the first run's hose colour (#1f5fae, shaded): blue well above red. The background,
    the grid and the HUD are greys with blue at most 40 above red."""
    return (img[..., 2] - img[..., 0]) > 80


def test_the_page_loads_without_a_network_request(open_page, pages):
    """Every request the page makes is its own file (nothing over the network, nothing else from
    disk), and it runs without an error."""
    for name in ("swing", "engaged", "both"):
        p = open_page(pages[name])
        p.draw("hdViewer.setTime(1.0)")
        assert set(p.requests) == {p.url}, p.requests
        assert not p.errors, p.errors


def test_the_canvas_shows_the_hose_and_it_moves(open_page, pages):
    """The canvas is not blank (the hose's colour covers hundreds of pixels, the rest is not all
    background), and at a later time the hose is elsewhere on the screen: the released hose swings
    metres in 2 s, more than 10 px at this scale."""
    p = open_page(pages["swing"])
    p.draw("hdViewer.setCamera('side'); hdViewer.setTime(0.0)")
    a = p.canvas()
    p.draw("hdViewer.setTime(1.5)")
    b = p.canvas()
    for img in (a, b):
        assert hose_pixels(img).sum() > 300
        assert (np.abs(img - BACKGROUND).max(axis=-1) > 30).mean() > 0.005
    changed = (np.abs(a - b).max(axis=-1) > 30).mean()
    ya, xa = np.argwhere(hose_pixels(a)).mean(axis=0)
    yb, xb = np.argwhere(hose_pixels(b)).mean(axis=0)
    assert changed > 0.002 and np.hypot(xa - xb, ya - yb) > 10


def _cursors(p: Page) -> list[tuple[float, float]]:
    """Per chart: the cursor's x and the plot area's width, in CSS pixels from the plot area's left."""
    return p.js("""Array.from(document.querySelectorAll('#charts .u-over')).map(o => {
        const c = o.querySelector('.hd-cursor').getBoundingClientRect(), r = o.getBoundingClientRect();
        return [c.left - r.left, r.width]; })""")


def test_the_charts_cursor_follows_the_3d_time(open_page, pages):
    """At every time set on the 3D view each chart's cursor stands at that time on the chart's
    axis (the axis spans the run, so the cursor is at (t - t0)/(t1 - t0) of the width, within 1.5
    px: the cursor line's rounding); while playing it moves right; a click on a chart sets the
    3D time to the time under the click."""
    p = open_page(pages["engaged"])
    t0, t1 = p.js("hdViewer.span")
    for t in (t0, t0 + 0.3 * (t1 - t0), t0 + 0.85 * (t1 - t0)):
        p.draw(f"hdViewer.setTime({t})")
        cursors = _cursors(p)
        assert len(cursors) == 3
        for x, width in cursors:
            assert x == pytest.approx((t - t0) / (t1 - t0) * width, abs=1.5)
    before = _cursors(p)[0][0]
    p.draw("hdViewer.setTime(hdViewer.span[0]); hdViewer.setLoop(false); hdViewer.play()")
    p.page.wait_for_timeout(400)
    p.draw("hdViewer.pause()")
    played = p.js("hdViewer.time")
    assert played > t0 and _cursors(p)[0][0] == pytest.approx((played - t0) / (t1 - t0) * _cursors(p)[0][1], abs=1.5)
    assert _cursors(p)[0][0] != before
    over = p.page.locator("#charts .u-over").nth(1)
    box = over.bounding_box()
    over.click(position={"x": 0.25 * box["width"], "y": box["height"] / 2})
    p.page.wait_for_timeout(100)
    assert p.js("hdViewer.time") == pytest.approx(t0 + 0.25 * (t1 - t0), abs=1.5 / box["width"] * (t1 - t0))


def test_the_engagement_shows_the_remeshed_hose_and_the_probe(open_page, pages):
    """The page draws the run's own link count at each time (21 joints, 19 after the two merges)
    and says in its HUD that the probe is coupled after contact."""
    p = open_page(pages["engaged"])
    p.draw("hdViewer.setTime(1.0)")
    assert p.js("hdViewer.frames()[0].joints") == 21 and "coupled" not in p.page.locator("#hud").inner_text()
    p.draw("hdViewer.setTime(hdViewer.span[1])")
    assert p.js("hdViewer.frames()[0].joints") == 19 and "coupled" in p.page.locator("#hud").inner_text()
    assert "18 links" in p.page.locator("#hud").inner_text()


def test_the_controls_play_switch_cameras_and_layouts(open_page, pages):
    """The play button and the space key start and stop the clock; each camera shows another
    picture; two runs overlaid and side by side are two pictures with a label per run when side by side."""
    p = open_page(pages["both"])
    p.page.click("#play")
    p.page.wait_for_timeout(300)
    assert p.js("hdViewer.playing") and p.js("hdViewer.time") > 0
    p.page.click("#play")
    assert not p.js("hdViewer.playing")
    p.page.locator("body").press(" ")
    assert p.js("hdViewer.playing")
    p.page.locator("body").press(" ")
    p.draw("hdViewer.setTime(1.0)")
    shots = {}
    for name in ("behind", "side", "above", "orbit"):
        p.page.click(f"[data-camera={name}]")
        p.draw("hdViewer.setTime(1.0)")
        assert p.js("hdViewer.camera") == name
        shots[name] = p.canvas()
    names = list(shots)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            assert (np.abs(shots[a] - shots[b]).max(axis=-1) > 30).mean() > 0.01, (a, b)
    p.page.click("[data-layout=side]")
    p.draw("hdViewer.setTime(1.0)")
    assert p.js("hdViewer.layout") == "side" and p.page.locator("#labels .view-label").count() == 2
    assert (np.abs(p.canvas() - shots["orbit"]).max(axis=-1) > 30).mean() > 0.01
