"""Run an engagement scenario (``[reel]`` and/or ``[probe]`` sections) and write its files:
``timeseries.csv`` (SI units), ``run.json`` (with the ``"engagement"`` summary) and
``engagement.png`` (time histories)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .. import __version__
from .driver import EngagementResult, simulate_engagement
from .spec import Reel

#: Keys of run.json's "engagement" object (ENGAGEMENT.md 4).
SUMMARY_KEYS = ("result", "miss_distance_m", "closure_speed_m_s", "peak_probe_load_n", "peak_exit_tension_n",
                "peak_slack_m", "peak_drogue_excursion_m")


def run_engagement(scenario) -> EngagementResult:
    """Simulate an engagement scenario; the result's ``meta`` records what was run."""
    reel = scenario.extra.get("reel", Reel())
    probe = scenario.extra.get("probe")
    result = simulate_engagement(scenario.params, reel, probe, scenario.duration_s)
    result.meta.update({"scenario": scenario.name, "source": scenario.source, "duration_s": scenario.duration_s,
                        "params": scenario.params.to_dict()})
    return result


def engagement_summary(result: EngagementResult) -> dict:
    """The run's ``"engagement"`` object: the brief's keys first, then the supporting figures."""
    o = result.outcome
    out = {k: o.get(k) for k in SUMMARY_KEYS}
    out.update({k: v for k, v in o.items() if k not in out})
    return out


def write_engagement(result: EngagementResult, out_dir: Path, plot: bool = True) -> list[Path]:
    """Write ``timeseries.csv``, ``run.json`` and (optionally) ``engagement.png`` to out_dir."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = [result.to_csv(out_dir / "timeseries.csv")]
    meta = dict(result.meta)
    events = meta.pop("events", [])
    doc = {
        "package": "hosedrogue",
        "version": __version__,
        "completed": result.completed,
        "message": result.message,
        "t_end_s": float(result.t_s[-1]) if result.t_s.size else 0.0,
        "equilibrium_drogue_position_m": np.asarray(result.equilibrium_m).tolist(),
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
