"""The whip-load study and what explains a load that does not converge (docs/engagement.md, "Whip loads"
and "Link-count convergence")."""

import json
import math

import numpy as np
import pytest

from hosedrogue.cli import main
from hosedrogue.results.convergence import flailing, went_slack
from hosedrogue.model.elastic_loop import elastic_run
from hosedrogue.model.layout import SCHEME_RK4
from hosedrogue.model.integrate import loop_arrays
from hosedrogue.controllers.linear import LinearController
from hosedrogue.model.system import HoseModel
from hosedrogue.model import layout as LY
from hosedrogue.spec.params import PAPER, Actuator
from hosedrogue.studies.whip_loads import axial_damping_n_s, first_axial_mode_rad_s, study_scenario

T = np.linspace(0.0, 10.0, 1001)


def test_slack_and_flail_are_read_from_the_histories():
    """What explains a peak that does not converge: a snap (exit tension below 10 % of the trail
    tension) and a flailing loop (slack above 0.1 m over the last second), on synthetic histories."""
    taut = np.full(T.size, 1500.0)
    snap = taut.copy()
    snap[300:320] = 50.0
    tight, loose = np.full(T.size, 0.01), np.full(T.size, 1.5)
    assert not went_slack(taut) and went_slack(snap) and flailing(T, loose) and not flailing(T, tight)


def test_first_axial_mode_is_the_chains():
    """The first axial frequency of the trailed hose as a bar fixed at the exit with the drogue's
    mass at its end (beta tan beta = mu L / m_d; 33.8 rad/s at 1e6 N), against the elastic chain's
    own: a straight 40-link chain, air, gravity and damping off, released from a uniform stretch of
    1e-4, its drogue's oscillation counted over 1 s (RK4 at 20 us). Bound 0.5 %: the split lumping's
    second-order error at 40 links (l / L = 1/40: ~(pi l / 2 L)^2 / 6 = 2.6e-4) plus the higher
    modes' share of the uniform start."""
    EA, n = 1e6, 40
    p = PAPER.replace(hose={"links": n, "link_inertia": "rod", "bending": "off", "mass_lumping": "split",
                            "axial_stiffness_n": EA}, flight={"density_scale": 0.0})
    omega = first_axial_mode_rad_s(p)
    assert omega == pytest.approx(33.78, abs=0.01)
    model = HoseModel(p)
    model.ps[LY.PS_G] = 0.0
    x0 = np.zeros(6 * n)
    x0[4 * n: 5 * n] = model.l * (1.0 + 1e-4)
    h, steps = 2e-5, 50000
    loop = loop_arrays(LinearController.static_zero(), np.zeros(2), Actuator(), np.zeros((1, 2)), 1.0)
    N = steps // 10 + 1
    ts, zs, us = np.empty(N), np.empty((N, 6 * n)), np.empty((N, 2))
    outs = (np.empty((N, n + 1, 3)), np.empty((N, 3)), np.empty((N, 3)), np.empty((N, 3)), np.empty(N))
    status, saved, _ = elastic_run(x0, h, steps, 10, SCHEME_RK4, 2, model.l, model.M, model.J, model.ps,
                                   model.env, model.gust_values, *loop, math.radians(85.0), ts, zs, us, *outs)
    assert status == LY.OK
    x = -outs[0][:saved, -1, 0]  # the drogue's distance aft of the exit
    d = x - np.mean(x)
    crossings = ts[:saved][1:][(d[:-1] < 0) & (d[1:] >= 0)]
    measured = 2 * math.pi / np.mean(np.diff(crossings))
    assert abs(measured / omega - 1.0) < 5e-3, (measured, omega)


def test_study_scenario_keeps_the_loss_factor():
    """A grid point: EA and the damping 0.1 EA / omega_1 (2960 N s at 1e6 N, rounded to the shipped
    3000; 9360 N s at 1e7 N), the closure speed, the latch window opened to 0.3 m/s, and a run
    lasting until 5 s after the probe stops."""
    sc = study_scenario("engage-response", 1e7, 0.5)
    assert sc.params.hose.axial_stiffness_n == 1e7
    assert sc.params.hose.axial_damping_n_s == pytest.approx(9360, rel=1e-3)
    assert axial_damping_n_s(sc.params, 1e6) == pytest.approx(2960, rel=1e-3)
    probe = sc.engagement.probe
    assert probe.closure_speed_m_s == 0.5 and probe.min_closure_speed_m_s == 0.3
    assert sc.duration_s == pytest.approx((3.0 + 2.0) / 0.5 + probe.stop_time_s + 5.0)


def test_cli_whip_loads_json(capsys):
    """``hosedrogue study whip-loads`` on one coarse point prints its row as JSON: captured, the
    five peaks, their flags ("unverified": no run is verified without --verify)."""
    code = main(["study", "whip-loads", "--stiffness", "1e6", "--closure-speeds", "2.5", "--scenarios",
                 "engage-constant-tension", "--links", "40", "--step", "0.0025", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    (row,) = out["rows"]
    assert row["result"] == "captured" and row["links"] == 40 and row["stiffness_n"] == 1e6
    assert row["peak_exit_tension_n"] > row["peak_tension_rise_n"] > 0
    assert all(v == "unverified" for k, v in row.items() if k.startswith("converged_"))


def test_cli_whip_loads_bad_input(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["study", "whip-loads", "--stiffness", "-5"])
    assert exc.value.code == 2
    assert "--stiffness" in capsys.readouterr().err


def test_cli_whip_loads_runs_the_users_file(tmp_path, capsys):
    """A user's engagement scenario runs in the grid beside a shipped one: the row names the file's
    scenario, and its hose, twice as heavy (8.8 kg/m), raises the trail tension (the peak exit
    tension less its rise) by more than nothing and less than the added weight, 16 m x 4.4 kg/m x g =
    690 N (the weight adds to the vertical component of the tow point's tension; the drag, its
    horizontal component, changes only with the hose's shape)."""
    mine = tmp_path / "wing-pod.toml"
    mine.write_text('[scenario]\nextends = "engage-constant-tension"\nname = "wing-pod"\n'
                    '[hose]\nmass_per_length_kg_m = 8.8\n')
    code = main(["study", "whip-loads", "--stiffness", "1e6", "--closure-speeds", "2.5", "--scenarios",
                 "engage-constant-tension", str(mine), "--links", "40", "--step", "0.0025", "--json"])
    assert code == 0
    shipped, user = json.loads(capsys.readouterr().out)["rows"]
    assert (shipped["scenario"], user["scenario"]) == ("engage-constant-tension", "wing-pod")
    trail = [r["peak_exit_tension_n"] - r["peak_tension_rise_n"] for r in (shipped, user)]
    added_weight_n = 16.0 * 4.4 * 9.80665
    assert 0.0 < trail[1] - trail[0] < added_weight_n


@pytest.mark.parametrize("name, says", [("swing-release", "'swing-release' is a fixed-length scenario"),
                                        ("no-such.toml", "no such file or shipped scenario")])
def test_cli_whip_loads_refuses_what_is_not_an_engagement(name, says, capsys):
    """A fixed-length scenario or a missing file: one line, exit 2, before any run."""
    assert main(["study", "whip-loads", "--scenarios", "engage-response", name]) == 2
    err = capsys.readouterr().err
    assert says in err and len(err.strip().splitlines()) == 1


def test_cli_whip_loads_verifies_and_reports_the_locked_reel_as_a_distribution(capsys):
    """``--verify 1 --ensemble 3`` on one locked-reel point (40 links): the row's flags are
    measured (True or False, none "unverified") and each peak has its median and 5-95 % points
    over the perturbed copies, in order."""
    code = main(["study", "whip-loads", "--stiffness", "1e6", "--closure-speeds", "2.5", "--scenarios",
                 "engage-locked", "--links", "40", "--step", "0.0025", "--verify", "1", "--ensemble", "3", "--json"])
    (row,) = json.loads(capsys.readouterr().out)["rows"]
    assert code == 0
    assert all(isinstance(v, bool) for k, v in row.items() if k.startswith("converged_"))
    for key in ("peak_exit_tension_n", "peak_probe_load_n", "peak_slack_m"):
        assert row[f"{key}_p05"] <= row[f"{key}_median"] <= row[f"{key}_p95"], key
