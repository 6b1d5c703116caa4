"""Verify a run: its headline figures measured against the same scenario on a finer mesh
(docs/convergence.md, "Verifying a run"; ``hosedrogue simulate SCENARIO --verify``).

:func:`verify_run` runs the scenario, then again on twice the links at the step the scheme needs
(:func:`refined_scenario`), and attaches to the run's result the comparison of every headline
figure (:func:`hosedrogue.results.convergence.compare_figures`): the value, the refined value, the
change, a Richardson estimate of the discretization error and ``converged`` (the change within
the tolerance). ``run.json`` carries it as ``"verification"``.
"""

from __future__ import annotations

import dataclasses

from ..errors import ParameterError
from ..results.convergence import (ASSUMED_ORDER, DEFAULT_TOLERANCE, compare_figures, flailing, headline_figures,
                                   went_slack)

__all__ = ["REFINEMENT", "ADAPTIVE_TOLERANCE_FACTOR", "refined_scenario", "verify_run", "verification",
           "check_tolerance"]

#: The refinement ratio of the links [-] (and of the fixed step: halved).
REFINEMENT = 2
#: The adaptive integrator (DOP853, eighth order) has no step to halve: its tolerances are divided
#: by this [-], 2^8, the factor its local error falls by when the step is halved.
ADAPTIVE_TOLERANCE_FACTOR = 256.0

#: ``notes`` entry when a peak of a hose still slack at the end is not converged.
FLAIL_NOTE = ("the hose is still slack at the end of the run (a loop flailing in the air stream, the locked reel's): "
              "a chaotic motion, whose tension and probe load peaks change with any change of the mesh, the step or "
              "the probe's path (a micrometre moves the peak exit tension by 40 %, benchmarks/locked_reel_chaos.py); "
              "report them as a distribution (hosedrogue simulate --ensemble, docs/engagement.md)")
#: ``notes`` entry when a peak of a hose that went slack and snapped taut is not converged.
SNAP_NOTE = ("the hose went slack and snapped taut: a snap is a steep tension wave whose peak the mesh resolves "
             "only as its link length and step allow (docs/engagement.md, \"Link-count convergence\")")


def check_tolerance(tolerance: float) -> float:
    """``tolerance`` as a float in (0, 1), or a one-line error.

    Parameters
    ----------
    tolerance : float
        Relative tolerance [-].

    Returns
    -------
    float

    Raises
    ------
    ParameterError
    """
    try:
        t = float(tolerance)
    except (TypeError, ValueError):
        t = float("nan")
    if isinstance(tolerance, bool) or not 0.0 < t < 1.0:
        raise ParameterError(f"tolerance = {tolerance!r}: must be a number in (0, 1) (a relative change, 0.03 is 3 %)")
    return t


def refined_scenario(scenario):
    """The scenario of a verification: twice the links and the step the scheme needs, the output
    interval kept (:func:`hosedrogue.studies.convergence.with_links`): RK4's step halved with the
    link length (its stability and fourth-order error follow the links), the SDIRK's halved (its
    error is second order in the step, as the links' is in 1/links: both fall by 4); the adaptive
    integrator's tolerances divided by :data:`ADAPTIVE_TOLERANCE_FACTOR`.

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The scenario.

    Returns
    -------
    hosedrogue.scenarios.Scenario
    """
    from .convergence import with_links

    sc = with_links(scenario, REFINEMENT * scenario.params.hose.links)
    n = sc.params.numerics
    if n.integrator == "adaptive":
        sc = dataclasses.replace(sc, params=sc.params.replace(numerics={
            "rtol": n.rtol / ADAPTIVE_TOLERANCE_FACTOR, "atol": n.atol / ADAPTIVE_TOLERANCE_FACTOR}))
    return sc


def _mesh(scenario, result) -> dict:
    p = scenario.params
    return {"links": p.hose.links, "step_s": p.numerics.step_s, "integrator": p.numerics.integrator,
            "completed": result.completed, "message": result.message}


def _notes(base, refined, figures: dict) -> list:
    notes = []
    if not refined.completed:
        notes.append(f"the refined run stopped early ({refined.message}): its figures cover only its part of the run")
    off = [k for k, f in figures.items() if not f["converged"]]
    peaks_off = [k for k in off if k.startswith("peak_") and not k.startswith("peak_control")]
    if peaks_off and hasattr(base, "slack_m"):
        if flailing(base.t_s, base.slack_m):
            notes.append(FLAIL_NOTE)
        elif went_slack(base.exit_tension_n):
            notes.append(SNAP_NOTE)
    if off:
        notes.append(f"not converged within the tolerance: {', '.join(off)}")
    return notes


def verification(scenario, base, refined_sc, refined, tolerance: float = DEFAULT_TOLERANCE) -> dict:
    """The ``"verification"`` document of a run and its refined run (both already run).

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The run's scenario.
    base : hosedrogue.results.run.RunResult
        Its result.
    refined_sc : hosedrogue.scenarios.Scenario
        The refined scenario (:func:`refined_scenario`).
    refined : hosedrogue.results.run.RunResult
        Its result.
    tolerance : float
        Relative tolerance [-].

    Returns
    -------
    dict
        ``status`` ("verified"), ``tolerance``, ``assumed_order``, ``run`` and ``refined`` (links,
        step [s], integrator, completed, message), ``converged`` (every figure), ``not_converged``,
        ``figures`` (:func:`~hosedrogue.results.convergence.compare_figures`), ``result_agrees``
        (an engagement's capture outcome the same on both meshes), ``notes``.
    """
    figures = compare_figures(headline_figures(base), headline_figures(refined), tolerance)
    doc = {"status": "verified", "tolerance": tolerance, "assumed_order": ASSUMED_ORDER,
           "run": _mesh(scenario, base), "refined": _mesh(refined_sc, refined),
           "converged": all(f["converged"] for f in figures.values()),
           "not_converged": [k for k, f in figures.items() if not f["converged"]], "figures": figures}
    if hasattr(base, "capture_category"):
        doc["result_agrees"] = base.capture_category() == refined.capture_category()
    doc["notes"] = _notes(base, refined, figures)
    return doc


def verify_run(scenario, tolerance: float = DEFAULT_TOLERANCE, base=None):
    """Run ``scenario`` and verify it: the same scenario on :func:`refined_scenario`'s mesh, every
    headline figure compared (:func:`verification`).

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The scenario (``load_scenario(name or file)``).
    tolerance : float
        Relative tolerance [-] of ``converged`` (default 0.03).
    base : hosedrogue.results.run.RunResult, optional
        The scenario's result if already run (it is not run again).

    Returns
    -------
    hosedrogue.results.run.RunResult
        ``base`` with its ``verification`` set (``run.json``'s ``"verification"``).
    """
    from ..scenarios.runner import run

    tolerance = check_tolerance(tolerance)
    refined_sc = refined_scenario(scenario)
    if base is None:
        base = run(scenario)
    refined = run(refined_sc)
    return dataclasses.replace(base, verification=verification(scenario, base, refined_sc, refined, tolerance))
