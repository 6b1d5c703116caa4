"""Issue 15: long runs. The paper's midpoint drag leaves the chain's zigzag modes almost undamped
and turbulence feeds them until a link's yaw reaches the coordinate limit. The two-point Gauss
drag and the hose's structural damping (the ``converged`` preset) damp them; these tests check
the damping on the linearization, hour-long runs in turbulence, energy accounting of the
damping moments, and how presets are named (docs/long-runs.md)."""

import math

import numpy as np
import pytest
import scipy.integrate

from hosedrogue.analysis.linearize import linearize
from hosedrogue.simulation import simulate_batch
from hosedrogue.spec.config import load_preset, preset_names, resolve_config
from hosedrogue.controllers.pid import PAPER_PID, pid_controller
from hosedrogue.model.system import HoseModel
from hosedrogue.spec.params import PAPER, ParameterError
from hosedrogue.scenarios.runner import run as run_scenario
from hosedrogue.scenarios import load_scenario
from hosedrogue.simulation import simulate

from test_dynamics import _dummy_equilibrium, swinging_start

HOUR_S = 3600.0


def least_damped(params):
    """Damping ratio and natural frequency [rad/s] of the least damped oscillatory mode."""
    poles = linearize(params).poles
    poles = poles[poles.imag > 0]
    zeta = -poles.real / np.abs(poles)
    i = int(np.argmin(zeta))
    return zeta[i], abs(poles[i])


def test_quadrature_drag_and_damping_damp_every_mode():
    """The issue's acceptance: the least damped mode of the stable model is damped at least 100
    times more than the paper's (whose ~4e-5 at 19 rad/s is what turbulence feeds). Both are
    eigenvalues of the same finite-difference linearization, whose relative error (~1e-9,
    analysis/linearize.py) is far below the factor of 100 asked for."""
    zeta_paper, w_paper = least_damped(PAPER)
    assert zeta_paper < 1e-4 and 15.0 < w_paper < 25.0  # the zigzag mode, 19.2 rad/s
    zeta_conv, _ = least_damped(load_preset("converged"))
    assert zeta_conv >= 100.0 * zeta_paper, (zeta_conv, zeta_paper)


def test_defaults_are_the_paper_model():
    """The reproduction keeps the paper's drag and no structural damping."""
    assert PAPER.hose.drag_quadrature == "midpoint"
    assert PAPER.hose.bending_damping_n_m2_s == 0.0


#: Length of the suite's long-run checks [s]: longer than the paper's model lasts in severe
#: turbulence at 8000 m (it blew up at 128-232 s, docs/long-runs.md), far shorter than the hour
#: the report's long-runs section runs (``hosedrogue reproduce``).
SHORT_S = 120.0


def test_long_turbulence_severe_scenario_runs():
    """`long-turbulence-severe` is an hour of severe turbulence (5.9 m/s at 8000 m) on the converged
    model from 10 s to the end; its first two minutes complete (the hour is the report's)."""
    sc = load_scenario("long-turbulence-severe")
    assert sc.params.hose == load_preset("converged").hose
    assert sc.duration_s == HOUR_S
    t = sc.params.turbulence
    assert t.enabled and t.start_s == 10.0 and t.start_s + t.duration_s >= sc.duration_s
    assert t.sigma_m_s[0] == pytest.approx(5.944)
    res = run_scenario(sc.with_overrides(duration_s=SHORT_S))
    assert res.completed, res.message
    assert res.t_s[-1] == pytest.approx(SHORT_S)


@pytest.mark.parametrize("intensity", ["light", "moderate", "severe"])
@pytest.mark.parametrize("controller", ["none", "pid"])
def test_converged_model_runs_in_lasting_turbulence(intensity, controller):
    """Two-minute runs of the converged model in light, moderate and severe turbulence (on from
    10 s), two seeds each, open loop and with the paper's PID, all complete (the hour-long runs
    are the report's long-runs section)."""
    p = load_preset("converged").replace(
        turbulence={"enabled": True, "intensity": intensity, "start_s": 10.0})
    ctrl = pid_controller(PAPER_PID["lateral"], PAPER_PID["vertical"]) if controller == "pid" else None
    df = simulate_batch(p, [2018, 2019], SHORT_S, controller=ctrl)
    assert df["completed"].all(), df[["seed", "completed", "t_end_s"]]
    assert np.allclose(df["t_end_s"], SHORT_S)


def perpendicular_omega(x, n):
    """Each link's angular velocity perpendicular to its axis [rad/s] (n, 3), from docs/model.md's
    omega_k = [s1 thd2, thd1, c1 thd2] minus its part along e_k (the frames' twist)."""
    q, qd = x[: 2 * n], x[2 * n:]
    th1, th2, d1, d2 = q[0::2], q[1::2], qd[0::2], qd[1::2]
    c1, s1, c2, s2 = np.cos(th1), np.sin(th1), np.cos(th2), np.sin(th2)
    e = np.stack([-c1 * c2, -s2, s1 * c2], axis=1)
    w = np.stack([s1 * d2, d1, c1 * d2], axis=1)
    return w - np.sum(w * e, axis=1)[:, None] * e


@pytest.mark.parametrize("bending", ["off", "moment"])
def test_energy_lost_equals_damping_work(bending, rng):
    """No air, damping on: T + V falls by exactly the work of the damping moments,
    int sum_k (c_b / lbar) |w_k+1 - w_k|^2 dt (w computed here from docs/model.md's formulas, not the
    kernel's e x de/dt). RK4 at 1e-3 s conserves energy to ~1e-10 of the kinetic energy
    (test_dynamics), and Simpson's rule on the same 1e-3 s samples integrates the smooth power
    to ~1e-12 relative, so 1e-9 of the initial kinetic energy is integrator accuracy with margin
    (measured: 2e-11); the dissipated work is ~20 % of it, so a wrong factor, sign or projection
    of the damping moments fails by orders of magnitude."""
    n, step, c_b = 4, 1e-3, 50.0
    p = PAPER.replace(hose={"links": n, "bending": bending, "bending_damping_n_m2_s": c_b},
                      flight={"density_scale": 0.0}, numerics={"step_s": step, "output_every": 1})
    m = HoseModel(p)
    x0 = swinging_start(n, rng)
    res = simulate(p, 4.0, x0=x0, model=m, equilibrium=_dummy_equilibrium(m, x0))
    assert res.completed, res.message
    energy = np.array([sum(m.energy(x)) for x in res.states])
    lbar = p.hose.length_m / n
    power = np.array([c_b / lbar * np.sum(np.diff(perpendicular_omega(x, n), axis=0) ** 2)
                      for x in res.states])
    work = np.concatenate([[0.0], scipy.integrate.cumulative_simpson(power, x=res.t_s)])
    kinetic0 = m.energy(x0)[0]
    assert work[-1] > 0.1 * kinetic0
    assert np.max(np.abs(energy - energy[0] + work)) < 1e-9 * kinetic0


def test_damping_off_conserves_energy_without_air(rng):
    """With c_b = 0 the Gauss drag and damping code paths add nothing without air."""
    n = 3
    p = PAPER.replace(hose={"links": n, "bending": "moment", "drag_quadrature": "gauss2"},
                      flight={"density_scale": 0.0})
    m = HoseModel(p)
    x0 = swinging_start(n, rng)
    ref = HoseModel(p.replace(hose={"drag_quadrature": "midpoint"}))
    np.testing.assert_array_equal(m.derivative(0.0, x0), ref.derivative(0.0, x0))


def test_gauss_drag_equals_midpoint_for_a_translating_link():
    """A link moving without turning, in uniform air, has the same relative velocity all along,
    so both quadratures give the same loads (to round-off, 1e-12 of the accelerations)."""
    n = 3
    p = PAPER.replace(hose={"links": n}, wake={"enabled": False})
    q = np.tile([0.1, 0.05], n)
    qd = np.zeros(2 * n)
    a = HoseModel(p).accelerations(q, qd)
    b = HoseModel(p.replace(hose={"drag_quadrature": "gauss2"})).accelerations(q, qd)
    np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * np.abs(a).max())


def test_presets_by_name_and_file(tmp_path):
    assert "converged" in preset_names()
    conv = load_preset("converged")
    h = conv.hose
    assert (h.link_inertia, h.bending, h.drag_quadrature) == ("rod", "moment", "gauss2")
    assert h.bending_damping_n_m2_s > 0
    assert resolve_config("converged") == conv
    f = tmp_path / "over.toml"
    f.write_text("[flight]\nairspeed_m_s = 200.0\n")
    assert resolve_config(str(f)).flight.airspeed_m_s == 200.0
    with pytest.raises(ParameterError, match=r"presets: converged") as exc:
        resolve_config("convergd")
    assert "\n" not in str(exc.value)
    with pytest.raises(ParameterError, match=r"allowed: converged"):
        load_preset("convergd")


def test_scenario_preset_overridden_by_its_sections(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text('[scenario]\nduration_s = 5.0\n[model]\npreset = "converged"\n[hose]\nbending = "paper"\n')
    sc = load_scenario(str(f))
    assert sc.params.hose.bending == "paper"  # the scenario's section wins
    assert sc.params.hose.drag_quadrature == "gauss2"  # the rest comes from the preset
    f.write_text('[scenario]\nduration_s = 5.0\n[model]\npreset = "nope"\n')
    with pytest.raises(ParameterError, match=r"model.preset = 'nope'"):
        load_scenario(str(f))
    f.write_text('[scenario]\nduration_s = 5.0\n[model]\nlinks = 3\n')
    with pytest.raises(ParameterError, match=r"model.links: unknown field"):
        load_scenario(str(f))


def test_shipped_long_scenarios_use_the_preset():
    """Every shipped scenario longer than the paper's 60 s window runs the converged model."""
    from hosedrogue.scenarios import shipped_scenarios

    conv = load_preset("converged").hose
    long = [load_scenario(name) for name in shipped_scenarios()]
    long = [sc for sc in long if sc.duration_s > 60.0]
    assert long
    for sc in long:
        assert sc.params.hose == conv, sc.name


def test_yaw_limit_message_names_the_remedy():
    """A run stopped at the coordinate limit says why it probably happened and what to use."""
    p = PAPER.replace(numerics={"max_yaw_deg": 1.0})
    n = p.hose.links
    m = HoseModel(p)
    x0 = np.zeros(4 * n)
    x0[0 : 2 * n : 2] = 0.3
    x0[1 : 2 * n : 2] = math.radians(0.5)
    x0[2 * n + 1 :: 2] = 1.0  # yaw rates carry the links past 1 deg at once
    res = simulate(p, 1.0, x0=x0, model=m, equilibrium=_dummy_equilibrium(m, x0))
    assert not res.completed
    assert "converged" in res.message and "\n" not in res.message


def test_long_runs_study_and_figure():
    """The study's data and figure on a short cap (the full study runs for minutes)."""
    from matplotlib.figure import Figure

    from hosedrogue.studies.long_runs_figures import plot_long_runs
    from hosedrogue.studies.long_runs import LongRunStudy, long_runs_study

    st = long_runs_study(intensities=("light", "severe"), seeds=(2018,), cap_s=20.0, hour_duration_s=20.0)
    assert isinstance(st, LongRunStudy)
    assert list(st.blowup["intensity"]) == ["light", "severe"]
    assert st.blowup["sigma_m_s"].is_monotonic_increasing
    assert list(st.modes["option"]) == ["paper", "+gauss2 drag", "+structural damping", "rod inertia", "converged"]
    assert st.damping_gain >= 100.0
    assert st.hour.completed and st.hour.t_s[-1] == pytest.approx(20.0)
    fig = plot_long_runs(st)
    assert isinstance(fig, Figure)
    for ax in fig.axes:
        assert "[" in ax.get_xlabel() and "[" in ax.get_ylabel()
    with pytest.raises(ParameterError, match="cap_s"):
        long_runs_study(cap_s=5.0)


def test_gauss_drag_sees_the_wake_at_its_points():
    """At rest in the tanker wake (which varies in y and z), the change of the generalized forces
    from midpoint to Gauss drag equals sum over drag points of F(P) . dr_P/dq, with the air
    velocity at each point from the wake function and dr_P/dq by central differences of the
    point's position (no joint split involved). Gravity, bending and drogue cancel in the
    difference. The difference is ~8 N m here (5.3 m links crossing the wake); the central
    difference's error (step 1e-6 rad) is ~1e-9 of the ~1e3 N m generalized forces (measured
    2e-7 N m), so 1e-6 N m resolves the difference to 1e-7 of itself."""
    from hosedrogue.environment.wake import wake_velocity
    from hosedrogue.model import layout as LY

    n = 3
    p = PAPER.replace(hose={"links": n}, wake={"vertical_offset_m": 0.5})
    mid, gauss = HoseModel(p), HoseModel(p.replace(hose={"drag_quadrature": "gauss2"}))
    wk = mid.steady_env[LY.ENV_WAKE:LY.ENV_WAKE + 6]
    V, rho, l = p.flight.airspeed_m_s, mid.rho, p.hose.length_m / n
    d, ct, cn = p.hose.outer_diameter_m, p.hose.tangential_drag_coefficient, p.hose.normal_drag_coefficient
    q = np.array([0.35, 0.1, 0.25, -0.15, 0.4, 0.05])

    def point(qq, k, s):
        joints = mid.joint_positions(qq)
        return (1 - s) * joints[k] + s * joints[k + 1]

    def drag(qq, k, s, length):
        r = point(qq, k, s)
        wy, wz = wake_velocity(r[1], r[2], wk)
        vrel = -np.array([-V, wy, wz])  # the link is at rest
        e = mid.joint_positions(qq)[k + 1] - mid.joint_positions(qq)[k]
        e /= np.linalg.norm(e)
        vt = vrel @ -e
        vn = vrel - vt * -e
        return (-0.5 * rho * vt * abs(vt) * np.pi * d * length * ct * -e
                - 0.5 * rho * np.linalg.norm(vn) * vn * np.pi * d * length * cn)

    def generalized(points):
        Q = np.zeros(2 * n)
        for k, s, length in points:
            F = drag(q, k, s, length)
            for j in range(2 * n):
                dq = np.zeros(2 * n)
                dq[j] = 1e-6
                Q[j] += F @ (point(q + dq, k, s) - point(q - dq, k, s)) / 2e-6
        return Q

    g = 0.5 / math.sqrt(3.0)
    expected = (generalized([(k, s, l / 2) for k in range(n) for s in (0.5 - g, 0.5 + g)])
                - generalized([(k, 0.5, l) for k in range(n)]))
    got = gauss.static_residual(q) - mid.static_residual(q)
    assert np.abs(expected).max() > 1.0  # the wake's variation along a link is visible
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-6)
