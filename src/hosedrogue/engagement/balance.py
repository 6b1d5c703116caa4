"""The engagement's balance position by the engagement's own compiled evaluation.

The balance position is the statics of the chain: the link angles (and, for elastic links, the
links' lengths) at which every generalized force vanishes at rest in steady air. The solver
(:func:`hosedrogue.analysis.equilibrium.solve_equilibrium`: the towed-cable guess, the banded
chord or MINPACK's Newton, the wake's continuation, the elastic chord) takes the chain's statics
as an object; :class:`EngagementStatics` evaluates them by the evaluation an engagement compiles
for its run anyway (:mod:`hosedrogue.model.engagement.evaluation`), with the reel held, no probe
and no bow wave, then sums the generalized forces from its loads as the fixed-length chain's
residual does (:func:`hosedrogue.model.chain_dynamics.generalized_forces`,
:func:`hosedrogue.model.elastic.static_forces`). At the start of a run the engagement's variable
exit link has its nominal length, so these are the fixed-length chain's equations, assembled in
the engagement's order: the two residuals differ in their last bits (measured 6e-15 N m of
forces up to 171 N m at 20 links), and their solutions by less than the solver's tolerance.

Why not the fixed-length chain's evaluation, as before: a process that runs an engagement then
compiles the fixed-length chain's evaluation for the balance position alone (its rigid and its
elastic statics: about 3 s of CPU of a cold ``simulate engage-response``, docs/develop.md,
"The compiled core", seventh round).
"""

from __future__ import annotations

import collections
import dataclasses

import numpy as np

from ..analysis.equilibrium import Equilibrium
from ..model import chain_dynamics as CD, elastic as E, layout as LY
from ..model.engagement import evaluation as EV
from ..model.system import HoseModel, StateOutputs
from ..spec.params import Params
from ..spec.sections import Reel
from .chain import Chain, chain_equilibrium, initial_chain
from .loop import no_loop
from .parameters import engagement_parameters


class EngagementStatics:
    """The statics of the engagement's chain at its start (free length the hose's, the reel held),
    for :func:`hosedrogue.analysis.equilibrium.solve_equilibrium` (the methods of its
    :class:`~hosedrogue.analysis.equilibrium.ChainStatics`).

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and environment.
    chain : Chain
        The mesh.
    model : HoseModel
        Its parameter, environment and gust arrays (:func:`~hosedrogue.engagement.chain.chain_model`).
    controlled : bool
        Evaluate by the variant compiled with the drogue controller's code (switched off here:
        the same numbers), the one a run with a drogue controller compiles; else the one without.
    """

    def __init__(self, params: Params, chain: Chain, model: HoseModel, controlled: bool = False):
        self.chain, self.model, self.n = chain, model, chain.n
        # the reel held (locked, no payout), no probe, no bow wave, no controller
        self.ep = engagement_parameters(params, Reel(law="locked", payout_m=0.0), None, chain, np.zeros(3), None)
        self.elastic = self.ep[LY.EP_ELASTIC] != 0.0
        self.nh = (6 if self.elastic else 4) * self.n
        self.z = np.zeros(self.nh + LY.Z_TAIL)
        self.z[self.nh + LY.Z_L] = float(np.sum(chain.l))  # the run's start: L = sum of the links
        self.l, self.M, self.J = chain.l.copy(), chain.M.copy(), chain.J.copy()  # the exit link's set in them
        self.ws, self.ws2 = CD.make_workspace(self.n), CD.make_workspace(self.n)
        self.ews = E.make_elastic_workspace(self.n) if self.elastic else None
        self.dM, self.out = np.empty(2), np.zeros(LY.O_SIZE)
        self.loop = no_loop()
        if self.elastic:
            self._evaluate = EV.eng_evaluate_elastic if controlled else EV.eng_evaluate_elastic_bare
        else:
            self._evaluate = EV.eng_evaluate if controlled else EV.eng_evaluate_bare
        self._at_rest(np.zeros(2 * self.n), chain.l, model.steady_env)  # sets the exit link's length in l

    def _at_rest(self, q, lam, env) -> None:
        """Evaluate the rest state of angles ``q`` (and lengths ``lam``) in the air ``env``."""
        n, z, m = self.n, self.z, self.model
        z[: 2 * n] = q
        if self.elastic:
            z[4 * n: 5 * n] = lam
            self._evaluate(0.0, z, n, self.l, self.M, self.J, m.ps, env, m.gust_values, self.ep, self.chain.chart,
                           self.loop, self.ws, self.ews, self.dM, self.out, 0.0, z)
        else:
            self._evaluate(0.0, z, n, self.l, self.M, self.J, m.ps, env, m.gust_values, self.ep, self.chain.chart,
                           self.loop, self.ws, self.ws2, self.dM, self.out)

    def residual(self, env: np.ndarray):
        """The rigid links' generalized forces at rest Q(q) (2n,) [N m] in the air ``env``; for
        elastic links the angles' entries of :meth:`elastic_residual` with every link at its
        material length (no tension: the rigid chain's statics, by the elastic evaluation the run
        compiles, as the solver's first stage)."""
        n, ws = self.n, self.ws
        if self.elastic:
            elastic = self.elastic_residual(env)
            unstretched = self.l.copy()  # the exit link's as the evaluation sets it (_at_rest at init)
            return lambda q: elastic(np.concatenate([q, unstretched]))[: 2 * n]
        Q = np.empty(2 * n)
        xi, G = CD.static_scratch(n)

        def fun(q):
            self._at_rest(q, None, env)
            CD.generalized_forces(self.l, self.M, n, ws[CD.WS_A], ws[CD.WS_B], ws[CD.WS_C], ws[CD.WS_F],
                                  ws[CD.WS_TAU], xi, G, Q)
            return Q.copy()

        return fun

    def elastic_residual(self, env: np.ndarray):
        """The elastic links' generalized forces at rest Q(y) (3n,) [N m] of y = [q, lam]."""
        n = self.n
        Q = np.empty(3 * n)

        def fun(y):
            lam = np.ascontiguousarray(y[2 * n:])
            self._at_rest(y[: 2 * n], lam, env)
            E.static_forces(n, self.l, lam, self.ws, self.ews, Q)
            return Q.copy()

        return fun

    def outputs(self, rest: np.ndarray) -> StateOutputs:
        """The outputs of the rest state ``rest`` ([q, 0] or [q, 0, lam, 0]) in steady air: joint
        positions [m], drogue drag and tow-point force [N] (with the weight of the hose mass lumped
        at the exit, ``ps[PS_M_TOW]``, as the fixed-length chain's outputs add it), exit tension [N]."""
        n, ws = self.n, self.ws
        self._at_rest(rest[: 2 * n], rest[4 * n: 5 * n] if self.elastic else None, self.model.steady_env)
        tow = ws[CD.WS_TOW].copy()  # the reel held: no L'' term
        tow[2] += self.model.ps[LY.PS_M_TOW] * self.model.ps[LY.PS_G]  # the exit's lumped mass, the model's
        return StateOutputs(ws[CD.WS_QDD].copy(), ws[CD.WS_R].copy(), ws[CD.WS_V].copy(), ws[CD.WS_DRAG].copy(), tow,
                            float(self.out[LY.O_T0]))


def engagement_equilibrium(params: Params, chain: Chain, duration_s: float | None = None,
                           controlled: bool = False) -> tuple[Equilibrium, HoseModel]:
    """The balance position of the chain by the engagement's own evaluation
    (:class:`EngagementStatics`; :func:`~hosedrogue.engagement.chain.chain_equilibrium` solves it
    by the fixed-length chain's): for a process that runs an engagement, which then compiles no
    evaluation of the other chain. The two balance positions differ by less than the solver's
    tolerance (tests/engagement/test_engagement_balance.py).

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and environment.
    chain : Chain
        The mesh (its free length the sum of its links).
    duration_s : float, optional
        Length of the run [s] the model's gust record must cover (see ``HoseModel``).
    controlled : bool
        Evaluate by the variant compiled with the drogue controller's code (the run has one) or
        without it: the same numbers, bit for bit.

    Returns
    -------
    equilibrium : hosedrogue.analysis.equilibrium.Equilibrium
    model : HoseModel
    """
    return chain_equilibrium(params, chain, duration_s,
                             statics=lambda model: EngagementStatics(params, chain, model, bool(controlled)))


#: The balance positions solved in this process, the 32 last used (as functools.lru_cache keeps
#: them, but keyed on the flight condition only: see :func:`_steady_equilibrium`)
_STEADY: collections.OrderedDict = collections.OrderedDict()


def _steady_equilibrium(steady: Params, controlled: bool) -> Equilibrium:
    """The balance position of ``steady`` by the engagement's own evaluation, once per process
    (by the variant of the first caller: the two give the same numbers, bit for bit)."""
    eq = _STEADY.get(steady)
    if eq is not None:
        _STEADY.move_to_end(steady)
        return eq
    eq, _ = engagement_equilibrium(steady, initial_chain(steady), controlled=controlled)
    for a in (eq.q, eq.joints_m, eq.drogue_position_m, eq.drogue_drag_n, eq.tow_force_n, eq.lengths_m):
        if a is not None:
            a.setflags(write=False)  # shared by every run that asks: nobody may change it
    _STEADY[steady] = eq
    if len(_STEADY) > 32:
        _STEADY.popitem(last=False)
    return eq


def initial_equilibrium(params: Params, controlled: bool = False) -> Equilibrium:
    """The balance position of the initial mesh (:func:`initial_chain`) in steady air, by the
    engagement's own evaluation (:func:`engagement_equilibrium`), solved once per process for each
    model and flight condition: the turbulence (its seed, intensity and window) and the run's
    length do not enter it (the same bits: tests/engagement), so a campaign's runs, which differ
    only in their gusts, share it. Its arrays are read-only.

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and environment.
    controlled : bool
        The run has a drogue controller: evaluate by the variant compiled with its code (the
        same numbers; a process then compiles the variant its run uses, not both).

    Returns
    -------
    hosedrogue.analysis.equilibrium.Equilibrium
    """
    return _steady_equilibrium(dataclasses.replace(params, turbulence=type(params.turbulence)()), bool(controlled))


