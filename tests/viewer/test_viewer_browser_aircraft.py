"""The viewer draws the receiver aircraft, in headless Chromium (the browser tests' machinery of
test_viewer_browser.py): seen from above, an F-16 run shows a grey body of thousands of pixels
that a thin line (the grid, the probe's mast) cannot make, and the same run without its aircraft
columns shows none."""

import dataclasses

import numpy as np
import pytest
from scipy import ndimage

import hosedrogue as hd
from hosedrogue import viewer
from hosedrogue.viewer.runs import AIRCRAFT
from test_viewer_browser import BACKGROUND, browser, open_page  # noqa: F401 (fixtures)

pytestmark = pytest.mark.browser


@pytest.fixture(scope="module")
def aircraft_pages(tmp_path_factory):
    root = tmp_path_factory.mktemp("viewer_f16")
    sc = hd.load_scenario("approach-f16-moderate")
    hd.write(hd.run(dataclasses.replace(sc, duration_s=1.0)), root / "f16", plot=False)
    run = viewer.read_run(root / "f16")
    bare = dataclasses.replace(run, columns={k: v for k, v in run.columns.items() if k not in AIRCRAFT})
    return (viewer.write_view([run], root / "f16.html"), viewer.write_view([bare], root / "bare.html"))


def grey_body_pixels(img: np.ndarray) -> int:
    """Pixels of a grey area (channels within 40 of each other, 40 darker than the background),
    after an opening with a 7 x 7 square: lines of a few pixels (the grid, the mast) vanish."""
    grey = (img.max(axis=2) - img.min(axis=2) < 40) & (img.sum(axis=2) < BACKGROUND.sum() - 40)
    return int(ndimage.binary_opening(grey, structure=np.ones((7, 7))).sum())


def test_the_aircraft_is_drawn_from_above(open_page, aircraft_pages):
    f16_path, bare_path = aircraft_pages
    counts = []
    for path in (f16_path, bare_path):
        page = open_page(path)
        page.draw("hdViewer.setCamera('above')")
        counts.append(grey_body_pixels(page.canvas()))
        assert not page.errors
    assert counts[0] > 3000 and counts[1] < 100, counts
