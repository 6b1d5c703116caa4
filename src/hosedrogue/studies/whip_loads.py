"""The whip's loads against the hose's axial stiffness and the closure speed, for the three reel laws.

A grid of engagement scenarios, by default the shipped ones (``engage-locked``,
``engage-constant-tension``, ``engage-response``), or the user's own (a TOML file, or a
:class:`~hosedrogue.scenarios.Scenario` built in Python, with a ``[probe]``): the axial stiffness EA [N] and the probe's closure speed [m/s] are varied,
everything else is the scenario's. The axial damping follows EA at the shipped loss factor: the
Kelvin-Voigt damping ``c_a = eta EA / omega_1`` with ``eta`` = 0.1 at the trailed hose's first
axial mode ``omega_1`` (:func:`first_axial_mode_rad_s`), so every EA has the same damping ratio
of its slowest axial wave (docs/model.md §11). The probe's latch window is opened down to
:data:`MIN_CLOSURE_SPEED_M_S` so that the slowest probe couples (the coupler sees the closure
speed along the inclined last link, 0.48 m/s of 0.5 m/s), and each run lasts until
:data:`SETTLE_S` after the probe stops. Each row reports the peaks of :mod:`hosedrogue.results.run`
(taken at every step) and, for the rows verified (``verify``: a sample of the grid run again on
twice the links at half the step, :mod:`hosedrogue.studies.verify`), which of them are converged;
the other rows' peaks are "unverified".

``hosedrogue study whip-loads`` runs it from the command line; the report's section "Whip loads"
presents it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import scipy.optimize

from ..spec.params import Params

#: The shipped engagement scenarios, one per reel law.
SCENARIOS = ("engage-locked", "engage-constant-tension", "engage-response")
#: The grid of the full study: axial stiffness [N] and closure speed [m/s] (the brief's ranges).
STIFFNESSES_N = (1e5, 1e6, 1e7, 1e8)
CLOSURE_SPEEDS_M_S = (0.5, 1.0, 1.5, 2.0, 2.5)
#: The shipped scenarios' loss factor of the axial damping at the first axial mode [-].
LOSS_FACTOR = 0.1
#: The latch window's lower end in the study [m/s], below the coupler's 0.48 m/s of the 0.5 m/s probe.
MIN_CLOSURE_SPEED_M_S = 0.3
#: Each run goes on this long after the probe stops [s]: the snap at the end of the push and its
#: waves (the shipped runs: 15 s, contact at 2 s, the push over at 3.6 s).
SETTLE_S = 5.0
#: The peaks of a row (units in the names), as the run's summary names them.
PEAKS = ("peak_exit_tension_n", "peak_tension_rise_n", "peak_drogue_tension_n", "peak_probe_load_n", "peak_slack_m")


def first_axial_mode_rad_s(params: Params) -> float:
    """The first axial natural frequency [rad/s] of the trailed elastic hose: a uniform bar of
    length L and mass mu L, fixed at the exit, with the drogue's mass m_d at its free end:
    ``omega_1 = beta c / L``, ``c = sqrt(EA / mu)``, beta the first root of ``beta tan beta =
    mu L / m_d`` (33.8 rad/s for the paper's hose at EA = 1e6 N).

    Parameters
    ----------
    params : Params
        Hose length [m], mass per length [kg/m], axial stiffness [N] (finite) and drogue mass [kg].

    Returns
    -------
    float
    """
    hose = params.hose
    ratio = hose.mass_per_length_kg_m * hose.length_m / params.drogue.mass_kg
    beta = scipy.optimize.brentq(lambda b: b * math.tan(b) - ratio, 1e-9, math.pi / 2 - 1e-12)
    return beta * math.sqrt(hose.axial_stiffness_n / hose.mass_per_length_kg_m) / hose.length_m


def axial_damping_n_s(params: Params, stiffness_n: float, loss_factor: float = LOSS_FACTOR) -> float:
    """Kelvin-Voigt axial damping [N s] of loss factor ``loss_factor`` at the first axial mode of
    the hose with axial stiffness ``stiffness_n`` [N]: ``eta EA / omega_1``.

    Parameters
    ----------
    params : Params
        The hose and drogue (:func:`first_axial_mode_rad_s`).
    stiffness_n : float
        Axial stiffness EA [N].
    loss_factor : float
        eta [-].

    Returns
    -------
    float
    """
    p = params.replace(hose={"axial_stiffness_n": float(stiffness_n), "axial_damping_n_s": 0.0})
    return loss_factor * stiffness_n / first_axial_mode_rad_s(p)


@dataclass(frozen=True)
class WhipLoadRow:
    """One run of the grid: its settings, outcome, peaks and their convergence flags."""

    scenario: str  #: the scenario's name (a shipped one, or the user's file's)
    law: str  #: reel law
    stiffness_n: float  #: axial stiffness EA [N]
    damping_n_s: float  #: axial damping c_a [N s]
    closure_speed_m_s: float  #: probe closure speed [m/s]
    links: int  #: links of the run [-]
    result: str  #: the capture's outcome
    completed: bool  #: the run reached its end
    peaks: dict  #: PEAKS -> value (N or m)
    converged: dict  #: PEAKS -> True/False as measured by the row's verification, or "unverified"
    #: the locked reel with ``ensemble``: PEAKS -> the peak's distribution over the perturbed copies
    #: (:func:`hosedrogue.studies.ensemble.distribution`: median, 5 % and 95 % points, bootstrap intervals)
    distributions: dict | None = None

    def to_dict(self) -> dict:
        """The row as a flat dict (``converged_<peak>`` flags after the peaks; with distributions,
        ``<peak>_median``, ``_p05``, ``_p95``)."""
        d = {k: v for k, v in dataclasses.asdict(self).items() if k not in ("peaks", "converged", "distributions")}
        d.update(self.peaks)
        d.update({f"converged_{k}": v for k, v in self.converged.items()})
        for k, dist in (self.distributions or {}).items():
            d.update({f"{k}_{q}": dist[q] for q in ("median", "p05", "p95")})
        return d


def engagement_scenario(scenario):
    """An engagement scenario of the study: a shipped name, a TOML file or a Scenario.

    Parameters
    ----------
    scenario : str, Path or hosedrogue.scenarios.Scenario
        A shipped engagement scenario's name, a scenario file, or a scenario built in Python.

    Returns
    -------
    hosedrogue.scenarios.Scenario

    Raises
    ------
    ParameterError
        The name or file is not a scenario, or the scenario has no engagement (``[probe]``).
    """
    from ..scenarios import Scenario, load_scenario

    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    return sc.require_model("engagement", "scenarios", "the whip-load study runs engagements (a scenario with "
                            f"[probe] and [reel], e.g. {SCENARIOS[-1]})")


def study_scenario(scenario, stiffness_n: float, closure_speed_m_s: float, links: int | None = None,
                   step_s: float | None = None):
    """The scenario of one grid point: ``scenario`` with EA, its damping, the closure speed, the wider
    latch window and the run's length; on ``links`` links at ``step_s`` [s] if given.

    Parameters
    ----------
    scenario : str, Path or hosedrogue.scenarios.Scenario
        An engagement scenario (:func:`engagement_scenario`).
    stiffness_n : float
        Axial stiffness EA [N].
    closure_speed_m_s : float
        Probe closure speed [m/s].
    links : int, optional
        Links of the run (default the scenario's).
    step_s : float, optional
        Integration step [s] with ``links`` (default the scenario's).

    Returns
    -------
    hosedrogue.scenarios.Scenario
    """
    from ..simulation.budget import on_step_grid
    from ..spec.sections import Engagement

    sc = engagement_scenario(scenario)
    hose = {"axial_stiffness_n": float(stiffness_n), "axial_damping_n_s": axial_damping_n_s(sc.params, stiffness_n)}
    numerics = {}
    if links is not None:
        hose["links"] = int(links)
        h = step_s if step_s is not None else sc.params.numerics.step_s
        numerics = {"step_s": h, "output_every": max(1, int(round(0.01 / h)))}
    probe = dataclasses.replace(sc.engagement.probe, closure_speed_m_s=float(closure_speed_m_s),
                                min_closure_speed_m_s=MIN_CLOSURE_SPEED_M_S)
    v = probe.closure_speed_m_s
    params = sc.params.replace(hose=hose, numerics=numerics)
    # on the run's output grid (the nearest output time), so the saved series reaches the run's end
    duration = on_step_grid((probe.standoff_m + probe.push_m) / v + probe.stop_time_s + SETTLE_S,
                            params.numerics.step_s, params.numerics.output_every)
    return dataclasses.replace(sc, params=params, duration_s=duration,
                               engagement=Engagement(reel=sc.engagement.reel, probe=probe,
                                                     bow_wave=sc.engagement.bow_wave, pilot=sc.engagement.pilot))


def run_point(scenario, stiffness_n: float, closure_speed_m_s: float, links: int | None = None,
              step_s: float | None = None, verify: bool = False, tolerance: float = 0.03, ensemble: int = 0,
              perturb: str = "probe-offset=1e-6") -> WhipLoadRow:
    """Run one grid point (:func:`study_scenario`) and read its row.

    Parameters
    ----------
    scenario, stiffness_n, closure_speed_m_s, links, step_s
        See :func:`study_scenario` (EA [N], closure speed [m/s], step [s]).
    verify : bool
        Also run it on twice the links at the refined step and flag each peak converged or not
        (:func:`hosedrogue.studies.verify.verify_run`); otherwise its peaks are "unverified".
    tolerance : float
        Relative tolerance of the verification [-].
    ensemble : int
        The locked reel (a chaotic flail): also this many perturbed copies (0: none) and each
        peak's distribution (:func:`hosedrogue.studies.ensemble.run_ensemble`).
    perturb : str
        The copies' perturbation (:func:`hosedrogue.studies.ensemble.parse_perturbation`).

    Returns
    -------
    WhipLoadRow
    """
    from ..scenarios.runner import run

    sc = study_scenario(scenario, stiffness_n, closure_speed_m_s, links, step_s)
    dist = None
    if ensemble and sc.engagement.reel.law == "locked":
        from .ensemble import run_ensemble

        dist = {k: v for k, v in run_ensemble(sc, ensemble, perturb).distributions.items() if k in PEAKS}
    if verify:
        from .verify import verify_run

        r = verify_run(sc, tolerance)
    else:
        r = run(sc)
    s = r.summary()
    return WhipLoadRow(scenario=sc.name, law=sc.engagement.reel.law, stiffness_n=float(stiffness_n),
                       damping_n_s=sc.params.hose.axial_damping_n_s, closure_speed_m_s=float(closure_speed_m_s),
                       links=sc.params.hose.links, result=s["result"], completed=r.completed,
                       peaks={k: s[k] for k in PEAKS}, converged=dict(s["converged"]), distributions=dist)


def whip_load_study(stiffnesses_n=STIFFNESSES_N, closure_speeds_m_s=CLOSURE_SPEEDS_M_S, scenarios=SCENARIOS,
                    links: int | None = None, step_s: float | None = None, progress=None, verify: int = 0,
                    tolerance: float = 0.03, ensemble: int = 0, perturb: str = "probe-offset=1e-6") -> list[WhipLoadRow]:
    """The grid: every scenario x stiffness x closure speed, one run each (deterministic: no
    turbulence, so no seeds); ``verify`` of its rows, spread evenly over the grid (the first and
    the last among them), verified.

    Parameters
    ----------
    stiffnesses_n : sequence of float
        Axial stiffnesses EA [N].
    closure_speeds_m_s : sequence of float
        Probe closure speeds [m/s].
    scenarios : sequence of str, Path or Scenario
        The engagement scenarios: shipped names (default: one per reel law), files or Scenarios
        (:func:`engagement_scenario`); every one is loaded and checked before the first run.
    links : int, optional
        Links of every run (default the scenarios').
    step_s : float, optional
        Integration step with ``links`` [s].
    progress : callable, optional
        Called with a short text before each run.
    verify : int
        How many rows to verify [-] (:func:`run_point`; 0: none, the grid's size or more: all).
    tolerance : float
        Relative tolerance of the verification [-].
    ensemble : int
        Perturbed copies of every locked-reel row (0: none): its peaks as distributions (:func:`run_point`).
    perturb : str
        Their perturbation ("probe-offset=SIZE_M" or "seed").

    Returns
    -------
    list of WhipLoadRow
    """
    from .verify import check_tolerance

    tolerance = check_tolerance(tolerance)
    loaded = [engagement_scenario(sc) for sc in scenarios]
    points = [(sc, ea, v) for sc in loaded for ea in stiffnesses_n for v in closure_speeds_m_s]
    sample = verified_rows(len(points), verify)
    rows = []
    for i, (sc, ea, v) in enumerate(points):
        if progress is not None:
            progress(f"{sc.name}, EA {ea:g} N, {v:g} m/s{' (verified)' if i in sample else ''}")
        rows.append(run_point(sc, ea, v, links, step_s, i in sample, tolerance, ensemble, perturb))
    return rows


def verified_rows(rows: int, verify: int) -> set:
    """The indices of the ``verify`` rows of ``rows`` that a study verifies: spread evenly, the
    first and the last among them.

    Parameters
    ----------
    rows : int
        Rows of the grid [-].
    verify : int
        Rows to verify [-] (at most all).

    Returns
    -------
    set of int
    """
    from ..errors import ParameterError

    if isinstance(verify, bool) or not isinstance(verify, (int, np.integer)) or verify < 0:
        raise ParameterError(f"verify = {verify!r}: must be a whole number of rows >= 0")
    k = min(int(verify), rows)
    return set(np.round(np.linspace(0, rows - 1, k)).astype(int).tolist()) if k else set()


def snap_scale_n(params: Params, speed_m_s: float) -> float:
    """The tension behind a snap front of speed ``speed_m_s`` [m/s] in the elastic hose,
    ``v sqrt(EA mu)`` [N] (the wave equation's, docs/model.md §11).

    Parameters
    ----------
    params : Params
        Axial stiffness EA [N] and mass per length mu [kg/m].
    speed_m_s : float
        Snap speed [m/s].

    Returns
    -------
    float
    """
    return float(speed_m_s * np.sqrt(params.hose.axial_stiffness_n * params.hose.mass_per_length_kg_m))
