"""Closed loop on the nonlinear model in the paper's turbulence case (paper Sec. 3.3, Fig. 12)."""

import numpy as np
import pytest

from hosedrogue.scenarios.runner import run as run_scenario
from hosedrogue.scenarios import load_scenario


@pytest.fixture(scope="module")
def runs():
    return {name: run_scenario(load_scenario(name))
            for name in ("paper-turbulence", "paper-turbulence-pid", "paper-turbulence-lqr")}


def peaks(res):
    return np.max(np.abs(res.drogue_offset_m[:, 1:]), axis=0)


def test_open_loop_moves_like_the_paper(runs):
    """Paper: 0.5-1 m peak displacement without control. Asserted loosely (0.2-2 m per axis)
    since one seed of a random process is compared with one published record."""
    p = peaks(runs["paper-turbulence"])
    assert np.all((p > 0.2) & (p < 2.0)), p


def test_pid_cuts_peak_displacement_tenfold(runs):
    """The brief: stable and at least ten times smaller peak displacement, on each axis."""
    res = runs["paper-turbulence-pid"]
    assert res.completed
    ratio = peaks(runs["paper-turbulence"]) / peaks(res)
    assert np.all(ratio >= 10.0), ratio
    # settled again after the gusts stop at 30 s: the PID loop's slowest pole (-1.1 1/s) has
    # had 25 time constants, so the drogue is back within 1 mm by t = 55 s
    assert np.max(np.abs(res.drogue_offset_m[res.t_s > 55.0, 1:])) < 1e-3


def test_paper_lqr_cuts_peak_displacement_tenfold(runs):
    """The paper's LQR (balanced-state reading, Kalman observer, designed on this model's
    2nd-order channels): at least ten times smaller peak displacement on each axis (measured
    20x lateral, 12x vertical; the paper reports 0.5-1 m -> 0.5-1 cm)."""
    res = runs["paper-turbulence-lqr"]
    assert res.completed
    ratio = peaks(runs["paper-turbulence"]) / peaks(res)
    print(f"LQR: peaks {peaks(res)} m, ratio {ratio}, peak force {np.abs(res.control_force_n).max(axis=0)} N")
    assert np.all(ratio >= 10.0), ratio
    # settled again after the gusts stop at 30 s: the slowest regulator pole (-1.57 1/s) has had
    # 39 time constants by t = 55 s, so the drogue is back within 1 mm
    assert np.max(np.abs(res.drogue_offset_m[res.t_s > 55.0, 1:])) < 1e-3


def test_integral_lqr_with_paper_weights_is_slow(runs, tmp_path):
    """The integral-action reading (design = "integral"), the paper's Q and R in SI units, gives a
    slow loop (see docs/paper-differences.md): stable, it reduces the peak, but by far less than
    tenfold and less than the balanced-state reading. Asserted as measured (3.5x / 2.5x)."""
    from importlib import resources

    src = (resources.files("hosedrogue.scenarios") / "paper-turbulence-lqr.toml").read_text()
    (tmp_path / "int.toml").write_text(src.replace('design = "balanced"', 'design = "integral"'))
    sc = load_scenario(str(tmp_path / "int.toml"))
    assert sc.controller_options["design"] == "integral"
    res = run_scenario(sc)
    assert res.completed
    ratio = peaks(runs["paper-turbulence"]) / peaks(res)
    assert np.all((ratio > 1.0) & (ratio < 10.0)), ratio
    assert np.all(peaks(res) > peaks(runs["paper-turbulence-lqr"]))
    # the slow loop (slowest pole ~-0.2 1/s) has had ~5 time constants after the gusts stop:
    # the 0.23 m peak has decayed below 5 cm
    assert np.max(np.abs(res.drogue_offset_m[res.t_s > 55.0, 1:])) < 0.05


def test_actuator_limits_and_sensor_noise():
    """Magnitude and rate limits hold on the applied force (rate checked by finite differences
    of the saved force, 0.01 s apart, with 1 % slack for the difference quotient); sensor noise
    is reproducible for a seed and changes the response."""
    import dataclasses

    sc = load_scenario("paper-turbulence-pid").with_overrides(duration_s=16.0)
    from hosedrogue.spec.sections import Actuator, Sensor

    limited = dataclasses.replace(sc, loop=dataclasses.replace(sc.loop, actuator=Actuator(max_force_n=20.0,
                                                                                        max_rate_n_s=200.0)))
    res = run_scenario(limited)
    assert res.completed
    assert np.max(np.abs(res.control_force_n)) <= 20.0 + 1e-9
    rate = np.abs(np.diff(res.control_force_n, axis=0)) / np.diff(res.t_s)[:, None]
    assert rate.max() <= 200.0 * 1.01
    assert rate.max() > 100.0  # the limit is active, not vacuous
    noisy = dataclasses.replace(sc, loop=dataclasses.replace(sc.loop, sensor=Sensor(noise_std_m=0.002)))
    a, b = run_scenario(noisy), run_scenario(noisy)
    assert np.array_equal(a.control_force_n, b.control_force_n)
    assert not np.array_equal(a.control_force_n, run_scenario(sc).control_force_n)


def test_paper_lqr_with_actuator_limits_and_sensor_noise(runs):
    """The observer-based LQR with a 40 N / 500 N/s actuator and 2 mm sensor noise: stable, the
    force limit holds, and the peak displacement is still cut (measured 5.6 x / 4.9 x: the 40 N
    limit is below the unlimited loop's 55 / 67 N peaks, so the 20 x / 12 x of the unlimited
    loop cannot be kept; asserted > 3 x)."""
    import dataclasses

    sc = load_scenario("paper-turbulence-lqr")
    from hosedrogue.spec.sections import Actuator, Sensor

    loop = dataclasses.replace(sc.loop, actuator=Actuator(max_force_n=40.0, max_rate_n_s=500.0),
                               sensor=Sensor(noise_std_m=0.002))
    res = run_scenario(dataclasses.replace(sc, loop=loop))
    assert res.completed
    assert np.max(np.abs(res.control_force_n)) <= 40.0 + 1e-9
    assert np.all(peaks(runs["paper-turbulence"]) / peaks(res) > 3.0)


def test_controller_design_options_are_used(tmp_path):
    """User PID gains and LQR weights from the scenario replace the paper's: a 100 x heavier LQR
    state weight must hold the drogue closer than the paper's weights do."""
    # the paper scenarios' gust window (turbulence without a window would act for the whole run)
    base = "[scenario]\nduration_s = 40.0\n[turbulence]\nenabled = true\nstart_s = 10.0\nduration_s = 20.0\n"
    (tmp_path / "lqr.toml").write_text(base + '[controller]\ntype = "lqr"\nq_diag = [1.2e6, 8e5, 8e5, 1e6]\n')
    (tmp_path / "pid.toml").write_text(base + '[controller]\ntype = "pid"\nlateral = [2000.0, 500.0, 300.0, 50.0]\n')
    paper_lqr = run_scenario(load_scenario("paper-turbulence-lqr").with_overrides(duration_s=40.0))
    heavy = run_scenario(load_scenario(str(tmp_path / "lqr.toml")))
    assert np.all(peaks(heavy) < 0.5 * peaks(paper_lqr))
    soft = run_scenario(load_scenario(str(tmp_path / "pid.toml")))
    paper_pid = run_scenario(load_scenario("paper-turbulence-pid").with_overrides(duration_s=40.0))
    assert peaks(soft)[0] > 2 * peaks(paper_pid)[0]  # weaker lateral gains, larger lateral motion
    assert peaks(soft)[1] == pytest.approx(peaks(paper_pid)[1], rel=0.05)  # vertical: paper's gains
