"""The viewer draws the receiver aircraft (docs/receiver.md, "In the run's files"): a run whose
receiver is an aircraft carries its position and attitude into the page's frames, read from the
run's folder as from the result in memory; a point receiver's run carries none."""

import base64
import dataclasses

import numpy as np
import pytest

import hosedrogue as hd
from hosedrogue import viewer
from hosedrogue.viewer.page import _frames
from hosedrogue.viewer.runs import AIRCRAFT


@pytest.fixture(scope="module")
def f16(tmp_path_factory):
    sc = hd.load_scenario("approach-f16-moderate")
    result = hd.run(dataclasses.replace(sc, duration_s=1.0))
    folder = tmp_path_factory.mktemp("f16")
    hd.write(result, folder, plot=False)
    return result, folder


def _decode(b64, width):
    return np.frombuffer(base64.b64decode(b64), dtype="<f4").reshape(-1, width)


def test_the_frames_carry_the_aircraft_from_the_folder_and_from_memory(f16):
    """Both the folder's run (CSV, 10 digits) and the result's give the columns at the frames, to
    float32's 6e-8 relative (2e-6 m at 26 m; 1e-6 m and rad allowed beyond that for the CSV)."""
    result, folder = f16
    cols = result.columns()
    for run in (viewer.read_run(folder), viewer.ViewRun.from_result(result)):
        fr = _frames(run, None)
        got = _decode(fr["aircraft"], 6)
        want = np.column_stack([cols[c] for c in AIRCRAFT])
        assert got.shape == want.shape
        assert np.allclose(got, want, rtol=1e-7, atol=1e-6)


def test_a_point_receiver_run_has_no_aircraft(tmp_path):
    sc = hd.load_scenario("approach-moderate-docking")
    run = viewer.ViewRun.from_result(hd.run(dataclasses.replace(sc, duration_s=0.2)))
    assert "aircraft" not in _frames(run, None) or _frames(run, None)["aircraft"] is None
    assert not any(c in run.columns for c in AIRCRAFT)
