"""A campaign verifies a sample of its runs (studies/campaign_verify.py, montecarlo --verify-sample):
which runs (seeded, the same in every process, a larger sample keeps the smaller's), that the run
verified is the campaign's own (its figures equal its row of runs.csv), that the refined run is the
same case on twice the links at half the step (equal to that case written out by hand and run),
strict JSON, the CSV table, the summary's block, and bad input refused before anything is written."""

import json
import math

import pytest

from hosedrogue.errors import ParameterError
from hosedrogue.scenarios import load_scenario
from hosedrogue.scenarios.runner import run
from hosedrogue.studies.campaign import run_campaign
from hosedrogue.studies.campaign_verify import sampled_runs
from hosedrogue.studies.seeds import run_seed
from hosedrogue.studies.store import read_runs

#: 6 links, RK4 at 5 ms, output every step, 3 s with turbulence from 0.5 s for 2 s (~25 ms a run)
TINY = """\
[scenario]
name = "tiny-turbulence"
duration_s = 3.0

[turbulence]
enabled = true
start_s = 0.5
duration_s = 2.0
{seed}
[hose]
links = {links}

[numerics]
integrator = "rk4"
step_s = {step}
output_every = {every}
"""


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = tmp_path_factory.mktemp("scenarios") / "tiny.toml"
    path.write_text(TINY.format(seed="", links=6, step=0.005, every=1))
    return str(path)


def _strict(text: str):
    def refuse(name):
        raise ValueError(f"not strict JSON: {name}")

    return json.loads(text, parse_constant=refuse)


def test_the_sample_is_seeded_sorted_and_grows_by_keeping_its_runs():
    a, b = sampled_runs(1000, 4, 7), sampled_runs(1000, 8, 7)
    assert a == sampled_runs(1000, 4, 7) == sorted(a) and len(set(a)) == 4
    assert set(a) <= set(b) and all(0 <= i < 1000 for i in b)
    assert sampled_runs(1000, 4, 8) != a  # another campaign seed, another sample
    assert sampled_runs(3, 10, 7) == [0, 1, 2]  # more than the runs: all of them


def test_campaign_verifies_its_sampled_runs(tiny, tmp_path, capsys):
    from hosedrogue import cli

    out = tmp_path / "mc"
    code = cli.main(["montecarlo", tiny, "--runs", "4", "--seed", "5", "--scheduler", "synchronous",
                     "--out", str(out), "--quiet", "--verify-sample", "1", "--tolerance", "0.05"])
    assert code == 0
    assert "verified runs" in capsys.readouterr().out
    doc = _strict((out / "verification.json").read_text())
    index = sampled_runs(4, 1, 5)[0]
    assert doc["runs"] == [index] and doc["tolerance"] == 0.05 and doc["status"] == "verified"
    entry, = doc["verified_runs"]
    v = entry["verification"]
    assert entry["seed"] == run_seed(5, index) and v["run"]["links"] == 6 and v["refined"]["links"] == 12
    # the run verified is the campaign's: its figures are its row's (same seed, window, radii)
    row = next(r for r in read_runs(out / "runs.csv") if r["run"] == index)
    for name in ("peak_radial_m", "rms_dy_m", "inside_0.1m_frac"):
        assert v["figures"][f"statistics.{name}"]["value"] == row[name]
    # the refined run is this case on 12 links at 2.5 ms, output every 2 steps (the same 5 ms), written out
    fine_path = tmp_path / "fine.toml"
    fine_path.write_text(TINY.format(seed=f"seed = {run_seed(5, index)}\n", links=12, step=0.0025, every=2))
    fine = run(load_scenario(str(fine_path))).statistics()
    for name, f in v["figures"].items():
        assert f["refined_value"] == fine[name.removeprefix("statistics.")], name
        assert f["converged"] == (abs(f["refined_value"] - f["value"]) <= max(
            0.05 * max(abs(f["value"]), abs(f["refined_value"])), 1e-3 if name.endswith("_m") else 5e-3 if
            name.endswith("_frac") else 1.0))
    summary = _strict((out / "summary.json").read_text())["verification"]
    assert "verified_runs" not in summary and summary["runs"] == [index]
    assert set(summary["figures"]) == set(v["figures"])
    assert summary["converged"] == all(f["converged"] for f in v["figures"].values())
    lines = (out / "verification.csv").read_text().splitlines()
    assert lines[0].startswith("run,controller,seed,figure,value,refined_value") and len(lines) == 1 + len(v["figures"])
    # a later call without a sample keeps the verification in the summary (the runs are deterministic)
    run_campaign(tiny, 4, out, seed=5, scheduler="synchronous", progress=False)
    assert _strict((out / "summary.json").read_text())["verification"] == summary


def test_without_a_sample_the_summary_says_unverified(tiny, tmp_path):
    out = tmp_path / "mc"
    run_campaign(tiny, 2, out, scheduler="synchronous", progress=False)
    assert _strict((out / "summary.json").read_text())["verification"]["status"] == "unverified"
    assert not (out / "verification.json").exists()


@pytest.mark.parametrize("kwargs, field", [({"verify_sample": -1}, "verify_sample"),
                                           ({"verify_sample": 1.5}, "verify_sample"),
                                           ({"verify_sample": 1, "tolerance": 0.0}, "tolerance"),
                                           ({"verify_sample": 1, "tolerance": math.nan}, "tolerance")])
def test_bad_sample_or_tolerance_is_refused_before_any_output(tiny, tmp_path, kwargs, field):
    out = tmp_path / "mc"
    with pytest.raises(ParameterError, match=field):
        run_campaign(tiny, 2, out, scheduler="synchronous", progress=False, **kwargs)
    assert not out.exists()
