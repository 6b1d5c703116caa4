"""The elastic balance position by chord iterations on the rigid solve's Jacobian (issue 32: no
finite-difference Jacobian of the 3n elastic unknowns) against MINPACK's hybrid Newton with a
central-difference Jacobian, the former method, kept as the fallback."""

import numpy as np

from hosedrogue.analysis import equilibrium as EQ
from hosedrogue.constants import G0
from hosedrogue.engagement.chain import chain_model, initial_chain
from hosedrogue.scenarios import load_scenario
from hosedrogue.studies.convergence import with_links


def test_chord_and_minpack_find_the_same_balance_position():
    """The responsive reel's hose on 40 links (EA 1e6 N, wake and bending on): the chord's angles
    and lengths equal those of MINPACK's Newton started from the same stretched rigid shape to
    1e-12 rad and 1e-12 m (both solve the residual to 1e-10 of the weight moment, which moves the
    drogue by far less than a micrometre; measured 4e-16 rad, 6e-17 m), in fewer than 20 residual
    evaluations (measured 8) against MINPACK's 2 x 120 per Jacobian."""
    p = with_links(load_scenario("engage-response"), 40).params
    model = chain_model(p, initial_chain(p))
    eq = EQ.solve_equilibrium(model.params, model=model)
    assert eq.solver.message.startswith("chord iterations") and eq.solver.nfev < 20
    scale = model.S[0] * G0 * model.l[0]
    rigid = EQ.solve_equilibrium(model.params.replace(hose={"axial_stiffness_n": np.inf, "axial_damping_n_s": 0.0}))
    sol, res, q, lam = EQ._elastic_newton(model, model.steady_env, rigid.q, scale, None)
    assert "chord" not in str(sol.message) and res < EQ.RESIDUAL_TOLERANCE
    q = (q + np.pi) % (2 * np.pi) - np.pi
    assert np.max(np.abs(q - eq.q)) < 1e-12 and np.max(np.abs(lam - eq.lengths_m)) < 1e-12


def test_the_engagements_banded_chord_finds_the_same_balance_position():
    """The engagement's balance position (``chain_equilibrium``: chord iterations on a banded
    Jacobian of half-width 5, then the elastic chord on that band) against MINPACK's Newton on the
    full problem: the same angles to 1e-12 rad, lengths to 1e-12 m (measured 1.2e-13 rad, 6e-17 m
    at 40 links); rigid links keep MINPACK's own answer, bit for bit."""
    from hosedrogue.engagement.chain import chain_equilibrium

    sc = with_links(load_scenario("engage-response"), 40)
    eq, model = chain_equilibrium(sc.params, initial_chain(sc.params))
    assert "band" in eq.solver.message
    ref = EQ.solve_equilibrium(model.params, model=model)
    assert np.max(np.abs(eq.q - ref.q)) < 1e-12 and np.max(np.abs(eq.lengths_m - ref.lengths_m)) < 1e-12
    rigid = sc.params.replace(hose={"axial_stiffness_n": np.inf, "axial_damping_n_s": 0.0})
    eq, model = chain_equilibrium(rigid, initial_chain(rigid))
    assert np.array_equal(eq.q, EQ.solve_equilibrium(model.params, model=model).q)


def test_band_factorized_once_solves_as_scipy_solve_banded():
    """The chord's solve from the band factorized once (LAPACK gbtrf, then gbtrs per step) is
    scipy.linalg.solve_banded's (gbsv: the same two routines) bit for bit, on a diagonally weighted
    random band of the engagement's size (320 unknowns, half-width BAND) and right-hand sides over
    eleven decades; a non-finite band is refused as solve_banded refuses it."""
    import pytest
    import scipy.linalg

    rng = np.random.default_rng(32)
    w, m = EQ.BAND, 320
    ab = rng.standard_normal((2 * w + 1, m))
    ab[w] += 10.0
    factors = EQ._band_lu(ab)
    for scale in 10.0 ** np.arange(-8, 4):
        r = scale * rng.standard_normal(m)
        assert EQ._band_solve(factors, r).tobytes() == scipy.linalg.solve_banded((w, w), ab, r).tobytes()
    ab[3, 7] = np.nan
    with pytest.raises(ValueError, match="infs or NaNs"):
        EQ._band_lu(ab)
