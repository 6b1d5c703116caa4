"""``hosedrogue design pid --rms-target``: a PID tuned to a predicted RMS offset in standard
turbulence (hosedrogue.controllers.rms_tuning; its comparison with the nonlinear model is in
tests/controllers/test_rms_tuning.py and benchmarks/covariance_rms.py)."""

import json

import pytest
from scipy.io import loadmat

from hosedrogue.cli import main
from hosedrogue.controllers.rms_tuning import MET_RTOL

FLIGHT = ["--altitude", "6100", "--airspeed", "128"]


def _design(capsys, *args):
    code = main(["design", "pid", *FLIGHT, *args, "--json"])
    return code, json.loads(capsys.readouterr().out)["controller"]


def test_a_tighter_target_needs_a_faster_loop_and_each_target_is_met(capsys):
    """The family's RMS falls as its crossover rises, so the least crossover meeting 0.05 m lies
    above the one meeting 0.1 m; each design's predicted RMS is its target within Brent's
    tolerance (the least crossover sits on the target, not below it)."""
    crossovers = {}
    for target in (0.1, 0.05):
        code, ctrl = _design(capsys, "--rms-target", str(target), str(target))
        assert code == 0 and ctrl["met"] and ctrl["turbulence"] == "moderate"
        for ch in ("lateral", "vertical"):
            assert ctrl[ch]["predicted_rms_m"] == pytest.approx(target, rel=10 * MET_RTOL)
        crossovers[target] = [ctrl[ch]["crossover_rad_s"] for ch in ("lateral", "vertical")]
    assert all(fast > slow for fast, slow in zip(crossovers[0.05], crossovers[0.1]))


def test_a_target_no_design_meets_writes_the_closest_marked_exit_3(tmp_path, capsys):
    out = tmp_path / "pid.mat"
    code = main(["design", "pid", *FLIGHT, "--rms-target", "1e-6", "1e-6", "--format", "mat", "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 3 and "predicted RMS" in captured.err and len(captured.err.strip().splitlines()) == 1
    mat = loadmat(out, simplify_cells=True)
    assert mat["lateral"]["targets_met"] in (0, False) and mat["vertical"]["targets_met"] in (0, False)


@pytest.mark.parametrize("args, says", [
    (["--rms-target", "0.1", "0.1", "--overshoot", "5", "5"], "not to step bounds; leave out --overshoot"),
    (["--sample-time", "0.01"], "--sample-time = 0.01: applies with --rms-target only"),
    (["--rms-target", "0.1", "0.1", "--sensor-delay", "0.01"], "give --sample-time"),
])
def test_bad_rms_options_are_one_line_exit_2(args, says, capsys):
    assert main(["design", "pid", *FLIGHT, *args]) == 2
    assert says in capsys.readouterr().err
