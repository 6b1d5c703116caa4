"""Convergence studies: integration step and number of links.

``step_convergence`` runs a case at several RK4 steps and measures the largest drogue-position
difference from a run at a much finer step; ``link_convergence`` measures how the balance
position and the lowest lateral and vertical modes change as the hose is cut into more links.
These numbers justify the default step (``Numerics.step_s``) and the paper's 20 links
(docs/convergence.md, and the report). ``with_links`` is the one rule for running a scenario on
another number of links (the step scaled with the link length), used by link-doubling checks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis.equilibrium import solve_equilibrium
from ..analysis.linearize import linearize
from ..controllers.pid import PAPER_PID, pid_controller
from ..spec.paper import SEC233_TURBULENCE_WINDOW
from ..spec.params import PAPER, Params
from ..simulation import simulate

#: The cases of the step study: a strong free swing, the paper's turbulence case, and the same
#: with the paper's PID in the loop (the stiffest: the derivative filter pole is at ~106 rad/s).
STEP_CASES = ("swing", "turbulence", "turbulence+pid")


@dataclass(frozen=True)
class StepStudy:
    """Result of :func:`step_convergence`."""

    case: str  #: the case run, one of :data:`STEP_CASES`
    steps_s: np.ndarray  #: RK4 steps compared [s]
    max_error_m: np.ndarray  #: max over time of |drogue position - reference| [m]
    reference_step_s: float  #: step of the reference run [s]
    duration_s: float  #: simulated time of each run [s]

    @property
    def observed_order(self) -> np.ndarray:
        """log2 of successive error ratios (4 for RK4 on smooth forcing)."""
        e = self.max_error_m
        return np.log2(e[:-1] / e[1:])


def _case_setup(case: str, params: Params):
    n = params.hose.links
    if case == "swing":
        p = params.replace(turbulence={"enabled": False})
        eq = solve_equilibrium(p)
        x0 = eq.state.copy()
        x0[0 : 2 * n : 2] += math.radians(15)
        x0[1 : 2 * n : 2] += math.radians(10)
        return p, eq, x0, None, 10.0
    p = params.replace(turbulence={"enabled": True, **SEC233_TURBULENCE_WINDOW})
    eq = solve_equilibrium(p)
    ctrl = pid_controller(PAPER_PID["lateral"], PAPER_PID["vertical"]) if case.endswith("pid") else None
    return p, eq, eq.state, ctrl, 30.0


def step_convergence(case: str = "swing", steps_s=(0.02, 0.01, 0.005, 0.0025),
                     reference_step_s: float = 0.000625, params: Params = PAPER) -> StepStudy:
    """Drogue-position error of RK4 at ``steps_s`` against a run at ``reference_step_s``.

    Parameters
    ----------
    case : str
        One of :data:`STEP_CASES`.
    steps_s : sequence of float
        RK4 steps to compare [s]; each must divide 0.04 s (the common output interval).
    reference_step_s : float
        Step of the reference run [s], much finer than ``steps_s``.
    params : Params
        Parameter set (turbulence is switched on or off by the case).

    Returns
    -------
    StepStudy
    """
    if case not in STEP_CASES:
        raise ValueError(f"case = {case!r}: must be one of {', '.join(STEP_CASES)}")
    p, eq, x0, ctrl, duration = _case_setup(case, params)
    out_dt = 0.04  # a common multiple of every step in the study

    def path(h):
        pp = p.replace(numerics={"step_s": h, "output_every": int(round(out_dt / h))})
        res = simulate(pp, duration, x0=x0, control=ctrl, equilibrium=eq)
        if not res.completed:
            raise RuntimeError(f"{case} at step {h} s: {res.message}")
        return res.drogue_position_m

    ref = path(reference_step_s)
    errs = np.array([np.max(np.abs(path(h) - ref)) for h in steps_s])
    return StepStudy(case, np.asarray(steps_s, float), errs, reference_step_s, duration)


@dataclass(frozen=True)
class LinkStudy:
    """Result of :func:`link_convergence`."""

    links: np.ndarray  #: link counts compared [-]
    drogue_position_m: np.ndarray  #: (k, 3) balance position of the drogue [m] in S_p
    lowest_lateral_rad_s: np.ndarray  #: damped frequency of the lowest mode seen laterally [rad/s]
    lowest_vertical_rad_s: np.ndarray  #: damped frequency of the lowest mode seen vertically [rad/s]


def link_convergence(links=(5, 10, 20, 40, 80), params: Params = PAPER) -> LinkStudy:
    """Balance position and lowest lightly damped mode frequencies against the link count.

    Parameters
    ----------
    links : sequence of int
        Link counts to compare [-].
    params : Params
        Parameter set (its ``hose.links`` is replaced by each count).

    Returns
    -------
    LinkStudy
    """
    pos, lat, ver = [], [], []
    for n in links:
        p = params.replace(hose={"links": int(n)})
        lm = linearize(p)
        pos.append(lm.equilibrium.drogue_position_m)
        w_lat, w_ver = lowest_modes(lm)
        lat.append(w_lat)
        ver.append(w_ver)
    return LinkStudy(np.asarray(links), np.array(pos), np.array(lat), np.array(ver))


@dataclass(frozen=True)
class ConvergenceStudy:
    """Both studies on one model: the RK4 step's and the link count's."""

    steps: tuple  #: StepStudy per case
    links: LinkStudy  #: the link count's

    def figures(self) -> dict:
        """The study's figure (:func:`hosedrogue.studies.convergence_figures.plot_convergence`).

        Returns
        -------
        dict
            ``{"convergence": matplotlib.figure.Figure}``.
        """
        from .convergence_figures import plot_convergence

        return {"convergence": plot_convergence(list(self.steps), self.links)}


def lowest_modes(lm) -> tuple[float, float]:
    """Lowest mode frequency [rad/s] visible in each output: the imaginary part of the
    lowest-frequency pole whose modal residue exceeds 1 % of the largest (the pendulum mode of
    the lateral and vertical channels).

    Parameters
    ----------
    lm : LinearModel
        Linear model with ``A``, ``B``, ``C`` (:func:`hosedrogue.analysis.linearize.linearize`).

    Returns
    -------
    (float, float)
        Lateral and vertical frequency [rad/s]; NaN where no mode is visible.
    """
    lam, vec = np.linalg.eig(lm.A)
    left = np.linalg.inv(vec)
    out = []
    for ch in range(2):
        res = np.abs((lm.C[ch] @ vec) * (left @ lm.B[:, ch]))
        order = np.argsort(np.abs(lam.imag))
        keep = [i for i in order if lam[i].imag > 0 and res[i] > 0.01 * res.max()]
        out.append(float(lam[keep[0]].imag) if keep else float("nan"))
    return out[0], out[1]


def with_links(scenario, links: int):
    """The scenario on ``links`` links, the step scaled with the link length and the output
    interval [s] kept (to the nearest whole number of steps): the mesh of a link-doubling check.
    With the stiff SDIRK (elastic links, whose bending and string waves are implicit,
    docs/model.md §11) the step is not bounded by the links: a finer mesh scales it with them,
    a coarser one keeps it.

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The scenario (its ``hose.links``, ``numerics.step_s`` [s] and ``numerics.output_every``).
    links : int
        Number of links [-], >= 1.

    Returns
    -------
    hosedrogue.scenarios.Scenario
    """
    import dataclasses

    from ..errors import ParameterError

    if isinstance(links, bool) or not isinstance(links, (int, np.integer)) or links < 1:
        raise ParameterError(f"links = {links!r}: must be an integer >= 1")
    p = scenario.params
    ratio = p.hose.links / links
    # RK4's step follows the link length both ways; the SDIRK's is set by the motion it resolves, so
    # a finer mesh halves it with the links (both refined together) and a coarser one keeps it
    sdirk = p.numerics.integrator == "sdirk2"
    step = p.numerics.step_s * (min(ratio, 1.0) if sdirk else ratio)
    every = max(1, int(round(p.numerics.output_every * p.numerics.step_s / step)))
    return dataclasses.replace(scenario, params=p.replace(hose={"links": int(links)},
                                                          numerics={"step_s": step, "output_every": every}))
