"""One scenario, one run, one result for both hose models: the dispatch, the refusals of what a
model cannot honour, the shared result interface and the agreement of the two chains."""

import json
import math

import numpy as np
import pytest
import scipy.io

import hosedrogue as hd
from hosedrogue import cli
from hosedrogue.results.run import COLUMNS
from hosedrogue.scenarios import load_scenario, merge_tables, scenario_from_dict


def _main(capsys, *argv):
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_simulate_engagement_writes_a_mat_file_with_named_signals(tmp_path, capsys):
    """``simulate engage-response --format mat`` (it used to end in a traceback): the .mat file
    holds every time-series column as a named signal with its unit, at full precision."""
    out = tmp_path / "run"
    code, text, err = _main(capsys, "simulate", "engage-response", "--duration", "0.2", "--format", "mat",
                            "--out", str(out))
    assert code == 0, err
    mat = scipy.io.loadmat(out / "timeseries.mat", squeeze_me=True)
    names = list(mat["signal_names"])
    assert names[: len(COLUMNS)] == list(COLUMNS) and "hose_length_m" in names
    units = dict(zip(names, mat["signal_units"]))
    assert units["exit_tension_n"] == "N" and units["hose_length_m"] == "m" and units["drogue_vy_m_s"] == "m/s"
    csv = np.genfromtxt(out / "timeseries.csv", delimiter=",", names=True)
    # the CSV rounds to 10 significant digits; the .mat keeps the doubles
    assert np.allclose(mat["signals"]["drogue_z_m"].item(), csv["drogue_z_m"], rtol=1e-9, atol=0.0)


@pytest.mark.parametrize("tables, field", [
    ({"scenario": {"duration_s": 1.0}, "bow_wave": {"enabled": True}}, "bow_wave"),
    ({"scenario": {"duration_s": 1.0}, "pilot": {"enabled": False}}, "pilot"),
    ({"scenario": {"duration_s": 1e-9}, "reel": {"law": "locked"}}, "scenario.duration_s"),
    ({"scenario": {"duration_s": 1e-9}}, "scenario.duration_s"),
    ({"scenario": {"duration_s": 1.0}, "reel": {}, "numerics": {"integrator": "adaptive"}}, "numerics.integrator"),
])
def test_what_the_model_cannot_honour_is_refused_in_one_line(tmp_path, capsys, tables, field):
    """A [bow_wave] or [pilot] without the engagement (the fixed-length hose has no probe), a run
    shorter than one RK4 step of either model, the adaptive integrator in an engagement: one
    line naming the field, exit status 2, nothing written."""
    path = tmp_path / "case.toml"
    lines = []
    for name, table in tables.items():
        lines.append(f"[{name}]")
        lines += [f"{k} = {json.dumps(v)}" for k, v in table.items()]
    path.write_text("\n".join(lines) + "\n")
    out = tmp_path / "out"
    code, _, err = _main(capsys, "simulate", str(path), "--out", str(out))
    assert code == 2
    assert err.count("\n") == 1 and field in err and "Traceback" not in err
    assert not out.exists()


def test_locked_reel_engagement_is_the_fixed_length_run(tmp_path):
    """The same hose (converged preset, 20 links, moderate turbulence, seed 7, 3 s) run as a
    fixed-length scenario and as an engagement with the reel locked: the same columns first, the
    drogue within 1e-6 m and the tow force within 1e-3 N at every sample (the bounds of the
    issue that asked for one path). The two runs integrate the same equations by different
    sequences of the same kernels (the engagement adds a second articulated-body solve for L''
    and superposes it with L'' = 0), so they may differ by round-off growing through 3 s of
    turbulence: measured 5e-15 m and 1.4e-12 N."""
    fixed = scenario_from_dict({
        "scenario": {"name": "fixed", "duration_s": 3.0}, "model": {"preset": "converged"},
        "turbulence": {"enabled": True, "intensity": "moderate", "seed": 7},
    })
    locked = scenario_from_dict({**fixed.to_dict(), "reel": {"law": "locked"}})
    assert fixed.engagement is None and locked.engagement is not None
    a, b = hd.run(fixed), hd.run(locked)
    assert a.completed and b.completed
    ca, cb = a.columns(), b.columns()
    assert list(ca)[: len(COLUMNS)] == list(cb)[: len(COLUMNS)] == list(COLUMNS)
    np.testing.assert_array_equal(ca["t_s"], cb["t_s"])
    assert np.max(np.abs(a.drogue_position_m - b.drogue_position_m)) < 1e-6
    assert np.max(np.abs(a.tow_force_n - b.tow_force_n)) < 1e-3
    assert np.max(np.abs(a.exit_tension_n - b.exit_tension_n)) < 1e-3
    for path, result in (("a", a), ("b", b)):  # either result goes through the one writer
        hd.write(result, tmp_path / path, formats=("csv", "mat"))
        doc = json.loads((tmp_path / path / "run.json").read_text())
        assert doc["statistics"]["peak_radial_m"] == pytest.approx(result.statistics()["peak_radial_m"])


def test_extends_merges_tables_and_names_the_child(tmp_path):
    """A scenario that extends a shipped one is the parent with the child's keys: tables merged
    key by key, the name the child's file stem, a controller of another type replacing the
    parent's options; a loop of extends is one line."""
    child = tmp_path / "mine.toml"
    child.write_text('[scenario]\nextends = "approach-moderate"\n\n[turbulence]\nintensity = "severe"\n\n'
                     '[probe]\nclosure_speed_m_s = 1.5\n')
    sc, ref = load_scenario(str(child)), load_scenario("approach-severe")
    assert sc.name == "mine" and sc.params == ref.params
    assert sc.engagement.probe.closure_speed_m_s == 1.5 and sc.engagement.probe.standoff_m == 3.0
    assert sc.engagement.bow_wave == ref.engagement.bow_wave
    merged = merge_tables({"controller": {"type": "pid", "lateral": [1, 2, 3, 4]}}, {"controller": {"type": "lqr"}})
    assert merged == {"controller": {"type": "lqr"}}
    (tmp_path / "a.toml").write_text('[scenario]\nextends = "b.toml"\nduration_s = 1.0\n')
    (tmp_path / "b.toml").write_text('[scenario]\nextends = "a.toml"\n')
    with pytest.raises(hd.ParameterError, match="scenario.extends.*loop"):
        load_scenario(str(tmp_path / "a.toml"))


def test_turbulence_without_a_window_acts_for_the_whole_run():
    """Turbulence enabled with no start or duration is on for the whole run (a 60 s run has
    gusts at 59 s), and the paper's scenarios state their 10-30 s window."""
    p = hd.PAPER.replace(turbulence={"enabled": True, "intensity": "moderate"})
    assert p.turbulence.start_s == 0.0 and math.isinf(p.turbulence.duration_s)
    from hosedrogue.model.system import HoseModel

    model = HoseModel(p, duration_s=60.0)
    assert np.any(model.gusts.at(np.array([59.0])) != 0.0)
    assert model.gusts_cover(60.0) and not HoseModel(p).gusts_cover(60.0)
    with pytest.raises(hd.ParameterError, match="model: its gust record"):
        hd.simulate(p, 1.0, model=HoseModel(p))
    paper = load_scenario("paper-turbulence").params.turbulence
    assert (paper.start_s, paper.duration_s) == (10.0, 20.0)


def test_config_files_apply_in_order_and_may_name_a_preset(tmp_path, capsys):
    """``--config`` may name a preset inside the file and may be given several times; steady
    prints the exit tension."""
    mine = tmp_path / "mine.toml"
    mine.write_text('[model]\npreset = "converged"\n\n[flight]\nairspeed_m_s = 180.0\n')
    slow = tmp_path / "slow.toml"
    slow.write_text('[flight]\nairspeed_m_s = 120.0\n')
    code, out, _ = _main(capsys, "steady", "--config", str(mine), "--json")
    one = json.loads(out)
    code2, out2, _ = _main(capsys, "steady", "--config", "converged", "--config", str(slow), "--config", str(mine),
                           "--json")
    assert code == code2 == 0 and json.loads(out2) == one  # the last one wins, from the same preset
    from hosedrogue.spec.config import load_preset

    ref = hd.solve_equilibrium(load_preset("converged").replace(flight={"airspeed_m_s": 180.0}))
    assert one["drogue_position_m"] == ref.drogue_position_m.tolist()
    code, out, _ = _main(capsys, "steady")
    assert code == 0 and "exit tension [N]" in out
    bad = tmp_path / "bad.toml"
    bad.write_text('[model]\npreset = "nope"\n')
    code, _, err = _main(capsys, "steady", "--config", str(bad))
    assert code == 2 and "preset" in err and err.count("\n") == 1
