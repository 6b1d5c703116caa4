"""Monte Carlo campaigns of engagement scenarios: each run goes to the engagement driver, runs.csv
gains result / miss_distance_m / closure_speed_m_s, summary.json a "capture" block with the Wilson
interval; rows do not depend on the number of workers or on interruption (exact comparisons, as in
tests/studies/test_campaign.py)."""

import json
import os
import re

import numpy as np
import pytest
from scipy import stats

from hosedrogue.studies import executor
from hosedrogue.studies.campaign import run_campaign
from hosedrogue.studies.statistics import wilson_interval
from test_campaign import assert_same_rows, interrupted_copy

#: approach-moderate's physics on a coarse mesh (10 links of 1.6 m, 3.5 s: contact at ~3 s) so a
#: run takes a few tens of ms; moderate turbulence: both captures and misses occur (5 of 12 captured with campaign seed 0).
TINY = """\
[scenario]
name = "tiny-approach"
duration_s = 3.5

[model]
preset = "converged"

[hose]
links = 10

[flight]
altitude_m = 8000.0
airspeed_m_s = 150.0

[turbulence]
enabled = true
intensity = "moderate"
start_s = 0.0
duration_s = 3.5

[numerics]
step_s = 0.005
output_every = 4

[reel]
law = "response"

[probe]
standoff_m = 3.0
closure_speed_m_s = 1.0
push_m = 0.5

[bow_wave]
enabled = true
"""
RUNS = 12


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = tmp_path_factory.mktemp("scenarios") / "tiny-approach.toml"
    path.write_text(TINY)
    return str(path)


@pytest.fixture(scope="module")
def reference(tiny, tmp_path_factory):
    out = tmp_path_factory.mktemp("reference")
    return out, run_campaign(tiny, RUNS, out, scheduler="synchronous", progress=False)


@pytest.mark.parametrize("k,n", [(0, 1), (1, 1), (0, 20), (3, 20), (10, 20), (20, 20), (137, 200), (999, 1000)])
def test_wilson_interval_against_scipy(k, n):
    ref = stats.binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
    # the same closed form evaluated independently: round-off of O(1) numbers
    np.testing.assert_allclose(wilson_interval(k, n), (ref.low, ref.high), rtol=1e-12, atol=1e-14)


def test_capture_block_and_columns(reference):
    out, summary = reference
    table = summary.runs
    assert {"result", "miss_distance_m", "closure_speed_m_s"} <= set(table.columns)
    cap = json.loads((out / "summary.json").read_text())["capture"]
    k = int((table["result"] == "captured").sum())
    assert cap["runs"] == RUNS == sum(cap["by_result"].values())
    assert cap["by_result"]["captured"] == k and cap["rate"] == k / RUNS
    assert cap["ci95"] == pytest.approx(list(wilson_interval(k, RUNS)), rel=1e-15)
    assert 0 < k < RUNS, "the tiny campaign should hold both captures and misses"
    # the result agrees with the capture test: a capture inside the 0.305 m radius and the 0.5-3
    # m/s window, a miss outside the radius
    cap_rows = table[table["result"] == "captured"]
    assert (cap_rows["miss_distance_m"] <= 0.305).all()
    assert cap_rows["closure_speed_m_s"].between(0.5, 3.0).all()
    assert (table[table["result"] == "miss"]["miss_distance_m"] > 0.305).all()
    assert (out / "miss_cdf.png").stat().st_size > 1000


def test_resume_completes_identically(reference, tiny, tmp_path):
    ref, _ = reference
    out = interrupted_copy(ref, tmp_path / "out", keep_rows=5)
    summary = run_campaign(tiny, RUNS, out, scheduler="synchronous", progress=False)
    assert summary.new_runs == RUNS - 5
    assert_same_rows(out, ref)
    assert (out / "summary.json").read_text() == (ref / "summary.json").read_text()


@pytest.mark.dask
def test_rows_do_not_depend_on_workers(reference, tiny, tmp_path):
    pytest.importorskip("distributed")
    ref, _ = reference
    cluster, client = executor.local_cluster(1)
    try:
        one = tmp_path / "one"
        run_campaign(tiny, RUNS, one, client=client, progress=False)
        cluster.scale(2)
        client.wait_for_workers(2)
        two = tmp_path / "two"
        run_campaign(tiny, RUNS, two, client=client, progress=False)
    finally:
        client.close()
        cluster.close()
    assert_same_rows(one, ref)
    assert_same_rows(two, ref)
    assert (two / "summary.json").read_text() == (ref / "summary.json").read_text()


def test_montecarlo_command_on_a_shipped_approach_scenario(tmp_path, capsys):
    from hosedrogue import cli

    out = tmp_path / "mc"
    code = cli.main(["montecarlo", "approach-moderate", "--runs", "2", "--scheduler", "synchronous",
                     "--out", str(out), "--quiet"])
    assert code == 0
    text = capsys.readouterr().out
    assert re.search(r"capture rate \d\.\d{3} \(Wilson 95 %: \d\.\d{3}-\d\.\d{3}\) over 2 runs", text)
    header = (out / "runs.csv").read_text().splitlines()[0].split(",")
    assert header[-7:] == ["result", "miss_distance_m", "closure_speed_m_s", "peak_probe_load_n",
                           "peak_exit_tension_n", "peak_slack_m", "message"]
