"""The viewer's page: its size and its frame rate in headless Chromium, printed (never asserted).

* the size of the page of a 15 s engagement at 160 links (the shipped ``engage-locked``: output
  every 10 ms, 1501 output times) with every output time as a 3D frame and at 25 frames per
  simulated second, and of the report's page of the three reels; the run folder's ``hose.npz``;
* the frame rate while playing, from the page's requestAnimationFrame-driven draws
  (``hdViewer.measureFrameRate``: draws counted over 5 s of playing, their timestamps from
  ``performance.now()``), in Debian's headless Chromium driven by Playwright, at 1280 x 800 CSS
  pixels, for one run and for the three runs overlaid and side by side. Headless Chromium draws
  WebGL in software (SwiftShader) on the CPU, where the page turns multisampling off (it halves
  the frame rate there); a browser with a GPU draws faster, antialiased.

Run:  .venv/bin/python benchmarks/viewer.py [--out DIR]   (needs Chromium: apt-get install chromium)
"""

from __future__ import annotations

import argparse
import shutil
import time
from pathlib import Path

import hosedrogue as hd
from hosedrogue import viewer

#: Frame rate a player needs to look smooth [1/s] (the target printed beside the measurement).
SMOOTH_FPS = 30.0

REELS = ("engage-locked", "engage-constant-tension", "engage-response")


def _runs(out: Path) -> dict:
    """The three shipped engagements (160 links, 15 s), written once into ``out`` and read back."""
    views = {}
    for name in REELS:
        folder = out / name
        if not (folder / "hose.npz").is_file():
            t0 = time.perf_counter()
            result = hd.run(hd.load_scenario(name))
            hd.write(result, folder, plot=False)
            print(f"ran {name}: {time.perf_counter() - t0:.1f} s wall (compile included)")
        views[name] = viewer.read_run(folder)
    return views


def _frame_rate(page_path: Path, layout: str | None = None, seconds: float = 5.0) -> dict:
    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1280, "height": 800})
        t0 = time.perf_counter()
        page.goto(page_path.resolve().as_uri())
        page.evaluate("""() => new Promise(ok => { const f = () => document.documentElement.dataset.hdDrawn
            ? ok() : requestAnimationFrame(f); f(); })""")
        load_s = time.perf_counter() - t0
        if layout:
            page.evaluate(f"() => hdViewer.setLayout('{layout}')")
        page.evaluate("() => hdViewer.setSpeed(0.5)")
        rate = page.evaluate(f"() => hdViewer.measureFrameRate({int(seconds * 1000)})")
        gl = page.evaluate("() => hdViewer.gl")
        browser.close()
    return {"load_s": load_s, "gl": gl, **rate}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="out/bench-viewer", help="folder for the runs and pages")
    out = Path(parser.parse_args().out)
    out.mkdir(parents=True, exist_ok=True)
    views = _runs(out)
    locked = views["engage-locked"]
    print(f"\nengage-locked: {locked.t_s.size} output times, {int(locked.joint_count.max()) - 1} links, "
          f"{locked.t_s[-1]:g} s; hose.npz {(out / 'engage-locked' / 'hose.npz').stat().st_size / 1e6:.2f} MB")
    pages = {"one run, every output time": viewer.write_view([locked], out / "locked-all.html"),
             "one run, 25 frames/s": viewer.write_view([locked], out / "locked-25.html", frame_rate_hz=25.0),
             "three reels, 25 frames/s (the report's)": viewer.write_view(list(views.values()), out / "reels-25.html",
                                                                          frame_rate_hz=25.0),
             "three reels, every output time": viewer.write_view(list(views.values()), out / "reels-all.html")}
    print("\npage sizes")
    for what, path in pages.items():
        print(f"  {what:<42} {path.stat().st_size / 1e6:6.2f} MB")
    print(f"\nframe rate while playing (headless Chromium, software WebGL, 1280 x 800; target {SMOOTH_FPS:g} /s)")
    for what, path, layout in (("one run, every output time", pages["one run, every output time"], None),
                               ("three reels overlaid", pages["three reels, 25 frames/s (the report's)"], "overlay"),
                               ("three reels side by side", pages["three reels, 25 frames/s (the report's)"], "side")):
        r = _frame_rate(path, layout)
        print(f"  {what:<28} {r['fps']:6.1f} frames/s ({r['frames']} draws in {r['seconds']:.2f} s); "
              f"page loaded and first frame drawn in {r['load_s']:.2f} s")
    print(f"  WebGL: {r['gl']['name']}; multisampling {'on' if r['gl']['antialias'] else 'off (software WebGL)'}")


if __name__ == "__main__":
    main()
