"""Whether a run's headline figures are converged with the mesh, measured on that run
(docs/convergence.md, "Verifying a run"): never decided by a rule.

:func:`headline_figures` reads the figures of a run that ``run.json`` leads with (the engagement's
peak loads and their rise, the slack, the drogue's excursion, the miss distance and closure speed;
the drogue displacement statistics of every run); :func:`compare_figures` sets each against the
same figure of the run repeated on twice the links at the refined step
(:func:`hosedrogue.studies.verify.verify_run` runs it) and says, for each, the change, a
Richardson estimate of the discretization error and ``converged``: the change within the
tolerance. A run that was not verified says so (:func:`unverified`): its figures are neither
converged nor not.

:func:`went_slack` and :func:`flailing` describe a run's hose (gone slack; still slack at the end,
the locked reel's chaotic loop); they explain a figure that does not converge, they never flag one.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["PEAK_KEYS", "ENGAGEMENT_FIGURES", "SLACK_TENSION_FRACTION", "FLAIL_SLACK_M", "FLAIL_WINDOW_S",
           "DEFAULT_TOLERANCE", "ASSUMED_ORDER", "UNVERIFIED", "UNVERIFIED_NOTE", "went_slack", "flailing",
           "headline_figures", "absolute_floor", "compare_figures", "unverified", "verification_document"]

#: The engagement's peaks (units in the names) whose flags the run's summary gives (``"converged"``).
PEAK_KEYS = ("peak_exit_tension_n", "peak_tension_rise_n", "peak_drogue_tension_n", "peak_probe_load_n", "peak_slack_m")

#: The engagement's headline figures a verification compares (run.json's ``"engagement"``), after
#: :data:`PEAK_KEYS`; every run adds its displacement statistics (``statistics.<name>``).
ENGAGEMENT_FIGURES = PEAK_KEYS + ("peak_drogue_excursion_m", "miss_distance_m", "closure_speed_m_s",
                                  "peak_control_force_n")

#: The relative change [-] within which a figure is called converged unless told otherwise: 3 %,
#: the bound of the engagements' link-doubling checks (docs/engagement.md, "Link-count convergence").
DEFAULT_TOLERANCE = 0.03

#: The order [-] in the refinement ratio 2 that the Richardson estimate assumes: the link count's
#: (the balance position and the modes converge at second order in 1/links, docs/convergence.md)
#: and the SDIRK's (second order in the step); RK4's fourth-order step error is then the smaller
#: part. The peaks of a snap wave are not smooth functions of the mesh, so for them the estimate
#: is indicative; ``converged`` uses the measured change only.
ASSUMED_ORDER = 2

#: A figure's value where a run was not verified.
UNVERIFIED = "unverified"
#: ``notes`` entry of a run that was not verified.
UNVERIFIED_NOTE = ("unverified: no figure of this run was checked against a finer mesh; run it with --verify "
                   "(hosedrogue.studies.verify.verify_run) to measure which are converged (docs/convergence.md)")

#: The hose counts as gone slack when its exit tension falls below this fraction of the steady
#: trail tension (the exit tension at the start, at the balance position) [-].
SLACK_TENSION_FRACTION = 0.1

#: Elastic links: the hose flails when its slack stays above FLAIL_SLACK_M [m] (ten times the ~1
#: cm sag of the steady trail, five times the responsive reel's dead band) over the run's last
#: FLAIL_WINDOW_S [s].
FLAIL_SLACK_M, FLAIL_WINDOW_S = 0.1, 1.0

#: Absolute changes below which a figure is converged whatever its relative change, by the unit
#: at the end of its name: a figure near zero (the miss distance of a capture, 1e-10 m; a control
#: force of a run without controller) has no meaningful relative change. 1 mm is 1/300 of the
#: capture radius and far below a drogue's size; 1 N is below 1e-3 of the trail tensions (1.5-5
#: kN); 1 mm/s of the closure speed's 0.5-2.5 m/s; 0.005 of a time fraction (half a percentage point).
ABSOLUTE_FLOORS = (("_m_s", 1e-3), ("_frac", 5e-3), ("_n", 1.0), ("_m", 1e-3))


def absolute_floor(key: str) -> float:
    """The change [in the figure's unit] below which figure ``key`` is converged
    (:data:`ABSOLUTE_FLOORS`, by the unit at the end of its name; 0 for a name without one).

    Parameters
    ----------
    key : str
        The figure's name (``statistics.`` prefix allowed).

    Returns
    -------
    float
    """
    for suffix, floor in ABSOLUTE_FLOORS:
        if key.endswith(suffix):
            return floor
    return 0.0


def went_slack(exit_tension_n) -> bool:
    """Whether the hose went (nearly) slack: its exit tension fell below
    :data:`SLACK_TENSION_FRACTION` of the trail tension at the start.

    Parameters
    ----------
    exit_tension_n : array (N,)
        Exit tension at the output times [N], the first at the balance position.

    Returns
    -------
    bool
    """
    T = np.asarray(exit_tension_n)
    return bool(T.size and np.min(T) < SLACK_TENSION_FRACTION * T[0])


def flailing(t_s, slack_m) -> bool:
    """Whether the hose is still slack at the end of the run (the locked reel's loop): its slack
    above :data:`FLAIL_SLACK_M` throughout the last :data:`FLAIL_WINDOW_S`.

    Parameters
    ----------
    t_s : array (N,)
        Output times [s].
    slack_m : array (N,)
        Slack at those times [m].

    Returns
    -------
    bool
    """
    t = np.asarray(t_s)
    return bool(t.size and np.min(np.asarray(slack_m)[t >= t[-1] - FLAIL_WINDOW_S]) > FLAIL_SLACK_M)


def _number(value):
    if value is None or isinstance(value, (bool, np.bool_, str)):
        return None
    v = float(value)
    return v if math.isfinite(v) else None


def headline_figures(result) -> dict:
    """The figures of a run that a verification compares: for an engagement
    :data:`ENGAGEMENT_FIGURES` of its summary, then for every run its displacement statistics
    (``statistics.<name>``, :meth:`hosedrogue.results.run.RunResult.statistics`).

    Parameters
    ----------
    result : hosedrogue.results.run.RunResult
        The run.

    Returns
    -------
    dict
        Name (unit in it) -> float, or None where the run has no such figure (no contact: no miss
        distance) or it is not finite.
    """
    out = {}
    if hasattr(result, "outcome"):
        o = result.outcome
        out.update({k: _number(o.get(k)) for k in ENGAGEMENT_FIGURES})
    out.update({f"statistics.{k}": _number(v) for k, v in result.statistics().items()})
    return out


def _one(key: str, a, b, tolerance: float, order: int) -> dict:
    """One figure's comparison (:func:`compare_figures`)."""
    if a is None or b is None:
        return {"value": a, "refined_value": b, "change": None, "relative_change": None, "error_estimate": None,
                "converged": False}
    change = b - a
    scale = max(abs(a), abs(b))
    rel = abs(change) / scale if scale > 0 else 0.0
    ratio = 2.0**order
    return {"value": a, "refined_value": b, "change": change, "relative_change": rel,
            # Richardson: the run's own error, and the refined run's, at the assumed order
            "error_estimate": -change * ratio / (ratio - 1.0), "refined_error_estimate": -change / (ratio - 1.0),
            "converged": bool(abs(change) <= tolerance * scale or abs(change) <= absolute_floor(key))}


def compare_figures(base: dict, refined: dict, tolerance: float = DEFAULT_TOLERANCE,
                    order: int = ASSUMED_ORDER) -> dict:
    """Each figure of a run against the same of its refined run.

    ``converged`` is True when the change is within ``tolerance`` of the larger of the two
    magnitudes, or within the figure's :func:`absolute_floor`; a figure missing from either run
    (None) is not converged. ``error_estimate`` is Richardson's estimate of the run's own
    discretization error at ``order`` in the refinement ratio 2, ``(value - refined) 2^p / (2^p - 1)``
    (the value minus the estimated limit), ``refined_error_estimate`` the refined run's.

    Parameters
    ----------
    base, refined : dict
        :func:`headline_figures` of the run and of its refined run.
    tolerance : float
        Relative tolerance [-].
    order : int
        Assumed order of convergence [-] (:data:`ASSUMED_ORDER`).

    Returns
    -------
    dict
        Name -> {value, refined_value, change, relative_change, error_estimate,
        refined_error_estimate, converged}.
    """
    return {k: _one(k, base[k], refined.get(k), tolerance, order) for k in base}


def unverified(keys=PEAK_KEYS) -> dict:
    """The flags of a run that was not verified: :data:`UNVERIFIED` for every figure.

    Parameters
    ----------
    keys : sequence of str
        The figures.

    Returns
    -------
    dict
    """
    return {k: UNVERIFIED for k in keys}


def verification_document(result) -> dict:
    """run.json's ``"verification"``: the run's ``verification``
    (:attr:`hosedrogue.results.run.RunResult.verification`), or ``{"status": "unverified"}`` with
    the note saying how to verify it.

    Parameters
    ----------
    result : hosedrogue.results.run.RunResult
        The run.

    Returns
    -------
    dict
    """
    if result.verification is None:
        return {"status": "unverified", "notes": [UNVERIFIED_NOTE]}
    return result.verification
