"""Monte Carlo campaigns: results independent of the number of workers, of completion order and
of interruption (resume), bounded work in flight, the output files and the error behaviour.

Every comparison of results is exact: each run is a deterministic function of (campaign seed, run
index) and runs.csv stores floats as their shortest round-trip strings, so sorted rows must match
character for character.
"""

import csv
import fcntl
import json
import math
import operator
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from hosedrogue.results import statistics as metrics
from hosedrogue.studies import executor, store
from hosedrogue.studies.campaign import run_campaign
from hosedrogue.studies.seeds import run_seed
from hosedrogue.spec.params import ParameterError

#: 6 links, 3 s, turbulence on from 0.5 s for 2 s: a run takes ~25 ms once compiled.
TINY = """\
[scenario]
name = "tiny-turbulence"
duration_s = 3.0

[turbulence]
enabled = true
start_s = 0.5
duration_s = 2.0

[hose]
links = 6
"""


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = tmp_path_factory.mktemp("scenarios") / "tiny.toml"
    path.write_text(TINY)
    return str(path)


@pytest.fixture(scope="module")
def tiny_pid(tmp_path_factory):
    path = tmp_path_factory.mktemp("scenarios") / "tiny-pid.toml"
    path.write_text(TINY + '\n[controller]\ntype = "pid"\n')
    return str(path)


@pytest.fixture(scope="module")
def reference(tiny, tmp_path_factory):
    """An 8-run campaign run in this process (no dask): the reference for every comparison."""
    out = tmp_path_factory.mktemp("reference")
    summary = run_campaign(tiny, 8, out, scheduler="synchronous", progress=False)
    return out, summary


@pytest.fixture(scope="module")
def dask_cluster():
    """campaign's own 1-process LocalCluster, shared by the module (starting one costs seconds)."""
    pytest.importorskip("distributed")
    cluster, client = executor.local_cluster(1)
    yield cluster, client
    client.close()
    cluster.close()


def rows_by_run(out):
    """(header, data lines sorted by (run, controller)) of out/runs.csv, as raw text."""
    with open(Path(out) / "runs.csv", newline="") as fh:
        lines = list(csv.reader(fh))
    header, data = lines[0], lines[1:]
    run, ctrl = header.index("run"), header.index("controller")
    return header, sorted(data, key=lambda r: (int(r[run]), r[ctrl]))


def assert_same_rows(out, ref):
    """runs.csv of ``out`` and ``ref`` hold the same rows, character for character."""
    header, rows = rows_by_run(out)
    ref_header, ref_rows = rows_by_run(ref)
    assert header == ref_header and len(rows) == len(ref_rows)
    diffs = [(b[0], b[1], header[k], b[k], a[k]) for a, b in zip(rows, ref_rows)
             for k in range(len(header)) if a[k] != b[k]]
    assert not diffs, f"(run, controller, column, reference, this) differ: {diffs}"


def interrupted_copy(src, dst, keep_rows):
    """dst: src's campaign.json and runs.csv cut after ``keep_rows`` rows plus half of the next
    row, as a kill in the middle of a write leaves it."""
    dst = Path(dst)
    dst.mkdir()
    shutil.copy(Path(src) / "campaign.json", dst / "campaign.json")
    lines = (Path(src) / "runs.csv").read_text().splitlines(keepends=True)
    partial = lines[keep_rows + 1][: len(lines[keep_rows + 1]) // 2]
    (dst / "runs.csv").write_text("".join(lines[: keep_rows + 1]) + partial)
    return dst


# --- seeds ---------------------------------------------------------------------------------------
def test_run_seeds_depend_on_campaign_seed_and_index_only():
    rng = np.random.default_rng(1)
    order = rng.permutation(1000)
    in_order = [run_seed(7, i) for i in range(1000)]
    shuffled = {int(i): run_seed(7, int(i)) for i in order}
    assert in_order == [shuffled[i] for i in range(1000)]
    assert len(set(in_order)) == 1000  # 1000 draws from 2**63: a collision has probability ~5e-14
    assert all(0 <= s < 2**63 for s in in_order)
    assert run_seed(7, 3) == int(
        np.random.SeedSequence([7, 3]).generate_state(1, dtype=np.uint64)[0]) % 2**63
    assert [run_seed(8, i) for i in range(100)] != in_order[:100]


# --- bad input -----------------------------------------------------------------------------------
BAD = [
    (dict(runs=0), "runs"),
    (dict(runs=2.5), "runs"),
    (dict(workers=0), "workers"),
    (dict(seed=-1), "seed"),
    (dict(capture_radii_m=(0.0,)), "capture_radii_m"),
    (dict(capture_radii_m=(0.1, -0.3)), "capture_radii_m"),
    (dict(capture_radii_m=()), "capture_radii_m"),
    (dict(capture_radii_m=(0.1, 0.1)), "capture_radii_m"),
    (dict(duration_s=0.0), "duration_s"),
    (dict(compare_controller=True), "compare_controller"),
    (dict(workers=2, scheduler="tcp://127.0.0.1:1"), "workers"),
    (dict(scenario="no-such-scenario"), "no-such-scenario"),
]


@pytest.mark.parametrize("kwargs, names", BAD, ids=[n + "-" + str(i) for i, (_, n) in enumerate(BAD)])
def test_bad_input_is_rejected_before_any_output(tiny, tmp_path, kwargs, names):
    kwargs = dict(kwargs)
    scenario = kwargs.pop("scenario", tiny)
    runs = kwargs.pop("runs", 2)
    out = tmp_path / "out"
    with pytest.raises(ParameterError) as info:
        run_campaign(scenario, runs, out, progress=False, **kwargs)
    message = str(info.value)
    assert names in message and "\n" not in message
    assert not out.exists()


@pytest.mark.dask
def test_unreachable_scheduler_leaves_no_output(tiny, tmp_path, monkeypatch):
    pytest.importorskip("distributed")
    monkeypatch.setattr(executor, "CONNECT_TIMEOUT_S", 1.0)
    out = tmp_path / "out"
    with pytest.raises(ParameterError, match="scheduler"):
        run_campaign(tiny, 2, out, scheduler="tcp://127.0.0.1:9", progress=False)
    assert not out.exists()


def test_resuming_with_other_settings_is_rejected(reference, tiny, tmp_path):
    ref, _ = reference
    out = shutil.copytree(ref, tmp_path / "out")
    before = {p.name: p.read_bytes() for p in Path(out).iterdir()}
    for kwargs, differing in [(dict(seed=1), "seed"), (dict(runs=9), "runs"),
                              (dict(capture_radii_m=(0.2,)), "capture_radii_m"),
                              (dict(duration_s=2.5), "duration_s")]:
        kwargs.setdefault("runs", 8)
        with pytest.raises(ParameterError, match=differing):
            run_campaign(tiny, out_dir=out, scheduler="synchronous", progress=False, **kwargs)
    assert {p.name: p.read_bytes() for p in Path(out).iterdir()} == before


def test_a_second_writer_is_locked_out(reference, tiny, tmp_path):
    out = shutil.copytree(reference[0], tmp_path / "out")
    with open(Path(out) / ".lock", "a") as fh:
        fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(ParameterError, match="another campaign"):
            run_campaign(tiny, 8, out, scheduler="synchronous", progress=False)


# --- resume --------------------------------------------------------------------------------------
def test_resume_drops_a_partial_line_and_completes_identically(reference, tiny, tmp_path):
    ref, _ = reference
    out = interrupted_copy(ref, tmp_path / "out", keep_rows=4)
    summary = run_campaign(tiny, 8, out, scheduler="synchronous", progress=False)
    assert summary.new_runs == 4
    assert_same_rows(out, ref)
    assert (out / "summary.json").read_text() == (ref / "summary.json").read_text()
    assert (out / "summary.csv").read_text() == (ref / "summary.csv").read_text()


def test_resume_after_a_partial_header(reference, tiny, tmp_path):
    ref, _ = reference
    out = tmp_path / "out"
    out.mkdir()
    shutil.copy(ref / "campaign.json", out)
    (out / "runs.csv").write_text("run,contro")
    summary = run_campaign(tiny, 8, out, scheduler="synchronous", progress=False)
    assert summary.new_runs == 8
    assert_same_rows(out, ref)


@pytest.mark.subprocess
def test_a_killed_campaign_resumes_to_the_same_result(tiny, tmp_path):
    """SIGKILL a campaign process part-way (no chance to clean up), then resume it."""
    runs = 30
    ref = tmp_path / "ref"
    run_campaign(tiny, runs, ref, scheduler="synchronous", progress=False)
    out = tmp_path / "killed"
    code = (f"from hosedrogue.studies.campaign import run_campaign; "
            f"run_campaign({tiny!r}, {runs}, {str(out)!r}, scheduler='synchronous', progress=False)")
    proc = subprocess.Popen([sys.executable, "-c", code], stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 45.0
        csv_path = out / "runs.csv"
        while time.monotonic() < deadline and proc.poll() is None:
            if csv_path.exists() and csv_path.read_bytes().count(b"\n") > 5:
                break
            time.sleep(0.005)
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    summary = run_campaign(tiny, runs, out, scheduler="synchronous", progress=False)
    assert 0 < summary.new_runs < runs, "the process finished before it was killed"
    assert_same_rows(out, ref)


# --- workers -------------------------------------------------------------------------------------
@pytest.mark.dask
def test_results_do_not_depend_on_workers_or_interruption(reference, dask_cluster, tiny, tmp_path):
    ref, _ = reference
    cluster, client = dask_cluster
    assert set(client.run(os.getenv, "NUMBA_NUM_THREADS").values()) == {"1"}
    assert list(client.nthreads().values()) == [1]
    one = tmp_path / "one"
    run_campaign(tiny, 8, one, client=client, progress=False)
    cluster.scale(2)
    client.wait_for_workers(2)
    assert list(client.nthreads().values()) == [1, 1]
    two = tmp_path / "two"
    run_campaign(tiny, 8, two, client=client, progress=False)
    assert_same_rows(one, ref)
    assert_same_rows(two, ref)
    for name in ("summary.json", "summary.csv"):
        assert (one / name).read_text() == (ref / name).read_text()
        assert (two / name).read_text() == (ref / name).read_text()

    resumed = interrupted_copy(two, tmp_path / "resumed", keep_rows=4)
    summary = run_campaign(tiny, 8, resumed, client=client, progress=False)
    assert summary.new_runs == 4
    assert_same_rows(resumed, ref)


@pytest.mark.dask
def test_work_in_flight_is_bounded(dask_cluster):
    results = []
    peak = executor.execute_dask(dask_cluster[1], iter(range(40)), operator.neg, 3, results.append)
    assert peak == 3
    assert sorted(results) == sorted(-i for i in range(40))


class _CountingClient:
    """A dask client that counts the tasks submitted to it."""

    def __init__(self, client):
        self.client, self.submitted = client, 0

    def submit(self, *args, **kw):
        self.submitted += 1
        return self.client.submit(*args, **kw)

    def __getattr__(self, name):
        return getattr(self.client, name)


@pytest.mark.dask
def test_short_tasks_reach_dask_in_batches(dask_cluster):
    """40 tasks of 50 ms: the first dask tasks carry one each, the later as many as take about
    BATCH_S (0.25 s: about 5), so far fewer than 40 dask tasks run them all, every result arriving."""
    client = _CountingClient(dask_cluster[1])
    results = []
    executor.execute_dask(client, iter([0.05] * 40), time.sleep, 3, results.append)
    assert results == [None] * 40
    assert 3 < client.submitted < 20, client.submitted  # 3 single tasks first; batches of 16 at most


def test_a_batch_stopped_by_an_error_returns_the_results_before_it():
    results, wall_s, error = executor.run_batch((1.0).__truediv__, [2.0, 4.0, 0.0, 8.0])
    assert results == [0.5, 0.25] and isinstance(error, ZeroDivisionError) and wall_s >= 0.0
    assert executor.run_batch(operator.neg, [1, 2])[0::2] == ([-1, -2], None)


# --- outputs -------------------------------------------------------------------------------------
def test_campaign_seed_changes_results_and_summary_is_complete(reference, tiny, tmp_path):
    ref, summary = reference
    other = run_campaign(tiny, 8, tmp_path / "seed1", seed=1, scheduler="synchronous", progress=False)
    assert not set(other.runs["seed"]) & set(summary.runs["seed"])
    assert not np.any(other.runs["peak_radial_m"].to_numpy() == summary.runs["peak_radial_m"].to_numpy())

    data = json.loads((ref / "summary.json").read_text())
    assert data["campaign"]["runs"] == 8 and data["campaign"]["seed"] == 0
    block = data["controllers"]["none"]
    assert block["runs"] == 8 and block["completed_fraction"] == 1.0
    expected = metrics.statistic_units((0.1, 0.305))
    assert set(block["statistics"]) == set(expected)
    for name, st in block["statistics"].items():
        assert st["count"] == 8 and st["unit"] == expected[name]
        values = [st[k] for k in ("mean", "std", "median", "p05", "p95")] + st["ci95_mean"]
        assert all(math.isfinite(v) for v in values), name
        lo, hi = st["ci95_mean"]
        assert lo <= st["mean"] <= hi and st["p05"] <= st["median"] <= st["p95"]
    # open loop: the turbulence moves the drogue, and no control force acts
    assert block["statistics"]["peak_radial_m"]["mean"] > 0.01
    assert block["statistics"]["peak_u_n"]["p95"] == 0.0
    for name in ("histograms.png", "cdf.png", "summary.csv", "timings.csv"):
        assert (ref / name).stat().st_size > 0
    assert "wall" not in (ref / "runs.csv").read_text().splitlines()[0]


def test_statistics_inside_the_turbulence_window(reference, tiny):
    """Recompute one row from a fresh run of the same seed, independently of summarize_run."""
    from hosedrogue.scenarios.runner import run as run_scenario
    from hosedrogue.scenarios import load_scenario

    _, summary = reference
    row = summary.runs.iloc[3]
    res = run_scenario(load_scenario(tiny).with_overrides(seed=run_seed(0, 3)))
    keep = [k for k, t in enumerate(res.t_s) if 0.5 - 1e-9 <= t < 2.5 - 1e-9]
    assert len(keep) == 200  # 2 s of 0.01 s output samples
    dy, dz = res.drogue_offset_m[keep, 1], res.drogue_offset_m[keep, 2]
    assert row["peak_dy_m"] == max(abs(v) for v in dy)
    # numpy sums pairwise, this loop sequentially: 200 terms differ by rounding only (~1e-14)
    assert row["rms_dz_m"] == pytest.approx(math.sqrt(sum(v * v for v in dz) / len(dz)), rel=1e-12)
    inside = sum(1 for a, b in zip(dy, dz) if math.hypot(a, b) <= 0.305)
    assert row["inside_0.305m_frac"] == inside / len(keep)


def test_controller_on_and_off_share_seeds(tiny_pid, tmp_path):
    out = tmp_path / "cmp"
    summary = run_campaign(tiny_pid, 3, out, scheduler="synchronous", compare_controller=True,
                           keep_timeseries=True, progress=False)
    runs = summary.runs
    assert list(runs["controller"]) == ["pid"] * 3 + ["none"] * 3
    on, off = runs[runs.controller == "pid"], runs[runs.controller == "none"]
    assert list(on["seed"]) == list(off["seed"])
    # the paper's PID holds the drogue far closer to its balance position than no control
    assert (on["peak_radial_m"].to_numpy() < off["peak_radial_m"].to_numpy()).all()
    assert (on["peak_u_n"] > 0).all() and (off["peak_u_n"] == 0).all()
    assert set(summary.statistics) == {"pid", "none"}
    series = sorted(p.name for p in (out / "runs").iterdir())
    assert series == [f"run_0000{i}_{c}.csv" for i in range(3) for c in ("none", "pid")]
    header = (out / "runs" / "run_00000_pid.csv").read_text().splitlines()[0]
    assert header.startswith("t_s,") and "u_y_n" in header
    assert (out / "histograms.png").exists() and (out / "cdf.png").exists()


# --- command line --------------------------------------------------------------------------------
def test_montecarlo_command(tiny, tmp_path, capsys):
    from hosedrogue import cli

    out = tmp_path / "mc"
    code = cli.main(["montecarlo", tiny, "--runs", "3", "--scheduler", "synchronous",
                     "--out", str(out), "--quiet", "--capture-radii", "0.2"])
    assert code == 0
    text = capsys.readouterr().out
    assert "100.0% of runs completed" in text and "wrote" in text
    assert re.search(r"capture radius \(mean over runs\): 0\.2 m \d+\.\d %", text)
    header = (out / "runs.csv").read_text().splitlines()[0]
    assert "inside_0.2m_frac" in header and "inside_0.1m_frac" not in header


def test_cli_main_runs_montecarlo(tiny, tmp_path):
    from hosedrogue import cli

    out = tmp_path / "mc"
    code = cli.main(["montecarlo", tiny, "--runs", "2", "--scheduler", "synchronous", "--out", str(out), "--quiet"])
    assert code == 0 and (out / "summary.json").exists()
    assert cli.main(["montecarlo", tiny, "--runs", "0", "--out", str(tmp_path / "bad")]) == 2
    assert not (tmp_path / "bad").exists()


def test_runs_csv_statistics_are_the_batch_module_s_columns(tiny):
    """A campaign row's statistics are the columns a real simulate_batch DataFrame has, in its
    order, and their values agree with the batch's for the same seed (both come from
    hosedrogue.results.statistics: the batch's compiled accumulator over every RK4 step, the campaign's pass
    over the saved series, here saved at every step too; 1e-12 relative covers the different
    summation orders)."""
    import dataclasses

    from hosedrogue.scenarios import load_scenario
    from hosedrogue.simulation import simulate_batch
    from hosedrogue.studies.campaign import RunTask, run_task, statistics_window

    radii = (0.1, 0.305)
    sc = load_scenario(tiny)
    sc = dataclasses.replace(sc, params=sc.params.replace(numerics={"output_every": 1}))
    df = simulate_batch(sc.params, [run_seed(0, 3)], sc.duration_s, capture_radii_m=radii)
    assert store.run_columns(radii)[3:-1] == [c for c in df.columns if c != "seed"]
    row = run_task(RunTask(sc, 3, run_seed(0, 3), "none", statistics_window(sc), radii))
    for column in ("peak_dy_m", "rms_radial_m", "inside_0.305m_frac"):
        assert row[column] == pytest.approx(df[column][0], rel=1e-12, abs=1e-15), column


def test_without_dask_the_default_runs_here_and_workers_are_refused(reference, tiny, tmp_path, monkeypatch):
    monkeypatch.setattr(executor, "dask_available", lambda: False)
    with pytest.raises(ParameterError, match="workers = 2: needs dask"):
        run_campaign(tiny, 8, tmp_path / "two", workers=2, progress=False)
    assert not (tmp_path / "two").exists()
    with pytest.warns(RuntimeWarning, match="in this process"):
        run_campaign(tiny, 8, tmp_path / "here", progress=False)
    assert_same_rows(tmp_path / "here", reference[0])


def test_a_campaign_without_its_figures_keeps_its_data_and_draws_them_later(reference, tiny, tmp_path):
    """plots=False (what the docking grid's cells use) writes the same data and no figure;
    summarizing the folder again draws the figures and writes the same summary.json (its
    verification block kept)."""
    from hosedrogue.studies.statistics import summarize_campaign

    ref, _ = reference
    out = tmp_path / "bare"
    run_campaign(tiny, 8, out, scheduler="synchronous", progress=False, plots=False)
    figures = ("histograms.png", "cdf.png")
    assert not any((out / name).exists() for name in figures)
    for name in ("runs.csv", "summary.json", "summary.csv"):
        assert (out / name).read_bytes() == (ref / name).read_bytes(), name
    summary = summarize_campaign(out)
    assert all((out / name).stat().st_size > 0 for name in figures)
    assert {p.name for p in summary.files} >= set(figures)
    assert (out / "summary.json").read_bytes() == (ref / "summary.json").read_bytes()
    assert "verification" in json.loads((out / "summary.json").read_text())
    with pytest.raises(ParameterError, match=r"^plots = 'no': must be True or False$"):
        run_campaign(tiny, 8, tmp_path / "bad", scheduler="synchronous", progress=False, plots="no")
    assert not (tmp_path / "bad").exists()
