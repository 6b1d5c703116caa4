"""Run an engagement scenario (``[reel]`` and/or ``[probe]`` sections) and write its files:
``timeseries.csv`` (SI units), ``run.json`` (with the ``"engagement"`` summary) and
``engagement.png`` (time histories)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..params import Actuator, Sensor
from ..results import run_header
from .driver import EngagementResult, simulate_engagement
from .spec import Reel

#: Keys of run.json's "engagement" object (docs/engagement.md, "What a run reports").
SUMMARY_KEYS = ("result", "miss_distance_m", "closure_speed_m_s", "peak_probe_load_n", "peak_exit_tension_n",
                "peak_slack_m", "peak_drogue_excursion_m", "peak_control_force_n")

#: Designed drogue controllers of this process, by design key (:func:`engagement_controller`).
_DESIGNS: dict = {}


def engagement_controller(scenario):
    """The scenario's drogue controller, designed as the fixed-length scenarios design it
    (:func:`hosedrogue.controllers.design.design_controller` on the fixed-length model of the
    same parameters, which is the engagement's initial chain), once per process: the design is
    kept by its key (parameters without the turbulence, which the design does not use; controller
    type and options), so a campaign designs it once per worker, and every run gets the same one.

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        Its ``controller`` ("none", "pid", "lqr"), ``controller_options`` and ``params``.

    Returns
    -------
    LinearController or None
        Measured drogue offset [m] -> force [N]; None for "none".
    """
    if scenario.controller == "none":
        return None
    steady = {k: v for k, v in scenario.params.to_dict().items() if k != "turbulence"}
    key = json.dumps([steady, scenario.controller, scenario.controller_options], sort_keys=True, default=repr)
    if key not in _DESIGNS:
        from ..controllers.design import design_controller

        _DESIGNS[key] = design_controller(scenario.controller, scenario.controller_options, scenario.params)
    return _DESIGNS[key]


def run_engagement(scenario) -> EngagementResult:
    """Simulate an engagement scenario; the result's ``meta`` records what was run.

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        Its ``params``, ``duration_s`` [s], the ``reel`` / ``probe`` / ``bow_wave`` / ``pilot``
        sections in ``extra`` (default reel, no probe, no bow wave, no pilot when absent) and its
        ``controller`` with ``actuator`` and ``sensor`` (:func:`engagement_controller`).

    Returns
    -------
    EngagementResult
    """
    reel = scenario.extra.get("reel", Reel())
    probe = scenario.extra.get("probe")
    pilot = scenario.extra.get("pilot")
    result = simulate_engagement(scenario.params, reel, probe, scenario.duration_s,
                                 bow_wave=scenario.extra.get("bow_wave"), control=engagement_controller(scenario),
                                 actuator=Actuator(**scenario.actuator), sensor=Sensor(**scenario.sensor),
                                 pilot=pilot)
    result.meta.update({"scenario": scenario.name, "source": scenario.source, "duration_s": scenario.duration_s,
                        "controller": scenario.controller, "controller_options": scenario.controller_options,
                        "actuator": scenario.actuator, "sensor": scenario.sensor,
                        "pilot": None if pilot is None else _plain(pilot),
                        "params": scenario.params.to_dict()})
    return result


def _plain(section) -> dict:
    from .spec import plain

    return plain(section)


#: The hose counts as gone slack when its exit tension falls below this fraction of the steady
#: trail tension (the exit tension at the start, at the balance position).
SLACK_TENSION_FRACTION = 0.1


def went_slack(result: EngagementResult) -> bool:
    """Whether the hose went (nearly) slack: the exit tension fell below
    :data:`SLACK_TENSION_FRACTION` of the steady trail tension. Then the hose whips, and the
    exit-tension spikes when it snaps taut again are not converged with the link count
    (docs/engagement.md; the shipped scenarios' minimum exit tension: locked reel -1.9 kN,
    responsive reel 38 N, of a 1.53 kN trail tension; the constant-tension reel keeps 551 N and
    all its peaks converge).

    Parameters
    ----------
    result : EngagementResult
        The run (its exit tension [N]; the first sample is the steady trail tension).

    Returns
    -------
    bool
    """
    T = np.asarray(result.exit_tension_n)
    return bool(T.size and np.min(T) < SLACK_TENSION_FRACTION * T[0])


#: ``notes`` entry of a run in which the hose went slack (:func:`went_slack`).
SLACK_NOTE = ("the hose went slack (exit tension below 10 % of the steady trail tension): peak_exit_tension_n "
              "and min_exit_tension_n are snap spikes of an inextensible link chain and are not converged "
              "with the link count (docs/engagement.md). The peak probe load and the peak slack of the shipped "
              "scenarios change by less than 5 % when their links are doubled")


def engagement_summary(result: EngagementResult) -> dict:
    """The run's ``"engagement"`` object: the brief's keys first, then the supporting figures,
    ``peak_tension_converged`` and ``notes`` (what not to read as converged).

    Parameters
    ----------
    result : EngagementResult
        The run.

    Returns
    -------
    dict
        Outcome keys with their units in the names (``miss_distance_m``, ``peak_probe_load_n``, ...).
    """
    o = result.outcome
    out = {k: o.get(k) for k in SUMMARY_KEYS}
    out.update({k: v for k, v in o.items() if k not in out})
    slack = went_slack(result)
    out["peak_tension_converged"] = not slack
    out["notes"] = [SLACK_NOTE] if slack else []
    return out


def write_engagement(result: EngagementResult, out_dir: Path, plot: bool = True) -> list[Path]:
    """Write ``timeseries.csv``, ``run.json`` and (optionally) ``engagement.png`` to out_dir.

    Parameters
    ----------
    result : EngagementResult
        The run.
    out_dir : str or pathlib.Path
        Output folder, created if missing.
    plot : bool
        Also write the time-history figure.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = [result.to_csv(out_dir / "timeseries.csv")]
    meta = dict(result.meta)
    events = meta.pop("events", [])
    doc = {
        **run_header(result),
        "engagement": engagement_summary(result),
        "events": events,
        **meta,
    }
    (out_dir / "run.json").write_text(json.dumps(doc, indent=2, default=float) + "\n")
    paths.append(out_dir / "run.json")
    if plot and result.t_s.size > 1:
        from ..plotting.engagement import plot_engagement_history
        from ..plotting.figures import save_figure

        paths.append(save_figure(plot_engagement_history({result.meta.get("scenario", "run"): result}),
                                 out_dir / "engagement.png"))
    return paths
