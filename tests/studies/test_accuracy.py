"""Link-count convergence of the two mass lumpings against the continuum limit (issue 11).

The continuum (``analysis/continuum.py``) is the towed-cable boundary-value problem solved to
1e-9 m; it shares no code with the link model but the wake function. Study case: the paper's
flight condition, wake on, bending off (the continuum neglects bending).
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from hosedrogue.analysis.continuum import solve_continuum
from hosedrogue.analysis.equilibrium import solve_equilibrium
from hosedrogue.spec.params import PAPER
from hosedrogue.studies.accuracy import (
    STUDY_BASE,
    difference_orders,
    frequency_convergence,
    lumping_convergence,
    observed_orders,
    richardson,
)

#: Observed order asked of a second-order scheme: 2 minus a margin for the higher-order terms
#: still visible at 10-40 links (measured: 2.00 for the position, 1.99-2.00 for the frequencies).
MIN_SECOND_ORDER = 1.8


@pytest.fixture(scope="module")
def continuum():
    return solve_continuum(STUDY_BASE)


@pytest.fixture(scope="module")
def split_study(continuum):
    return lumping_convergence("split", links=(10, 20, 40, 80), continuum=continuum, dynamics=False)


def test_continuum_reproduces_tow_point_and_load_balance(continuum):
    """The shooting hits the tow point to 1e-9 m (its stated tolerance), and the tow force is the
    drogue's load plus the hose's loads: checked on the vertical, where the hose's drag is small,
    as the whole weight mu L g plus the drogue's weight and the z-drag terms integrated along the
    returned shape (trapezoid on 201 points: 1e-3 N is ~1e-6 of the tow force)."""
    assert continuum.position_error_m < 1e-9
    assert np.allclose(continuum.position_m[0], 0.0, atol=1e-9)
    seg = np.linalg.norm(np.diff(continuum.position_m, axis=0), axis=1)
    # inextensible: the shape's polygon length is the hose length to the chord error of 200
    # chords of a gently curved line (curvature ~0.05 /m, chord 0.08 m: ~1e-6 relative)
    assert seg.sum() == pytest.approx(PAPER.hose.length_m, rel=1e-5)


@pytest.mark.parametrize("wake", [True, False])
def test_continuum_matches_richardson_limit_of_split_links(wake):
    """The continuum drogue agrees with the Richardson limit (order 2) of the ``split`` link
    model at 40 and 80 links to 0.1 mm (the brief's bound; measured 4e-11 m with the wake)."""
    base = STUDY_BASE.replace(wake={"enabled": wake}, hose={"mass_lumping": "split"})
    cont = solve_continuum(base)
    r40 = solve_equilibrium(base.replace(hose={"links": 40})).drogue_position_m
    r80 = solve_equilibrium(base.replace(hose={"links": 80})).drogue_position_m
    assert np.linalg.norm(richardson(r40, r80, 2.0) - cont.drogue_position_m) < 1e-4


def test_split_lumping_is_second_order(split_study):
    """``split``: the drogue within 1 mm of the continuum at 10 links and 0.3 mm at 20 (the
    brief's bounds; measured 0.45 and 0.11 mm), observed order >= 1.8 (measured 2.00)."""
    err = split_study.position_error_m
    assert err[0] < 1e-3
    assert err[1] < 0.3e-3
    assert np.all(split_study.position_orders >= MIN_SECOND_ORDER)


def test_aft_lumping_is_first_order(continuum):
    """The paper's ``aft`` lumping converges at first order (orders within 0.9-1.1: measured
    0.98-1.00) and is ~7 cm off at 20 links (measured 74 mm), so the paper's case is untouched."""
    st = lumping_convergence("aft", links=(10, 20, 40), continuum=continuum, dynamics=False)
    assert np.all(np.abs(st.position_orders - 1.0) < 0.1)
    assert 0.05 < st.position_error_m[1] < 0.1


def test_split_frequencies_converge_at_second_order():
    """Lowest lateral and vertical frequencies with ``split`` lumping and rod link inertia
    (measured order 2.00 for both at 10-20-40 links)."""
    fs = frequency_convergence(STUDY_BASE.replace(hose={"mass_lumping": "split"}), links=(10, 20, 40))
    assert fs.lateral_orders[0] >= MIN_SECOND_ORDER
    assert fs.vertical_orders[0] >= MIN_SECOND_ORDER


def _converged_preset():
    """The shipped ``converged`` preset (``hosedrogue/spec/presets/converged.toml``, added by another
    change) as Params, or None while it is missing."""
    from importlib.resources import files

    from hosedrogue.spec.config import load_params

    path = files("hosedrogue").joinpath("spec", "presets", "converged.toml")
    assert path.is_file(), "the 'converged' preset must be shipped (hosedrogue/spec/presets/converged.toml)"
    return load_params(str(path))


def test_converged_preset_frequencies_converge_at_second_order():
    """The ``converged`` preset's lowest lateral and vertical frequencies converge at order
    >= 1.8 (links 10-20-40 around its own count); the preset must be shipped."""
    base = _converged_preset()
    fs = frequency_convergence(base, links=(10, 20, 40))
    assert fs.lateral_orders[0] >= MIN_SECOND_ORDER
    assert fs.vertical_orders[0] >= MIN_SECOND_ORDER


def test_order_helpers():
    """Exact arithmetic on made-up sequences: e = 1/n^2 gives order 2 (to round-off)."""
    n = np.array([5, 10, 20, 40])
    assert np.allclose(observed_orders(1.0 / n**2), 2.0, atol=1e-12)
    assert np.allclose(difference_orders(3.0 + 1.0 / n), 1.0, atol=1e-12)
    assert richardson(3.0 + 1.0 / 10**2, 3.0 + 1.0 / 20**2, 2.0) == pytest.approx(3.0, abs=1e-15)


@pytest.mark.subprocess
def test_cli_steady_continuum_json():
    """``hosedrogue steady --continuum --json`` prints the continuum's drogue and tow force."""
    out = subprocess.run([sys.executable, "-m", "hosedrogue", "steady", "--continuum", "--json"],
                         capture_output=True, text=True, check=True).stdout
    d = json.loads(out)
    assert d["model"] == "continuum" and d["solver_success"]
    x, y, z = d["drogue_position_m"]
    assert x < 0 and z > 0 and len(d["tow_force_n"]) == 3


def test_paper_turbulence_scenario_matches_the_papers_reading():
    """The shipped ``paper-turbulence`` scenario (smoothed cubic gust reading, RK4 at 0.02 s)
    follows the drogue path of the paper's reading (linear, hard window) at a converged step
    (0.00125 s) within 0.1 mm over the 60 s run (the stated error of the new step; measured
    0.067 mm: 0.025 mm step error plus 0.066 mm from the 0.02 s averaging)."""
    from hosedrogue.scenarios import load_scenario
    from hosedrogue.simulation import simulate

    p_new = load_scenario("paper-turbulence").params
    p_old = p_new.replace(turbulence={"interpolation": "linear", "smoothing_s": 0.0},
                          numerics={"step_s": 0.00125, "output_every": 32})
    eq = solve_equilibrium(p_new)
    new = simulate(p_new, 60.0, equilibrium=eq)
    old = simulate(p_old, 60.0, equilibrium=eq)
    assert new.completed and old.completed
    np.testing.assert_allclose(new.t_s, old.t_s, rtol=0, atol=1e-9)
    assert np.abs(new.drogue_position_m - old.drogue_position_m).max() < 1e-4
