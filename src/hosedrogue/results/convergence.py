"""Which peak loads of an engagement run are converged with the link count, and why the others
are not (docs/engagement.md, "Link-count convergence"): the rule behind ``run.json``'s
``"converged"``, ``peak_tension_converged`` and ``notes``
(:meth:`hosedrogue.results.run.EngagementResult.summary`).

The rule is physical, read from a run's own histories, and was established by doubling the
links of the shipped engagement scenarios (160 -> 320 links of 0.1 m):

* rigid links: when the hose went slack (:func:`went_slack`) its tension peaks are the
  discretization-set impulses of an inextensible chain; the probe load and the slack converge;
* elastic links on links no longer than :data:`RESOLVED_LINK_M`: a hose still slack at the end
  of the run (:func:`flailing`: a loop flailing in the air stream, chaotic) has only its slack
  converged: a micrometre's change of the probe's path moves its peak exit tension by 40 % and its
  probe load by 8.5 %, its slack by 0.17 % (``benchmarks/locked_reel_chaos.py``); a hose that went slack and snapped taut has its exit tension, its rise and the probe
  load converged (the axial damping smooths the snap's wave on its way to the exit), not its
  drogue-end tension (made where the last slack goes out); otherwise every peak is converged;
* elastic links on longer links: none is claimed converged.
"""

from __future__ import annotations

import numpy as np

__all__ = ["PEAK_KEYS", "SLACK_TENSION_FRACTION", "RESOLVED_LINK_M", "FLAIL_SLACK_M", "FLAIL_WINDOW_S",
           "went_slack", "flailing", "converged_peaks"]

#: The peaks whose convergence with the link count a run reports (``"converged"`` in its summary).
PEAK_KEYS = ("peak_exit_tension_n", "peak_tension_rise_n", "peak_drogue_tension_n", "peak_probe_load_n", "peak_slack_m")

#: The hose counts as gone slack when its exit tension falls below this fraction of the steady
#: trail tension (the exit tension at the start, at the balance position) [-].
SLACK_TENSION_FRACTION = 0.1

#: Elastic links: the hose flails when its slack stays above FLAIL_SLACK_M [m] (ten times the ~1
#: cm sag of the steady trail, five times the responsive reel's dead band) over the run's last
#: FLAIL_WINDOW_S [s].
FLAIL_SLACK_M, FLAIL_WINDOW_S = 0.1, 1.0

#: Elastic links: the longest link [m] at which the peaks were shown to converge (the shipped
#: engagements, 160 -> 320 links of a 16 m hose); a coarser run claims none.
RESOLVED_LINK_M = 0.1

#: ``notes`` entry of a rigid run in which the hose went slack.
SLACK_NOTE = ("the hose went slack (exit tension below 10 % of the steady trail tension): peak_exit_tension_n "
              "and min_exit_tension_n are snap spikes of an inextensible link chain and are not converged "
              "with the link count (docs/engagement.md). The peak probe load and the peak slack of the shipped "
              "scenarios change by less than 5 % when their links are doubled")
#: ``notes`` entry of an elastic run whose hose is still slack at its end.
FLAIL_NOTE = ("the hose is still slack at the end of the run (a loop flailing in the air stream): a chaotic "
              "motion whose tension and probe load peaks change with every change of the mesh, the step or the "
              "probe's path (a micrometre moves the peak exit tension by 40 %); of the peaks only peak_slack_m "
              "is converged (docs/engagement.md, \"Link-count convergence\")")
#: ``notes`` entry of an elastic run whose hose went slack and snapped taut again.
SNAP_NOTE = ("the hose went slack and snapped taut: the snap's tension wave is smoothed by the axial damping on "
             "its way to the exit, so peak_exit_tension_n, peak_tension_rise_n and the probe load are converged "
             "with the link count, peak_drogue_tension_n (the snap at the drogue end) is not (docs/engagement.md)")
#: ``notes`` entry of an elastic run on links longer than :data:`RESOLVED_LINK_M`.
COARSE_NOTE = ("the links are longer than the 0.1 m at which the engagements' peaks were shown to converge "
               "(docs/engagement.md, \"Link-count convergence\"): no peak is claimed converged")


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


def converged_peaks(t_s, exit_tension_n, slack_m, link_length_m: float, elastic: bool) -> tuple[dict, list]:
    """Which peaks of :data:`PEAK_KEYS` are converged with the link count, and the notes on why the
    others are not (the module's rule).

    Parameters
    ----------
    t_s, exit_tension_n, slack_m : array (N,)
        Output times [s], exit tension [N] and slack [m].
    link_length_m : float
        The run's link length [m] (hose length over links at the start).
    elastic : bool
        Elastic links (finite axial stiffness).

    Returns
    -------
    converged : dict
        Peak key -> bool.
    notes : list of str
    """
    slack = went_slack(exit_tension_n)
    if not elastic:
        return {k: not slack or k in PEAK_KEYS[3:] for k in PEAK_KEYS}, [SLACK_NOTE] if slack else []
    if link_length_m > RESOLVED_LINK_M * (1.0 + 1e-9):
        return {k: False for k in PEAK_KEYS}, [COARSE_NOTE]
    if flailing(t_s, slack_m):
        return {k: k == "peak_slack_m" for k in PEAK_KEYS}, [FLAIL_NOTE]
    flags = {k: True for k in PEAK_KEYS}
    flags["peak_drogue_tension_n"] = not slack
    return flags, [SNAP_NOTE] if slack else []
