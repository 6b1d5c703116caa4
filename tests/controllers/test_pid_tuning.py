"""PID tuned to step bounds (controllers/pid_tuning.py, ``hosedrogue design pid``): the bounds met on
the paper's plant and on others (the issue's 24 m hose at 230 m/s, the engineer's wing-pod hose),
checked by an independent evaluation of the step; the closest design written and marked when
nothing meets them; the pole placement; the MATLAB file; run.json's controller record."""

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
from hosedrogue.spec.paper import CHANNELS, TABLE3

#: Two evaluations of one step agree to this [-] in the times: the tuner's modal form with
#: root-found crossings, and control.step_response on Table 3's grid (step <= 0.1 / |p|_max, linear
#: interpolation between samples: measured 6e-5 to 1e-4 of the rise time on the paper's models).
SAME_STEP_TIME = 5e-4
#: ... and to this [percentage points] in the overshoot (the grid's peak sampling, measured 1.4e-5).
SAME_STEP_OVERSHOOT_PP = 1e-3


def _cli_json(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, (json.loads(out) if out.strip().startswith("{") else out), err


def _assert_within(d, targets=None):
    """Every design-model figure of ``design pid --json`` within its bound, read by Table 3's own step
    code (control.step_response on its grid) from the printed gains, within that code's
    interpolation error SAME_STEP_TIME (the tuner aims SEARCH_MARGIN = 2e-3 inside every bound)."""
    lat, ver = _plants(d)
    gains = {ch: PIDGains(d["controller"][ch]["kp_n_per_m"], d["controller"][ch]["ki_n_per_m_s"],
                          d["controller"][ch]["kd_n_s_per_m"], d["controller"][ch]["n_filter_rad_s"]) for ch in CHANNELS}
    steps = pid_steps(lat, ver, gains)
    for ch in CHANNELS:
        ref = (targets or {}).get(ch) or TABLE3[("PID", ch)]
        m = steps[ch].metrics
        assert d["controller"][ch]["met"] and d[ch]["rise_time_s"] <= ref["rise_time_s"], (ch, d[ch])
        assert m.rise_time_s <= ref["rise_time_s"] * (1.0 + SAME_STEP_TIME), (ch, m)
        assert m.settling_time_s <= ref["settling_time_s"] * (1.0 + SAME_STEP_TIME), (ch, m)
        assert m.overshoot_pct <= ref["overshoot_pct"] + SAME_STEP_OVERSHOOT_PP, (ch, m)
        for key in ("rise_time_s", "settling_time_s"):  # the table's figures are the exact step's
            assert d[ch][key] == pytest.approx(getattr(m, key), rel=SAME_STEP_TIME)


def _plants(d):
    """The design models printed by ``design pid --json`` (its Table 2 form), as transfer functions."""
    return tuple(control.tf(d["plant"][ch]["num"], d["plant"][ch]["den"]) for ch in CHANNELS)


def test_design_pid_meets_table3_on_the_papers_plant(capsys):
    """Table 3's figures as bounds on the paper's Table 2 models: met, checked by Table 3's own step
    code; the design is the least K_P + K_D N found, here 8 times less than Eq. 33's lateral one."""
    code, d, err = _cli_json(capsys, "design", "pid", "--plant", "paper", "--json")
    assert code == 0, err
    assert d["controller"]["source"] == "tuned" and d["controller"]["met"]
    _assert_within(d)
    g = PAPER_PID["lateral"]
    assert d["controller"]["lateral"]["high_frequency_gain_n_per_m"] < g.kp + g.kd * g.n_filter


def test_design_pid_24m_hose_at_230_m_s_writes_the_mat(capsys, tmp_path):
    """The issue's check: Table 3's targets on a 24 m hose at 230 m/s, 7600 m (the converged preset):
    exit 0 and a .mat whose channels are marked as meeting the bounds."""
    cfg = tmp_path / "hose24.toml"
    cfg.write_text("[hose]\nlength_m = 24.0\n")
    out = tmp_path / "pid.mat"
    code, d, err = _cli_json(capsys, "design", "pid", "--config", "converged", "--config", str(cfg), "--airspeed", "230",
                             "--altitude", "7600", "--json", "--format", "mat", "--out", str(out))
    assert code == 0, err
    assert d["plant"]["flight"]["hose_length_m"] == 24.0
    _assert_within(d)
    m = loadmat(out, squeeze_me=False)
    assert all(bool(m[ch][0, 0]["targets_met"].squeeze()) for ch in CHANNELS)


def test_design_pid_the_engineers_wing_pod_hose(capsys, tmp_path):
    """The issue's engineer: a 22.9 m hose of 3.6 kg/m at 128 m/s, 6100 m, rise at most 1 s, settling
    at most 2.5 s, overshoot at most 10 %: met."""
    cfg = tmp_path / "pod.toml"
    cfg.write_text("[hose]\nlength_m = 22.9\nmass_per_length_kg_m = 3.6\n")
    bounds = {"rise_time_s": 1.0, "settling_time_s": 2.5, "overshoot_pct": 10.0}
    code, d, err = _cli_json(capsys, "design", "pid", "--config", str(cfg), "--airspeed", "128", "--altitude", "6100",
                             "--rise-time", "1", "1", "--settling-time", "2.5", "2.5", "--overshoot", "10", "10", "--json")
    assert code == 0, err
    _assert_within(d, {ch: bounds for ch in CHANNELS})


def test_pole_placement_recovers_the_papers_gains():
    """The four closed-loop poles of the paper's PID loop give back its four gains (Eq. 33)."""
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


def test_modal_settling_sees_an_extremum_between_samples():
    """The cause of the issue's 'table 1.5446 s, message 0.7542 s': near the old tuner's lateral design
    for the 22.9 m hose (K_P 223.06), the response pokes out of the 2 % band for a moment near
    4.46 s, between two samples of the modal grid (the last sample outside it is at 3.74 s). The
    exact settling time agrees with control.step_response on a 1 ms grid (an independent evaluation)."""
    plant = control.tf([0.0008392, 0.0153], [1.0, 0.2361, 1.669])
    g = PIDGains(223.0, 207.29, 114.123, 99.8536)
    t = np.arange(0.0, 20.0, 1e-3)
    ref = closed_loop_step(plant, g.transfer_function(), t).metrics
    m = ModalStep(*plant_polynomials(plant), [g.kp, g.ki, g.kd, g.n_filter]).metrics()
    assert ref.settling_time_s > 4.0  # the late excursion exists
    assert m.settling_time_s == pytest.approx(ref.settling_time_s, rel=SAME_STEP_TIME)


def test_the_choice_meets_the_bounds_at_least_cost_among_its_neighbours():
    """The tuned design meets the bounds (independent step) and the same bits come twice; of 200
    designs around it (gains within +-20 %) none that meets the bounds on the exact step has a
    smaller K_P + K_D N by more than the search's tolerance (1 %, _DE_TOL)."""
    plant = channel_models("paper", 2)[1]
    target = paper_step_targets()["vertical"]
    tuning = tune_pid_to_step(plant, target)
    again = tune_pid_to_step(plant, target)
    assert tuning.gains == again.gains and tuning.met
    g = tuning.gains
    m = pid_steps(plant, plant, {"lateral": g, "vertical": g})["lateral"].metrics
    assert m.rise_time_s <= target.rise_time_s * (1 + SAME_STEP_TIME)
    assert m.settling_time_s <= target.settling_time_s * (1 + SAME_STEP_TIME)
    assert m.overshoot_pct <= target.overshoot_pct + SAME_STEP_OVERSHOOT_PP
    rng = np.random.default_rng(7)
    num, den = plant_polynomials(plant)
    base = np.array([g.kp, g.ki, g.kd, g.n_filter])
    for _ in range(200):
        x = base * np.exp(rng.uniform(-0.2, 0.2, 4))
        st = ModalStep(num, den, x)
        if not st.stable:
            continue
        mm = st.metrics()
        if (mm.rise_time_s <= target.rise_time_s and mm.settling_time_s <= target.settling_time_s
                and mm.overshoot_pct <= target.overshoot_pct):
            assert x[0] + x[2] * x[3] >= 0.99 * tuning.high_frequency_gain_n_per_m


def test_min_damping_is_honoured_or_the_closest_is_given():
    """With a damping floor every closed-loop pole of the design is damped at least that much; when
    nothing meets the bounds the closest design comes with what it misses."""
    plant = channel_models("paper", 2)[0]
    target = paper_step_targets()["lateral"]
    tuning = tune_pid_to_step(plant, target, min_damping=0.8)
    poles = control.feedback(tuning.gains.transfer_function() * plant, 1).poles()
    assert np.min(-poles.real / np.abs(poles)) >= 0.8 and tuning.met
    slow = control.tf([-1.0, 1.0], [1.0, 2.0, 1.0])  # a zero at +1 rad/s bounds any loop's bandwidth to ~1 rad/s
    with pytest.raises(TargetsNotMet) as exc:
        tune_pid_to_step(slow, StepTargets(0.1, 1.0, 5.0))
    closest = exc.value.closest
    assert not closest.met and closest.shortfalls() and closest.shortfalls()[0] in str(exc.value)


@pytest.mark.parametrize("args,field", [((0.0, 1.0, 4.0), "rise_time_s"), ((0.1, 0.1, 4.0), "settling_time_s"),
                                        ((0.1, 1.0, -1.0), "overshoot_pct"), ((0.1, 1.0, 100.0), "overshoot_pct"), ((0.1, 1.0, float("nan")), "overshoot_pct")])
def test_step_targets_validate(args, field):
    with pytest.raises(ValueError, match=field):
        StepTargets(*args)


def test_unmeetable_bounds_exit_3_the_closest_written_and_marked(capsys, tmp_path):
    """On this model's 6th-order reduction no PID meets Table 3's lateral bounds: exit 3, one line on
    stderr naming the channel and the figure missed with the same numbers as the JSON's table, and
    the closest design written, marked targets_met = false."""
    out = tmp_path / "pid.mat"
    code, d, err = _cli_json(capsys, "design", "pid", "--order", "6", "--json",
                             "--format", "mat", "--out", str(out))
    assert code == 3 and out.exists()
    assert len(err.strip().splitlines()) == 1 and "no design meets the bounds" in err and "lateral" in err
    assert d["controller"]["met"] is False and d["controller"]["lateral"]["met"] is False
    assert f"settling {d['lateral']['settling_time_s']:.4g} s" in err
    m = loadmat(out, squeeze_me=False)
    assert not bool(m["lateral"][0, 0]["targets_met"].squeeze())


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


def test_full_order_check_names_the_unstable_channel():
    """The CLI's full-order check: a loop that is unstable around the larger model is reported as
    such for its channel only, the other channel keeps its figures (no traceback)."""
    from hosedrogue.cli.design import _full_order

    design = channel_models("paper", 2)
    unstable = control.tf([-0.01], [1.0, 1.0, 1.0])  # the force's sign reversed: negative feedback becomes positive
    out = _full_order(dict(PAPER_PID), design, (unstable, channel_models("paper", 6)[1]))
    assert out["lateral"]["stable"] is False and "unstable" in out["lateral"]["message"]
    assert out["vertical"]["stable"] is True and out["vertical"]["rise_time_s"] > 0.0
