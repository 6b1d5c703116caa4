"""Command line of the loop analysis: ``linearize --turbulence`` (covariance analysis) and
``margins``: their JSON, figure and one-line errors (the numbers are tested in tests/controllers)."""

import json

import pytest

from hosedrogue.cli import main


def run(capsys, *argv):
    try:
        code = main(list(argv))
    except SystemExit as exc:  # argparse's errors
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def test_linearize_predicts_rms_open_and_closed(capsys):
    code, out, err = run(capsys, "linearize", "--links", "8", "--turbulence", "moderate", "--controller", "pid",
                         "--sample-time", "0.005", "--sensor-delay", "0.005", "--json")
    assert code == 0, err
    d = json.loads(out)
    open_, closed = d["predicted_rms_m"], d["predicted_rms_closed_loop_m"]
    assert set(open_) == set(closed) == {"lateral", "vertical"}
    # the paper's PID cuts the open loop's RMS by two orders of magnitude (tests/controllers checks the values)
    assert all(0.0 < closed[k] < 0.05 * open_[k] for k in open_)
    assert d["turbulence"]["level"] == "moderate" and d["controller"]["sample_time_s"] == 0.005
    code, out, _ = run(capsys, "linearize", "--links", "8", "--turbulence", "light")
    assert code == 0 and "predicted RMS offset in light turbulence" in out


def test_margins_json_and_figure(capsys, tmp_path):
    fig = tmp_path / "loops.png"
    code, out, err = run(capsys, "margins", "--links", "8", "--json", "--out", str(fig))
    assert code == 0, err
    d = json.loads(out)
    for ch in ("lateral", "vertical"):
        assert d[ch]["stable"] and d[ch]["phase_margin_deg"] > 0 and d[ch]["delay_margin_s"] > 0
        assert d[ch]["gain_margin"] is None  # continuous PID: no phase crossover, infinite, written as null
    assert fig.stat().st_size > 10_000


@pytest.mark.parametrize("argv, names", [
    (["margins", "--sample-time", "0.01", "--sensor-delay", "0.015"], "sensor.delay_s"),
    (["margins", "--sensor-delay", "0.01"], "--sensor-delay"),
    (["margins", "--controller", "none"], "--controller"),
    (["margins", "--out", "loops.txt"], "--out"),
    (["margins", "--controller", "lqr", "--lateral-gains", "1", "1", "1", "1"], "--lateral-gains"),
    (["linearize", "--controller", "pid"], "--controller"),
    (["linearize", "--turbulence", "moderate", "--controller", "pid", "--sample-time", "0.01",
      "--sensor-delay", "0.05"], "unstable"),
    (["linearize", "--turbulence", "extreme"], "--turbulence"),
])
def test_bad_loop_options_one_line_exit_2(capsys, tmp_path, argv, names):
    argv = [a if a != "loops.txt" else str(tmp_path / a) for a in argv]
    code, out, err = run(capsys, *argv, "--links", "8")
    assert code == 2 and names in err and len(err.strip().splitlines()) == 1, err
    assert not list(tmp_path.iterdir())


def test_frozen_turbulence_config_is_refused(capsys, tmp_path):
    cfg = tmp_path / "frozen.toml"
    cfg.write_text('[turbulence]\nenabled = true\ndistribution = "frozen"\n')
    code, _, err = run(capsys, "linearize", "--links", "8", "--config", str(cfg))
    assert code == 2 and "turbulence.distribution" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("command", ["margins", "linearize"])
def test_loop_options_state_their_units(capsys, command):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for option, unit in (("--sample-time", "sample time [s]"), ("--sensor-delay", "delay [s]"),
                         ("--lateral-gains", "K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s]")):
        assert option in text and unit in text, (option, unit)
