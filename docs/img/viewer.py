"""Make the viewer's screenshots of docs/viewer.md (docs/img/viewer_*.png): the shipped scenarios
in the viewer page, photographed by Debian's headless Chromium (Playwright). Run it after a change
to the viewer or to these runs (about two minutes; needs Chromium: apt-get install chromium):

    .venv/bin/python docs/img/viewer.py
"""

import io
import shutil
import tempfile
from pathlib import Path

import hosedrogue as hd
from hosedrogue import viewer
from hosedrogue.studies.docking import APPROACH_RUNS, APPROACH_SEED, approach_runs

HERE = Path(__file__).parent
REELS = ("engage-locked", "engage-constant-tension", "engage-response")

#: name -> (page, viewport [CSS px], what to do before the picture: JavaScript on hdViewer)
SHOTS = {
    "viewer_locked.png": ("locked", (1280, 720), "hdViewer.setCamera('behind'); hdViewer.setTime(2.8)"),
    "viewer_reels_side.png": ("reels", (1280, 720), "hdViewer.setLayout('side'); hdViewer.setCamera('side'); "
                                                    "hdViewer.setTime(3.0)"),
    "viewer_approach.png": ("approach", (1280, 720), "hdViewer.setCamera('behind'); hdViewer.setTime(2.6)"),
}


def pages(folder: Path) -> dict:
    """The viewer pages of the screenshots, written into ``folder``."""
    reels = {name: hd.run(hd.load_scenario(name)) for name in REELS}
    approaches = approach_runs(runs=tuple(APPROACH_RUNS), seed=APPROACH_SEED)
    return {
        "locked": viewer.write_view([viewer.ViewRun.from_result(reels["engage-locked"])], folder / "locked.html"),
        "reels": viewer.write_view([viewer.ViewRun.from_result(r, label=n.removeprefix("engage-"))
                                    for n, r in reels.items()], folder / "reels.html", frame_rate_hz=25.0),
        "approach": viewer.write_view([viewer.ViewRun.from_result(r, label=n) for n, r in approaches.items()],
                                      folder / "approach.html", layout="side"),
    }


def main() -> None:
    from PIL import Image
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as tmp:
        made = pages(Path(tmp))
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=shutil.which("chromium") or "/usr/bin/chromium",
                                        args=["--no-sandbox"])
            for name, (page_key, (w, h), script) in SHOTS.items():
                page = browser.new_page(viewport={"width": w, "height": h})
                page.goto(made[page_key].resolve().as_uri())
                page.evaluate("""() => new Promise(ok => { const f = () => document.documentElement.dataset.hdDrawn
                    ? ok() : requestAnimationFrame(f); f(); })""")
                page.evaluate(f"() => {{ {script}; }}")
                page.wait_for_timeout(500)
                png = Image.open(io.BytesIO(page.screenshot())).convert("RGB")
                # 256 colours: the page's flat colours survive, the file stays small
                png.quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(HERE / name, optimize=True)
                print(f"wrote {HERE / name} ({(HERE / name).stat().st_size / 1e3:.0f} kB)")
                page.close()
            browser.close()


if __name__ == "__main__":
    main()
