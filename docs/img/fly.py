"""Make the screenshots of docs/fly.md (docs/img/fly_*.png): ``hosedrogue fly approach-moderate``
served in this process and flown by a script in Debian's headless Chromium (Playwright): the
right arrow, then the up arrow, held, closing on the drogue. Run it after a change to the live
page (about half a minute; needs Chromium: apt-get install chromium):

    .venv/bin/python docs/img/fly.py
"""

import io
import shutil
import tempfile
from pathlib import Path

import hosedrogue as hd
from hosedrogue import fly

HERE = Path(__file__).parent


def shot(page, name: str) -> None:
    from PIL import Image

    png = Image.open(io.BytesIO(page.screenshot())).convert("RGB")
    # 256 colours: the page's flat colours survive, the file stays small
    png.quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(HERE / name, optimize=True)


def main() -> None:
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as tmp:
        live = fly.LiveFlight(hd.load_scenario("approach-moderate"), Path(tmp) / "flights", log=lambda line: None)
        server = fly.FlyServer(live, log=lambda line: None).start()
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=shutil.which("chromium") or "/usr/bin/chromium",
                                        args=["--no-sandbox"])
            page = browser.new_page(viewport={"width": 1280, "height": 760})
            page.goto(server.url)
            page.wait_for_timeout(1000)
            page.keyboard.press("Enter")
            page.keyboard.down("ArrowRight")
            page.wait_for_timeout(500)
            page.keyboard.up("ArrowRight")
            page.keyboard.down("ArrowUp")
            page.wait_for_timeout(400)
            page.keyboard.up("ArrowUp")
            page.wait_for_timeout(700)
            shot(page, "fly_cockpit.png")
            page.keyboard.press("2")
            page.wait_for_timeout(300)
            shot(page, "fly_side.png")
            page.keyboard.press("1")
            while live.state != "ended":
                page.wait_for_timeout(100)
            page.wait_for_timeout(500)
            shot(page, "fly_ended.png")
            browser.close()
        server.stop("the screenshots are taken")
        server.wait(30.0)


if __name__ == "__main__":
    main()
