"""The receiver aircraft in a run's files (docs/receiver.md, "In the run's files"): its time series
as columns of ``timeseries.csv`` after the engagement's, its summary in ``run.json``."""

import dataclasses
import json
import math

import numpy as np
import pandas as pd
import pytest
from scipy.spatial.transform import Rotation

from hosedrogue.engagement.aircraft_receiver import COLUMNS
from hosedrogue.scenarios import load_scenario
from hosedrogue.scenarios.runner import run, write
from hosedrogue.units import unit_of

MOUNT = (8.5, 0.0, 0.0)  # approach-f16-moderate's probe mount [m]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """approach-f16-moderate's first 1.5 s, in steady air (its wake, no gusts) so that the start is
    the trim, written as ``hosedrogue simulate`` writes it."""
    sc = load_scenario("approach-f16-moderate")
    sc = dataclasses.replace(sc, duration_s=1.5, params=sc.params.replace(turbulence={"enabled": False}))
    out = tmp_path_factory.mktemp("f16")
    write(run(sc), out, plot=False)
    return pd.read_csv(out / "timeseries.csv"), json.loads((out / "run.json").read_text())


def test_the_aircraft_columns_follow_the_engagement_with_their_units(files):
    ts, _ = files
    names = list(ts.columns)
    assert names[-len(COLUMNS):] == list(COLUMNS)
    units = {c: unit_of(c) for c in COLUMNS}
    assert units["aircraft_x_m"] == "m" and units["aircraft_roll_rad"] == "rad"
    assert units["aircraft_airspeed_m_s"] == "m/s" and units["aircraft_throttle"] == "1"
    assert ts[list(COLUMNS)].notna().all().all()
    assert ts["aircraft_throttle"].between(0.0, 1.0).all()


def test_the_probe_tip_is_the_columns_cg_and_attitude_moving_the_mount(files):
    """The probe's columns (the compiled engagement's tip, fed the aircraft's path) against the
    aircraft's: its centre of gravity plus the mount turned by scipy's rotation of roll, pitch and
    yaw. At the ends of the 20 ms control steps (every other 10 ms output) the fed cubic passes
    through the aircraft's tip: they agree to the CSV's 10 significant digits, 5e-9 m on each of
    the two 20 m coordinates (1.5e-8 allowed). Between them the cubic Hermite's error is
    h^4/384 |p''''| = 4.2e-10 s^4 |p''''|: 1e-5 m allows 2.4e4 m/s^4."""
    ts, _ = files
    r = Rotation.from_euler("ZYX", ts[["aircraft_yaw_rad", "aircraft_pitch_rad", "aircraft_roll_rad"]].to_numpy())
    tip = ts[["aircraft_x_m", "aircraft_y_m", "aircraft_z_m"]].to_numpy() + r.apply(MOUNT)
    err = np.abs(tip - ts[["probe_x_m", "probe_y_m", "probe_z_m"]].to_numpy()).max(axis=1)
    ends = np.isclose(np.mod(ts["t_s"].to_numpy() + 1e-9, 0.02), 0.0, atol=1e-6)
    assert ends.sum() == 76 and err[ends].max() < 1.5e-8
    assert err[~ends].max() < 1e-5


def test_the_start_is_the_trim_in_run_json(files):
    """In steady air the aircraft starts at its trim: the columns' airspeed, angle of attack,
    sideslip, pitch and controls at t = 0 (from the state and the wake's air there) against the
    trim's solved values in run.json (degrees), to the CSV's 10 digits (1e-8 relative) over the
    trim's 1e-9 m/s^2 acceptance."""
    ts, doc = files
    ac = doc["aircraft"]
    tr = ac["trim"]
    row = ts.iloc[0]
    assert ac["model"] == "f16" and ac["probe_mount_m"] == list(MOUNT)
    json.dumps(ac, allow_nan=False)  # the aircraft's part is strict JSON (raises on NaN or inf)
    assert row["aircraft_airspeed_m_s"] == pytest.approx(tr["airspeed_m_s"], rel=1e-8)
    for col, key in (("alpha_rad", "alpha_deg"), ("beta_rad", "beta_deg"), ("pitch_rad", "theta_deg"),
                     ("elevator_rad", "elevator_deg"), ("aileron_rad", "aileron_deg"), ("rudder_rad", "rudder_deg")):
        assert row[f"aircraft_{col}"] == pytest.approx(math.radians(tr[key]), rel=1e-8, abs=1e-12), col
    assert row["aircraft_throttle"] == pytest.approx(tr["throttle"], rel=1e-8)


def test_the_summary_peaks_are_the_columns(files):
    """run.json's peak changes from the start against the CSV's columns: a difference of two values
    each rounded to 10 significant digits, within 1e-9 of the column's largest value (151 m/s:
    1e-7 m/s)."""
    ts, doc = files
    ac = doc["aircraft"]
    for stem, unit in (("roll", "_rad"), ("pitch", "_rad"), ("yaw", "_rad"), ("airspeed", "_m_s"),
                       ("alpha", "_rad"), ("beta", "_rad"), ("throttle", "")):
        c = ts[f"aircraft_{stem}{unit}"].to_numpy()
        assert ac[f"peak_{stem}_change{unit}"] == pytest.approx(np.abs(c - c[0]).max(), abs=1e-9 * np.abs(c).max())
    assert ac["peak_pitch_change_rad"] > 0.0  # the controller flies the aircraft: the attitude moves
