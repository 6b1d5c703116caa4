"""PID tuned to step targets (controllers/pid_tuning.py, ``hosedrogue design pid``): the targets met on
the paper's plant and on another plant, checked by an independent evaluation of the step; the
pole placement behind the one-parameter family; the MATLAB file; run.json's controller record."""

import json

import control
import numpy as np
import pytest
from scipy.io import loadmat

from hosedrogue.cli import main
from hosedrogue.controllers.design import paper_step_targets
from hosedrogue.controllers.pid import PAPER_PID, PIDGains, pid_controller
from hosedrogue.controllers.pid_loop import ModalStep, plant_polynomials
from hosedrogue.controllers.pid_tuning import StepTargets, TargetsNotMet, pid_for_poles, tune_pid_to_step
from hosedrogue.controllers.stepinfo import closed_loop_step
from hosedrogue.controllers.table3 import channel_models, pid_steps, time_grid_for
from hosedrogue.paper import CHANNELS, TABLE3

#: Two evaluations of one step agree to this [-] in the times: the tuner's modal form with
#: root-found crossings, and control.step_response on Table 3's grid (step <= 0.1 / |p|_max, linear
#: interpolation between samples: measured 6e-5 to 1e-4 of the rise time on the paper's models).
SAME_STEP_TIME = 5e-4
#: ... and to this [percentage points] in the overshoot (the grid's peak sampling, measured 1.4e-5).
SAME_STEP_OVERSHOOT_PP = 1e-3
#: The issue's check: rise and settling time within 10 %, overshoot at most 1 pp above Table 3's.
CHECK_TIME, CHECK_OVERSHOOT_PP = 0.10, 1.0

#: A different tanker and hose: 20 m of hose at 120 m/s and 6000 m (the paper: 16 m, 150 m/s, 8000 m).
OTHER_PLANT = ("--airspeed", "120", "--altitude", "6000")


def _cli_json(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, (json.loads(out) if out.strip().startswith("{") else out), err


def _assert_meets_table3(d):
    for ch in CHANNELS:
        ref = TABLE3[("PID", ch)]
        assert abs(d[ch]["rise_time_s"] / ref["rise_time_s"] - 1.0) <= CHECK_TIME, (ch, d[ch])
        assert abs(d[ch]["settling_time_s"] / ref["settling_time_s"] - 1.0) <= CHECK_TIME, (ch, d[ch])
        assert d[ch]["overshoot_pct"] <= ref["overshoot_pct"] + CHECK_OVERSHOOT_PP, (ch, d[ch])


def test_design_pid_meets_table3_on_the_papers_plant(capsys):
    """The issue's check on the paper's Table 2 models. The step figures printed come from
    Table 3's own step code (control.step_response on its grid), not from the tuner."""
    code, d, err = _cli_json(capsys, "design", "pid", "--plant", "paper", "--json")
    assert code == 0, err
    assert d["controller"]["source"] == "tuned" and d["controller"]["met"]
    _assert_meets_table3(d)
    for ch in CHANNELS:  # the tuner meets them to its MET, so the independent step agrees closely
        for key in ("rise_time_s", "settling_time_s"):
            assert d[ch][key] == pytest.approx(TABLE3[("PID", ch)][key], rel=SAME_STEP_TIME)
        assert d[ch]["overshoot_pct"] == pytest.approx(TABLE3[("PID", ch)]["overshoot_pct"], abs=SAME_STEP_OVERSHOOT_PP)
        assert d[ch]["full_order"]["stable"]  # closed around the paper's 6th-order models


def test_design_pid_meets_table3_on_another_plant(capsys, tmp_path):
    """The issue's check on another plant: a 20 m hose at 120 m/s, 6000 m. The paper's gains
    miss the targets there (overshoot far above Table 3's); the tuned gains meet them."""
    cfg = tmp_path / "hose20.toml"
    cfg.write_text("[hose]\nlength_m = 20.0\n")
    code, paper, err = _cli_json(capsys, "design", "pid", "--gains", "paper", "--config", str(cfg), *OTHER_PLANT, "--json")
    assert code == 0, err
    assert any(paper[ch]["overshoot_pct"] > TABLE3[("PID", ch)]["overshoot_pct"] + CHECK_OVERSHOOT_PP for ch in CHANNELS)
    code, d, err = _cli_json(capsys, "design", "pid", "--config", str(cfg), *OTHER_PLANT, "--json")
    assert code == 0, err
    assert d["plant"]["flight"]["hose_length_m"] == 20.0 and d["plant"]["flight"]["airspeed_m_s"] == 120.0
    _assert_meets_table3(d)


def test_pole_placement_recovers_the_papers_gains():
    """The four closed-loop poles of the paper's PID loop give back its four gains (Eq. 33): the
    linear solve behind 'three targets leave a one-parameter family'."""
    for ch in CHANNELS:
        plant = channel_models("paper", 2)[CHANNELS.index(ch)]
        g = PAPER_PID[ch]
        poles = control.feedback(g.transfer_function() * plant, 1).poles()
        back = pid_for_poles(plant, poles)
        for a, b in ((back.kp, g.kp), (back.ki, g.ki), (back.kd, g.kd), (back.n_filter, g.n_filter)):
            assert a == pytest.approx(b, rel=1e-8)  # root finding and back: rounding only


def test_modal_step_agrees_with_table3s_step():
    """The tuner's exact step (modal form, crossings by root finding) against control.step_response
    with Table 3's interpolated figures, for the paper's PID on its models."""
    for ch, plant in zip(CHANNELS, channel_models("paper", 2)):
        g = PAPER_PID[ch]
        ref = closed_loop_step(plant, g.transfer_function(),
                               time_grid_for(control.feedback(g.transfer_function() * plant, 1).poles())).metrics
        m = ModalStep(*plant_polynomials(plant), [g.kp, g.ki, g.kd, g.n_filter]).metrics()
        assert m.rise_time_s == pytest.approx(ref.rise_time_s, rel=SAME_STEP_TIME)
        assert m.settling_time_s == pytest.approx(ref.settling_time_s, rel=SAME_STEP_TIME)
        assert m.overshoot_pct == pytest.approx(ref.overshoot_pct, abs=SAME_STEP_OVERSHOOT_PP)


def test_the_family_meets_the_targets_and_the_choice_is_best_damped():
    """Every design the tuner reports as meeting the targets does (independent step), the chosen
    one is the best damped within the tie, and a second call gives the same bits."""
    plant = channel_models("paper", 2)[1]
    target = paper_step_targets()["vertical"]
    tuning = tune_pid_to_step(plant, target)
    again = tune_pid_to_step(plant, target)
    assert tuning.gains == again.gains
    fam = tuning.family
    assert fam.shape[0] > 10  # a curve, not a point
    rows = fam[np.linspace(0, fam.shape[0] - 1, 4).astype(int)]
    for row in rows:
        g = PIDGains(*row[:4])
        m = pid_steps(plant, plant, {"lateral": g, "vertical": g})["lateral"].metrics
        assert m.rise_time_s == pytest.approx(target.rise_time_s, rel=SAME_STEP_TIME)
        assert m.settling_time_s == pytest.approx(target.settling_time_s, rel=SAME_STEP_TIME)
        assert m.overshoot_pct == pytest.approx(target.overshoot_pct, abs=SAME_STEP_OVERSHOOT_PP)
    poles = control.feedback(tuning.gains.transfer_function() * plant, 1).poles()
    zeta = np.min(-poles.real / np.abs(poles))
    assert zeta == pytest.approx(tuning.min_damping, abs=1e-9)
    assert zeta >= fam[:, 4].max() - 0.01  # DAMPING_TIE


def test_min_damping_is_honoured_or_refused():
    """With a damping floor every closed-loop pole of the design is damped at least that much; a
    floor no design meeting the targets reaches is refused with the closest design attached."""
    plant = channel_models("paper", 2)[0]
    target = paper_step_targets()["lateral"]
    tuning = tune_pid_to_step(plant, target, min_damping=0.8)
    poles = control.feedback(tuning.gains.transfer_function() * plant, 1).poles()
    assert np.min(-poles.real / np.abs(poles)) >= 0.8
    with pytest.raises(TargetsNotMet) as exc:  # 50 % overshoot settled 2 ms after a 0.068 s rise
        tune_pid_to_step(plant, StepTargets(0.068, 0.07, 50.0))
    assert exc.value.closest.residual > 1e-6


@pytest.mark.parametrize("args,field", [((0.0, 1.0, 4.0), "rise_time_s"), ((0.1, 0.1, 4.0), "settling_time_s"),
                                        ((0.1, 1.0, 0.0), "overshoot_pct"), ((0.1, 1.0, float("nan")), "overshoot_pct")])
def test_step_targets_validate(args, field):
    with pytest.raises(ValueError, match=field):
        StepTargets(*args)


def test_unmeetable_targets_exit_3_nothing_written(capsys, tmp_path):
    out = tmp_path / "pid.mat"
    code, d, err = _cli_json(capsys, "design", "pid", "--plant", "paper", "--rise-time", "0.068", "0.076",
                             "--settling-time", "0.07", "1.31", "--overshoot", "50", "4.32", "--json",
                             "--format", "mat", "--out", str(out))
    assert code == 3 and not out.exists()
    assert len(err.strip().splitlines()) == 1 and "targets not met" in err and "lateral" in err
    assert d["controller"]["met"] is False and d["controller"]["lateral"]["met"] is False


def _cellstrs(a) -> list[str]:
    return [str(np.asarray(x).ravel()[0]) for x in np.asarray(a).ravel()]


def test_pid_mat_round_trip(capsys, tmp_path):
    """design pid --format mat: the gains with their names and units, and a realization A, B, C, D
    whose frequency response is -C(j w) of those gains (two independent forms of one controller)."""
    path = tmp_path / "sub" / "pid.mat"
    code, d, err = _cli_json(capsys, "design", "pid", "--plant", "paper", "--gains", "paper", "--json",
                             "--format", "mat", "--out", str(path))
    assert code == 0, err
    m = loadmat(path, squeeze_me=False)
    assert _cellstrs(m["gain_names"]) == ["K_P", "K_I", "K_D", "N"]
    assert _cellstrs(m["gain_units"]) == ["N/m", "N/(m s)", "N s/m", "rad/s"]
    assert _cellstrs(m["input_names"]) == ["P_ny_m", "P_nz_m"] and _cellstrs(m["input_units"]) == ["m", "m"]
    assert _cellstrs(m["output_names"]) == ["u_y_n", "u_z_n"] and _cellstrs(m["output_units"]) == ["N", "N"]
    assert len(_cellstrs(m["state_names"])) == m["A"].shape[0] == 4
    ss = control.ss(m["A"], m["B"], m["C"], m["D"])
    w = np.array([0.3, 3.0, 30.0, 300.0])
    for k, ch in enumerate(CHANNELS):
        s = m[ch][0, 0]
        g = PIDGains(float(s["K_P"].squeeze()), float(s["K_I"].squeeze()), float(s["K_D"].squeeze()),
                     float(s["N"].squeeze()))
        assert g == PAPER_PID[ch] and g.kp == d["controller"][ch]["kp_n_per_m"]
        resp = np.array([ss(1j * wk)[k, k] for wk in w])
        assert np.allclose(resp, -g.frequency_response(w), rtol=1e-12)
        assert float(s["rise_time_s"].squeeze()) == pytest.approx(d[ch]["rise_time_s"])


def test_lqr_mat_round_trip(capsys, tmp_path):
    """design lqr --format mat: K, prefilter and observer gain per channel, and the observer-based
    realization equal to A - B K - L C assembled from the file's own balanced models."""
    path = tmp_path / "lqr.mat"
    code, d, err = _cli_json(capsys, "design", "lqr", "--plant", "paper", "--json", "--format", "mat", "--out", str(path))
    assert code == 0, err
    m = loadmat(path, squeeze_me=False)
    assert str(m["design"][0]) == "balanced" and _cellstrs(m["output_names"]) == ["u_y_n", "u_z_n"]
    blocks = []
    for ch in CHANNELS:
        s = m[ch][0, 0]
        K, L = s["K"], s["L"]
        assert np.allclose(K.ravel(), d["controller"][ch]["gain_K"])
        assert float(s["prefilter"].squeeze()) == pytest.approx(d["controller"][ch]["prefilter_n_per_m"])
        blocks.append(s["A_balanced"] - s["B_balanced"] @ K - L @ s["C_balanced"])
    assert np.allclose(m["A"], np.block([[blocks[0], np.zeros((2, 2))], [np.zeros((2, 2)), blocks[1]]]), rtol=1e-12)


def test_run_json_records_the_controller(tmp_path):
    """A closed-loop run's run.json names its controller and gives its numbers: the PID gains as
    given in the scenario (the other channel the paper's), with a realization that is
    pid_controller's; for the LQR the regulator and observer gains of the designed controller."""
    gains = [5000.0, 4000.0, 1500.0, 60.0]
    sc = tmp_path / "pid.toml"
    sc.write_text(f'[scenario]\nduration_s = 0.1\n[controller]\ntype = "pid"\nlateral = {gains}\n')
    assert main(["simulate", str(sc), "--out", str(tmp_path / "o")]) == 0
    rec = json.loads((tmp_path / "o" / "run.json").read_text())["controller_design"]
    assert rec["type"] == "pid" and rec["source"] == "scenario"
    lat, ver = rec["lateral"], rec["vertical"]
    assert [lat["kp_n_per_m"], lat["ki_n_per_m_s"], lat["kd_n_s_per_m"], lat["n_filter_rad_s"]] == gains
    assert ver["kp_n_per_m"] == PAPER_PID["vertical"].kp and ver["source"] == "paper Eq. 33"
    ref = pid_controller(PIDGains(*gains), PAPER_PID["vertical"])
    assert np.array_equal(rec["realization"]["D"], ref.D) and np.array_equal(rec["realization"]["A"], ref.A)

    sc = tmp_path / "lqr.toml"
    sc.write_text('[scenario]\nduration_s = 0.1\n[controller]\ntype = "lqr"\n')
    assert main(["simulate", str(sc), "--out", str(tmp_path / "l")]) == 0
    rec = json.loads((tmp_path / "l" / "run.json").read_text())["controller_design"]
    from hosedrogue.analysis.linearize import linearize
    from hosedrogue.controllers.design import paper_lqr_design_for
    from hosedrogue.spec.params import PAPER

    design = paper_lqr_design_for(linearize(PAPER))
    assert rec["type"] == "lqr" and rec["design"] == "balanced"
    assert np.allclose(rec["gain_K"], design.gain, rtol=1e-9)
    assert np.allclose(rec["observer_gain_L"], design.observer_gain, rtol=1e-9)


def test_the_family_passes_through_the_papers_lateral_design():
    """From Table 3's printed lateral figures the tuner's family, read at the paper's N, gives back
    Eq. 33's lateral gains: within 2 %. Eq. 33's own step misses Table 3's printed rise time by
    0.4 % (0.0677 against 0.068 s: the paper prints two digits), and meeting the printed figure moves
    the gains at that N by 1.1 % (measured, K_I)."""
    tuning = tune_pid_to_step(channel_models("paper", 2)[0], paper_step_targets()["lateral"])
    fam = tuning.family
    assert np.all(np.diff(fam[:, 3]) > 0) or np.all(np.diff(fam[:, 3]) < 0)  # one branch, N monotone along it
    fam = fam[np.argsort(fam[:, 3])]
    g = PAPER_PID["lateral"]
    at = [np.exp(np.interp(np.log(g.n_filter), np.log(fam[:, 3]), np.log(fam[:, j]))) for j in range(3)]
    assert at == pytest.approx([g.kp, g.ki, g.kd], rel=0.02)


def test_full_order_check_names_the_unstable_channel():
    """The CLI's full-order check: a loop that is unstable around the larger model is reported as
    such for its channel only, the other channel keeps its figures (no traceback)."""
    from hosedrogue.cli.design import _full_order

    design = channel_models("paper", 2)
    unstable = control.tf([-0.01], [1.0, 1.0, 1.0])  # the force's sign reversed: negative feedback becomes positive
    out = _full_order(dict(PAPER_PID), design, (unstable, channel_models("paper", 6)[1]))
    assert out["lateral"]["stable"] is False and "unstable" in out["lateral"]["message"]
    assert out["vertical"]["stable"] is True and out["vertical"]["rise_time_s"] > 0.0
