"""The paper's LQR read as a regulator of the balanced states (controllers.lqr_balanced).

Recorded when this file was written (python-control 0.10.2, slycot), on the paper's Table 2
2nd-order models with the paper's Q and R, rise / settling / overshoot:
    lateral  0.8356 s / 1.4847 s / 0 %   (paper 0.839 / 1.49 / 2.24)
    vertical 0.6165 s / 1.0486 s / 0 %   (paper 0.671 / 1.45 / 5.07)
Regulator poles -11.82, -2.690 (lateral) and -6.692, -4.442 rad/s (vertical); observer poles
-90.6, -17.0 and -79.7, -18.1 rad/s; prefilters 2066.2 and 2064.4 N/m.
"""

from __future__ import annotations

import itertools

import control
import numpy as np
import pytest

from hosedrogue.analysis.reduction import hankel_singular_values
from hosedrogue.controllers import step_metrics
from hosedrogue.controllers.lqr import PAPER_LQR_Q, PAPER_LQR_R
from hosedrogue.controllers.lqr_balanced import (
    balanced_realization,
    lqr_balanced_design,
    lqr_balanced_reference_loop,
)
from hosedrogue.spec.paper import CHANNELS, TABLE3, table2_transfer_function

# Step grid: 0.1 ms over 10 s. The fastest regulator pole is -11.8 rad/s (85 ms), the slowest
# -2.69 rad/s: 10 s is 27 of its time constants; interpolated crossings are accurate to ~1e-6 s.
T = np.linspace(0.0, 10.0, 100_001)

# The brief's tolerance for the lateral LQR row: 3 %. The paper prints 3 significant digits
# (0.839 s is +/-0.06 %) and does not state its simulation settings.
TABLE3_LQR_RTOL = 0.03


@pytest.fixture(scope="module")
def paper_design():
    return lqr_balanced_design(table2_transfer_function("lateral", 2), table2_transfer_function("vertical", 2))


def _steps(design, plant=None):
    loop = lqr_balanced_reference_loop(design, plant)
    out = {}
    for k, ch in enumerate(CHANNELS):
        resp = control.step_response(loop, T, input=k, squeeze=False)
        out[ch] = (resp.outputs[k, 0], resp.outputs[2 + k, 0], resp.outputs[1 - k, 0])
    return out


def test_balanced_realization_gramians_and_transfer_function():
    for ch in CHANNELS:
        g = table2_transfer_function(ch, 2)
        bal, T_, hsv = balanced_realization(g)
        wc, wo = control.gram(bal, "c"), control.gram(bal, "o")
        # Both Gramians equal diag(hsv); 1e-9 relative to sigma_1: round-off of the Lyapunov
        # solves and the square-root transformation on a 2-state system.
        np.testing.assert_allclose(wc, np.diag(hsv), atol=1e-9 * hsv[0])
        np.testing.assert_allclose(wo, np.diag(hsv), atol=1e-9 * hsv[0])
        # Same HSVs as the reduction module's independent computation (SB03OD factors).
        np.testing.assert_allclose(hsv, hankel_singular_values(g), rtol=1e-9)
        # Same input-output map; 1e-9 relative: a similarity transform, round-off only.
        w = np.logspace(-2, 3, 50)
        np.testing.assert_allclose(bal(1j * w), g(1j * w), rtol=1e-9)
        assert np.all(bal.B >= 0.0)  # the sign convention


@pytest.mark.parametrize("channel", CHANNELS)
def test_paper_lqr_on_paper_plant_against_table3(paper_design, channel):
    y, u, other = _steps(paper_design)[channel]
    m = step_metrics(T, y, final_value=1.0)
    ref = TABLE3[("LQR", channel)]
    print(f"LQR (balanced) {channel}: rise {m.rise_time_s:.4f} s, settling {m.settling_time_s:.4f} s, "
          f"overshoot {m.overshoot_pct:.2f} %, peak force {np.abs(u).max():.0f} N per m (paper {ref})")
    # Unit DC gain from the prefilter: settled on the reference (2 % band passed by 1.5 s, and
    # the slowest pole has had 27 time constants by 10 s).
    assert abs(y[-1] - 1.0) < 1e-6
    assert np.abs(other).max() < 1e-9  # channels decoupled (round-off)
    if channel == "lateral":
        assert abs(m.rise_time_s - ref["rise_time_s"]) / ref["rise_time_s"] < TABLE3_LQR_RTOL
        assert abs(m.settling_time_s - ref["settling_time_s"]) / ref["settling_time_s"] < TABLE3_LQR_RTOL
    else:
        # Not reproduced (docs/paper-differences.md): the paper has 0.671 s / 1.45 s / 5.07 %.
        # Recorded values, 1 ms: well above the grid's interpolation error, below any change
        # of the design.
        assert m.rise_time_s == pytest.approx(0.6165, abs=1e-3)
        assert m.settling_time_s == pytest.approx(1.0486, abs=1e-3)
    # Real closed-loop poles and a far zero: no overshoot (the paper's 2.24 / 5.07 % are not
    # reproduced by this reading).
    assert m.overshoot_pct < 0.01


def test_paper_lqr_poles_and_separation(paper_design):
    d = paper_design
    # Recorded design (module docstring); 1e-3 relative: round-off is far smaller, the figure
    # guards against a change of the weights' reading.
    np.testing.assert_allclose(np.sort(d.lateral.regulator_poles.real), [-11.819, -2.6905], rtol=1e-3)
    np.testing.assert_allclose(np.sort(d.vertical.regulator_poles.real), [-6.6925, -4.4418], rtol=1e-3)
    # Documented design property: every observer pole faster than every regulator pole.
    assert d.observer_poles.real.max() < d.regulator_poles.real.min()
    # Regulation loop with the LinearController: poles = regulator and observer poles
    # (separation principle); 1e-6 relative for eigenvalues of a non-normal 8x8 matrix.
    loop = np.sort_complex(d.controller.closed_loop(d.plant).poles())
    np.testing.assert_allclose(loop, np.sort_complex(np.concatenate([d.regulator_poles, d.observer_poles])),
                               rtol=1e-6)
    # The reference step through the observer equals full state feedback: r does not excite the
    # estimation error. 1e-9: round-off of two discretizations.
    K, N = d.gain, d.prefilter
    sf = control.ss(d.plant.A - d.plant.B @ K, d.plant.B @ N, d.plant.C, 0)
    y_sf = control.step_response(sf, T[:20_001], input=0, squeeze=False).outputs[0, 0]
    y_obs = control.step_response(lqr_balanced_reference_loop(d), T[:20_001], input=0, squeeze=False).outputs[0, 0]
    np.testing.assert_allclose(y_obs, y_sf, atol=1e-9)


def test_gain_does_not_depend_on_balanced_state_signs(paper_design):
    """Flip the sign of balanced states (S = diag(+-1)): the gain in the original coordinates,
    the prefilter, the poles and the controller's y -> u map must not change."""
    base = paper_design
    w = np.logspace(-2, 3, 60)
    ref_frd = base.controller.as_statespace()(1j * w)
    for s_lat, s_ver in itertools.product(itertools.product((1, -1), repeat=2), repeat=2):
        d = lqr_balanced_design(table2_transfer_function("lateral", 2), table2_transfer_function("vertical", 2),
                                signs=(s_lat, s_ver))
        # The balanced gain itself flips with the states ...
        np.testing.assert_allclose(d.lateral.gain, base.lateral.gain * np.array(s_lat), rtol=1e-9)
        # ... the law does not. 1e-9 relative: round-off of two Riccati solutions.
        for ch in ("lateral", "vertical"):
            a, b = getattr(d, ch), getattr(base, ch)
            np.testing.assert_allclose(a.gain_original, b.gain_original, rtol=1e-9)
            assert a.prefilter == pytest.approx(b.prefilter, rel=1e-9)
            np.testing.assert_allclose(np.sort_complex(a.observer_poles), np.sort_complex(b.observer_poles), rtol=1e-9)
        # Frequency responses of two 4-state realizations of one controller: 1e-8 relative
        # (round-off of the Riccati solutions, amplified by evaluating (jwI - A)^-1); atol
        # 1e-12 N/m for the exactly-zero cross-channel entries.
        np.testing.assert_allclose(d.controller.as_statespace()(1j * w), ref_frd, rtol=1e-8, atol=1e-12)


def test_design_on_a_non_balanced_realization_is_the_same(paper_design):
    """Any realization of the same channel (here the transfer function's companion form scaled
    by an arbitrary similarity) gives the same controller y -> u."""
    g = control.tf2ss(table2_transfer_function("lateral", 2))
    S = np.array([[3.0, 1.0], [-0.5, 2.0]])
    g2 = control.ss(S @ g.A @ np.linalg.inv(S), S @ g.B, g.C @ np.linalg.inv(S), 0)
    d = lqr_balanced_design(g2, table2_transfer_function("vertical", 2))
    w = np.logspace(-2, 3, 60)
    # same tolerances as the sign test: round-off of two Riccati solutions
    np.testing.assert_allclose(d.controller.as_statespace()(1j * w),
                               paper_design.controller.as_statespace()(1j * w), rtol=1e-8, atol=1e-12)


def test_rejects_bad_weights_and_plants():
    lat, ver = table2_transfer_function("lateral", 2), table2_transfer_function("vertical", 2)
    Q = np.array(PAPER_LQR_Q)
    Q[0, 1] = Q[1, 0] = 10.0
    with pytest.raises(ValueError, match="diagonal"):
        lqr_balanced_design(lat, ver, Q, PAPER_LQR_R)
    with pytest.raises(ValueError, match="Q must have shape"):
        lqr_balanced_design(lat, ver, np.eye(3), PAPER_LQR_R)
    with pytest.raises(ValueError, match="r must be"):
        lqr_balanced_design(lat, ver, PAPER_LQR_Q, np.diag([0.4, 0.0]))
    with pytest.raises(ValueError, match="stable"):
        balanced_realization(control.tf([1.0], [1.0, -1.0]))


def test_table3_rows_paper_plant():
    """The library's Table 3 on the paper's plant: PID within the 6 % of test_controllers, the
    balanced LQR's lateral row within 3 %, the integral LQR as the documented slow sensitivity
    (rise > 5 s, recorded 6.66 / 10.31 s)."""
    from hosedrogue.controllers.table3 import table3_rows

    rows = {(r["controller"], r["channel"]): r for r in table3_rows()}
    assert {r[0] for r in rows} == {"PID", "LQR", "LQR-integral"}
    for ch in CHANNELS:
        pid = rows[("PID", ch)]
        for key in ("rise_time_s", "settling_time_s", "overshoot_pct"):
            assert abs(pid[key] - pid[f"paper_{key}"]) / pid[f"paper_{key}"] < 0.06
        assert rows[("LQR-integral", ch)]["rise_time_s"] > 5.0
    lat = rows[("LQR", "lateral")]
    for key in ("rise_time_s", "settling_time_s"):
        assert abs(lat[key] - lat[f"paper_{key}"]) / lat[f"paper_{key}"] < TABLE3_LQR_RTOL


def test_lqr_step_on_paper_6th_order_model():
    """The balanced LQR designed on the paper's 2nd-order models, closed around its 6th-order
    ones through the observer (Fig. 11 for the LQR): stable, a DC gain within 5 % of 1 (the
    prefilter is exact for the design model only; recorded 1.020 / 1.044), settled within 3 s."""
    from hosedrogue.controllers.table3 import step_responses

    steps = step_responses("LQR", "paper", evaluate_on=6)
    for ch in CHANNELS:
        m = steps[ch].metrics
        print(f"LQR on paper 6th {ch}: {m}")
        assert abs(m.final_value - 1.0) < 0.05
        assert m.settling_time_s < 3.0
