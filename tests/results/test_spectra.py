"""The spectrum of a run's drogue offset (hosedrogue.results.spectra): Parseval on signals whose
power is known, the stated resolution, and a scenario's run.json with its linear prediction."""

import json
import math
from types import SimpleNamespace

import numpy as np
import pytest

from hosedrogue.results.spectra import F_MAX_HZ, displacement_spectrum, rms_from_spectrum


def _run(t, y, z, window=(0.0, math.inf)):
    off = np.column_stack([np.zeros_like(t), y, z])
    return SimpleNamespace(t_s=t, drogue_offset_m=off, statistics_window_s=window, meta={})


def test_sinusoids_power_and_resolution():
    # A sinusoid of amplitude a on a frequency bin holds a^2 / 2 of power: the Hann-windowed
    # density sums to it (the window's equivalent noise bandwidth is in scipy's scaling), up to the
    # leakage outside F_MAX_HZ (none here, 0.3 and 1.2 Hz) and round-off: tolerance 1e-6.
    h, T = 0.01, 400.0
    t = np.arange(0.0, T, h)
    y = 0.2 * np.sin(2 * np.pi * 0.3 * t)
    z = 0.05 * np.sin(2 * np.pi * 1.2 * t + 0.4)
    spec = displacement_spectrum(_run(t, y, z))
    assert spec["segment_s"] == pytest.approx(40.0) and spec["resolution_hz"] == pytest.approx(0.025)
    assert max(spec["frequency_hz"]) <= F_MAX_HZ
    lat, ver = rms_from_spectrum(spec)
    assert lat**2 == pytest.approx(0.2**2 / 2, rel=1e-6)
    assert ver**2 == pytest.approx(0.05**2 / 2, rel=1e-6)
    f = np.array(spec["frequency_hz"])
    assert f[np.argmax(spec["lateral_m2_hz"])] == pytest.approx(0.3)
    assert f[np.argmax(spec["vertical_m2_hz"])] == pytest.approx(1.2)


def test_short_window_halves_and_too_short_is_none():
    h = 0.01
    t = np.arange(0.0, 30.0, h)
    y = np.sin(2 * np.pi * 0.5 * t)
    spec = displacement_spectrum(_run(t, y, y, window=(10.0, 30.0)))
    assert spec["window_s"] == pytest.approx([10.0, 30.0]) and spec["segment_s"] == pytest.approx(10.0)
    assert displacement_spectrum(_run(t, y, y, window=(10.0, 11.0))) is None  # 100 samples


def test_scenario_run_json_spectrum_with_prediction():
    # paper-turbulence-pid, 4 s of its gust window (from 10 s): the PSD and its prediction are in
    # run.json as strict JSON; an engagement's run has none (its hose length varies).
    from hosedrogue.scenarios import load_scenario
    from hosedrogue.scenarios.runner import run
    from hosedrogue.scenarios.spectrum import spectrum_prediction

    result = run(load_scenario("paper-turbulence-pid").with_overrides(duration_s=14.0))
    spec = result.run_document()["spectrum"]
    json.dumps(spec, allow_nan=False)
    assert spec["window_s"] == pytest.approx([10.0, 14.0], abs=0.011)  # the last sample's step (0.01 s)
    pred = spec["predicted"]
    assert set(pred["rms_m"]) == {"lateral", "vertical"} and len(pred["frequency_hz"]) == len(pred["lateral_m2_hz"])
    note = spectrum_prediction(load_scenario("approach-moderate"))
    assert "engagement" in note["note"]
