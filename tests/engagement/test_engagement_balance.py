"""The engagement's balance position by its own evaluation (hosedrogue.engagement.balance) against
the fixed-length chain's (an independent assembly of the same statics: its own kinematics, loads
and generalized forces), and the compiled code an engagement then needs."""

import subprocess
import sys

import numpy as np
import pytest

from hosedrogue.analysis import equilibrium as EQ
from hosedrogue.engagement.balance import EngagementStatics, engagement_equilibrium
from hosedrogue.engagement.chain import chain_equilibrium, chain_model, initial_chain
from hosedrogue.scenarios import load_scenario


def _steady(name):
    p = load_scenario(name).params
    return p.replace(turbulence={"enabled": False})


@pytest.mark.parametrize("name", ["approach-moderate", "approach-turn-moderate", "engage-response"])
def test_the_engagements_balance_is_the_fixed_length_chains(name):
    """Rigid links in level flight and in the tanker's steady turn, elastic links (160, EA 1e6 N):
    both solve the same statics to 1e-10 of the weight moment, so they agree to far better than
    what that tolerance moves (a micrometre): angles to 1e-14 rad, lengths and joints to 1e-12 m,
    forces to 1e-8 N (measured 4.4e-16 rad, 3.9e-14 m, 2.2e-10 N: the engagement's exit link is
    L minus the other links, whose rounding (1e-16 m) its axial stiffness turns into 1e-8 N of
    tension)."""
    p = _steady(name)
    chain = initial_chain(p)
    ref, _ = chain_equilibrium(p, chain)
    own, _ = engagement_equilibrium(p, chain)
    assert own.residual < EQ.RESIDUAL_TOLERANCE and ref.residual < EQ.RESIDUAL_TOLERANCE
    assert np.max(np.abs(own.q - ref.q)) < 1e-14
    assert np.max(np.abs(own.joints_m - ref.joints_m)) < 1e-12
    assert (own.lengths_m is None) == (ref.lengths_m is None) == (not p.hose.elastic)
    if own.lengths_m is not None:
        assert np.max(np.abs(own.lengths_m - ref.lengths_m)) < 1e-12
    for a, b in ((own.drogue_drag_n, ref.drogue_drag_n), (own.tow_force_n, ref.tow_force_n),
                 (own.exit_tension_n, ref.exit_tension_n)):
        assert np.max(np.abs(np.asarray(a) - np.asarray(b))) < 1e-8
    # the variant compiled with the drogue controller's code gives the same bits
    again, _ = engagement_equilibrium(p, chain, controlled=True)
    assert again.q.tobytes() == own.q.tobytes() and again.tow_force_n.tobytes() == own.tow_force_n.tobytes()


@pytest.mark.parametrize("name", ["approach-moderate", "engage-response"])
def test_the_two_residuals_agree_away_from_the_balance(name):
    """At the towed-cable guess (generalized forces up to 170 N m) and, for elastic links, with
    every link stretched by 1e-3: the engagement's residual and the fixed-length chain's agree to
    1e-9 of the largest entry (measured 6e-15 for rigid links; 8e-10 for the elastic lengths'
    entries, the exit link's rounding times EA as above), and are not zero there."""
    p = _steady(name)
    chain = initial_chain(p)
    model = chain_model(p, chain)
    own, ref = EngagementStatics(p, chain, model), EQ.ChainStatics(model)
    q = EQ.towed_cable_guess(model)
    a, b = own.residual(model.steady_env)(q), ref.residual(model.steady_env)(q)
    assert np.max(np.abs(b)) > 1.0 and np.max(np.abs(a - b)) < 1e-9 * np.max(np.abs(b))
    if p.hose.elastic:
        y = np.concatenate([q, chain.l * 1.001])
        a, b = own.elastic_residual(model.steady_env)(y), ref.elastic_residual(model.steady_env)(y)
        assert np.max(np.abs(b)) > 1.0 and np.max(np.abs(a - b)) < 1e-9 * np.max(np.abs(b))


def test_an_engagement_compiles_no_fixed_length_evaluation():
    """A run of engage-response (elastic links, the SDIRK) and one of approach-moderate (rigid)
    in a fresh process: neither the fixed-length chain's state evaluation nor its elastic static
    residual is compiled or loaded (the balance position is the engagement's own)."""
    code = (
        "import dataclasses\n"
        "from hosedrogue.scenarios import load_scenario\n"
        "from hosedrogue.scenarios.runner import run\n"
        "from hosedrogue.model import chain_dynamics as CD, elastic as E\n"
        "for name in ('engage-response', 'approach-moderate'):\n"
        "    assert run(dataclasses.replace(load_scenario(name), duration_s=0.05)).completed\n"
        "print(len(CD.evaluate_point.signatures), len(CD.evaluate_point_still.signatures),"
        " len(E.elastic_static_residual.signatures), len(E.elastic_evaluate_ws.signatures))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split() == ["0", "0", "0", "0"]
