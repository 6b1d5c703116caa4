"""Linearization, reduction and closed loop on the nonlinear model (paper Sec. 3)."""

import numpy as np
import pytest

from hosedrogue.analysis.equilibrium import solve_equilibrium
from hosedrogue.analysis.linearize import linearize
from hosedrogue.analysis.reduction import balanced_truncation, hankel_singular_values, truncation_error_bound
from hosedrogue.controllers.design import reduced_channels
from hosedrogue.spec.params import PAPER
from hosedrogue.simulation import simulate


@pytest.fixture(scope="module")
def paper_linear():
    return linearize(PAPER)


@pytest.mark.parametrize("channel", [0, 1])
def test_linear_matches_nonlinear_small_step(paper_linear, channel):
    """A 1 N step on each input: the nonlinear and linear responses of the drogue agree within
    2 % of the linear response's peak over 5 s (the brief's bound). At 1 N the drogue moves a
    few millimetres, where the quadratic drag's nonlinearity contributes ~0.1 %."""
    import control

    lm = paper_linear
    eq = lm.equilibrium
    u = np.zeros(2)
    u[channel] = 1.0
    p = PAPER.replace(numerics={"step_s": 0.0025, "output_every": 4})
    res = simulate(p, 5.0, control=lambda t, x: u, equilibrium=eq)
    lin = control.forced_response(lm.ss, res.t_s, np.outer(u, np.ones_like(res.t_s)))
    y_lin = lin.outputs[channel]
    y_nl = res.drogue_offset_m[:, 1 + channel]
    assert np.max(np.abs(y_lin)) > 1e-3  # the step really moves the drogue (mm)
    assert np.max(np.abs(y_nl - y_lin)) < 0.02 * np.max(np.abs(y_lin))
    # the other channel barely moves: only the wake's asymmetry couples the channels (~4 % of
    # the direct response at this condition, see the report), so 5 % bounds it
    assert np.max(np.abs(res.drogue_offset_m[:, 2 - channel])) < 0.05 * np.max(np.abs(y_lin))


def test_linear_model_is_stable_and_lightly_damped(paper_linear):
    poles = paper_linear.poles
    assert poles.size == 4 * PAPER.hose.links
    assert np.all(poles.real < 0)
    # every mode of a towed hose is an oscillation (complex pair), none is overdamped
    assert np.all(np.abs(poles.imag) > 0)
    zeta = -poles.real / np.abs(poles)
    # Lightly damped: the paper's 2nd-order fits of the pendulum modes (Table 2) have zeta = 0.107
    # (lateral) and 0.106 (vertical); aerodynamic damping of a towed pendulum at this dynamic
    # pressure is of the order D / (2 m V omega) = 1230 N / (2 * 64 kg * 150 m/s * 1.5 rad/s)
    # = 0.04 for the drogue alone. No mode may be damped more than 0.15 (well above both).
    assert zeta.max() < 0.15
    # the slowest (pendulum) pair is the best damped of the chain's modes, as in a towed cable
    # whose higher modes see less drag per unit modal mass
    lowest = np.argmin(np.abs(poles))
    assert zeta[lowest] > 0.02 and zeta[lowest] >= np.quantile(zeta, 0.9)


@pytest.mark.parametrize("order", [6, 2])
def test_reduction_within_hankel_bound(paper_linear, order):
    """Balanced truncation theorem: ||G - G_r||_inf <= 2 * (sum of discarded Hankel singular
    values). Checked on a dense frequency grid 0.01-1000 rad/s covering every pole."""
    ch = reduced_channels(paper_linear, None)
    w = np.logspace(-2, 3, 4000)
    for full in (ch.lateral, ch.vertical):
        hsv = hankel_singular_values(full)
        assert np.all(np.diff(hsv) <= 1e-12 * hsv[0]) and hsv[-1] >= 0
        red = balanced_truncation(full, order)
        err = np.abs(full.frequency_response(w).complex.squeeze() - red.frequency_response(w).complex.squeeze())
        assert err.max() <= truncation_error_bound(hsv, order) * (1 + 1e-6)


def test_two_channels_decoupled_without_wake():
    """Free stream: the lateral input does not move the drogue vertically at all (mirror
    symmetry), so the linear cross-coupling is zero to round-off."""
    lm = linearize(PAPER.replace(wake={"enabled": False}))
    import control

    g = control.dcgain(lm.ss)
    assert abs(g[1, 0]) < 1e-9 * abs(g[0, 0]) and abs(g[0, 1]) < 1e-9 * abs(g[1, 1])


def test_reduced_channels_are_remembered_per_living_model_and_order(paper_linear):
    """The memo of reduced_channels: the same order gives the same object, a numpy integer order
    gives both channels as the int does (bit for bit), and a model's entry leaves with it."""
    import gc

    from hosedrogue.controllers import design

    two = reduced_channels(paper_linear, 2)
    assert reduced_channels(paper_linear, 2) is two
    numpy_two = reduced_channels(paper_linear, np.int64(2))
    for a, b in ((two.lateral, numpy_two.lateral), (two.vertical, numpy_two.vertical)):
        for m in "ABCD":
            assert np.array_equal(getattr(a, m), getattr(b, m))
    other = linearize(PAPER.replace(flight={"airspeed_m_s": 160.0}))
    reduced_channels(other, 2)
    assert id(other) in design._REDUCED
    key = id(other)
    del other
    gc.collect()
    assert key not in design._REDUCED
