"""Loop margins (hosedrogue.controllers.margins): an exact loop, python-control's
stability_margins on the same loops, and the delay margin confirmed by simulating the sampled
nonlinear loop on both sides of it."""

import math

import control
import numpy as np
import pytest

from hosedrogue.analysis.equilibrium import solve_equilibrium
from hosedrogue.analysis.linearize import linearize
from hosedrogue.controllers import margins as mg
from hosedrogue.controllers.design import paper_pid
from hosedrogue.simulation.simulate import simulate
from hosedrogue.spec.config import resolve_configs
from hosedrogue.spec.sections import Sensor

CONVERGED = resolve_configs(["converged"])


@pytest.fixture(scope="module")
def lm():
    return linearize(CONVERGED)


def test_integrator_loop_exact():
    # L = k / s: |L| = 1 at w = k, phase -90 deg: PM 90 deg, delay margin (pi / 2) / k, no phase
    # crossover. Tolerance 1e-9: Brent's method's xtol/rtol of 1e-12 on the crossing.
    k = 7.0
    m = mg.margins(control.tf2ss(control.tf([k], [1.0, 0.0])))
    assert m.crossover_rad_s == pytest.approx(k, rel=1e-9)
    assert m.phase_margin_deg == pytest.approx(90.0, rel=1e-9)
    assert m.delay_margin_s == pytest.approx(math.pi / 2 / k, rel=1e-9)
    assert m.gain_margin == math.inf


@pytest.mark.parametrize("sample_time_s, delay_s", [(0.0, 0.0), (0.01, 0.0), (0.005, 0.005)])
@pytest.mark.parametrize("channel", ["lateral", "vertical"])
def test_margins_agree_with_python_control(lm, channel, sample_time_s, delay_s):
    # python-control's stability_margins on the same loop's frequency response (an FRD on the same
    # grid: its polynomial method cannot hold a loop of order ~90). Both refine the same crossings
    # with Brent's method; tolerance 1e-7 covers the FRD's interpolation between grid points 0.5 %
    # apart, where the loop's phase and gain are smooth.
    loop = mg.channel_loop(lm, paper_pid(), channel, sample_time_s, delay_s)
    ours = mg.margins(loop)
    gm, pm, _, w_gm, w_pm, _ = control.stability_margins(control.FRD(loop, mg.frequency_grid(loop)))
    assert ours.phase_margin_deg == pytest.approx(pm, rel=1e-7)
    assert ours.crossover_rad_s == pytest.approx(w_pm, rel=1e-7)
    if math.isinf(gm):
        assert math.isinf(ours.gain_margin)
    else:
        assert ours.gain_margin == pytest.approx(gm, rel=1e-7)
        assert ours.gain_crossover_phase_rad_s == pytest.approx(w_gm, rel=1e-7)


def _growth(delay_samples: int, T: float, eq, params) -> np.ndarray:
    """Largest drogue offset over the last 2 s of 10 s over that in [0.5, 2.5] s, per axis, after a
    small kick (1e-3 rad/s on every link's rates) with the paper's PID sampled at T."""
    x0 = eq.state.copy()
    x0[2 * params.hose.links:] += 1e-3
    r = simulate(params, 10.0, x0=x0, control=paper_pid(), equilibrium=eq,
                 sensor=Sensor(delay_s=delay_samples * T), sample_time_s=T)
    assert r.completed
    y = np.abs(r.drogue_position_m[:, 1:] - eq.drogue_position_m[1:])
    early = y[(r.t_s > 0.5) & (r.t_s < 2.5)].max(axis=0)
    return y[r.t_s > 8.0].max(axis=0) / early


def test_delay_margin_is_the_edge_of_stability_in_simulation(lm):
    # The sampled loop (T = 2 ms, simulated at a 1 ms step) with the sensor delay a whole number of
    # samples just below and just above the smaller channel's delay margin (15.6 ms: 7 and 8
    # samples). Below: the kick decays (the linear loop's slowest decay 0.085 1/s over 8 s, and the
    # loop's modes far faster: ratio < 1). Above: the lateral loop's pole is outside the unit circle
    # (growth 0.54 1/s in the linear model: e^(0.54 x 7.5) = 57): ratio > 10.
    T = 0.002
    params = CONVERGED.replace(numerics={"step_s": 0.001})
    found = mg.loop_margins(lm, paper_pid(), T, 0.0)
    assert all(m.stable for m in found.values())
    edge = min(m.delay_margin_s for m in found.values()) / T
    below, above = math.floor(edge), math.ceil(edge)
    assert below >= 1 and above - edge > 0.1 and edge - below > 0.1  # not on a sample: a clear test
    eq = solve_equilibrium(params)
    assert np.all(_growth(below, T, eq, params) < 1.0)
    assert np.max(_growth(above, T, eq, params)) > 10.0
    # and the margins at the delay above the edge say the loop is unstable
    assert not mg.loop_margins(lm, paper_pid(), T, above * T)["lateral"].stable
