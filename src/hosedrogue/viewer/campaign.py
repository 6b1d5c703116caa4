"""The viewer of a campaign: a few of its runs run again and shown together.

A campaign keeps one row per run (``runs.csv``), not the runs' hoses. Each run is fixed by the
campaign's scenario (``campaign.json``) and its seed, so :func:`rerun` gives the same run again
(the same bits: docs/campaigns.md); :func:`representative_runs` picks, per controller, the runs
with the smallest, the median and the largest key figure (the miss distance of an engagement, the
peak radial drogue offset otherwise), and :func:`write_campaign_view` runs them, writes their
folders and the page.
"""

from __future__ import annotations

from pathlib import Path

from .page import write_view
from .runs import ViewRun

__all__ = ["representative_runs", "rerun", "write_campaign_view", "KEY_FIGURES"]

#: The figure that orders a campaign's runs: the engagement's miss at the coupler plane [m], the
#: fixed-length hose's peak radial drogue offset in the statistics window [m].
KEY_FIGURES = {"engagement": "miss_distance_m", "fixed-length": "peak_radial_m"}


def representative_runs(summary) -> list[dict]:
    """Per controller, the runs with the smallest, the median and the largest key figure
    (:data:`KEY_FIGURES`) among the completed runs that have it (all runs if none has).

    Parameters
    ----------
    summary : hosedrogue.studies.statistics.CampaignSummary
        The campaign (its ``settings`` and ``runs``).

    Returns
    -------
    list of dict
        ``run`` (index), ``controller``, ``seed``, ``figure`` (column name), ``value`` (its value
        [m], NaN where the run has none) and ``why`` ("smallest", "median", "largest"), without
        repeats.
    """
    import numpy as np

    key = KEY_FIGURES.get(summary.settings.get("model"), "peak_radial_m")
    picks, seen = [], set()
    df = summary.runs
    for controller in summary.settings["controllers"]:
        sub = df[df["controller"] == controller]
        good = sub[sub["completed"].astype(bool) & np.isfinite(sub[key].to_numpy(dtype=float))]
        rows = (good if len(good) else sub).sort_values([key, "run"], na_position="last")
        for why, i in (("smallest", 0), ("median", len(rows) // 2), ("largest", len(rows) - 1)):
            row = rows.iloc[i]
            if (int(row["run"]), controller) in seen:
                continue
            seen.add((int(row["run"]), controller))
            picks.append({"run": int(row["run"]), "controller": controller, "seed": int(row["seed"]), "figure": key,
                          "value": float(row[key]), "why": why})
    return picks


def rerun(settings: dict, seed: int, controller: str):
    """One run of a campaign again: its scenario (``campaign.json``) with the run's seed and controller.

    Parameters
    ----------
    settings : dict
        The campaign's ``campaign.json`` content (``CampaignSummary.settings``).
    seed : int
        The run's turbulence seed [-] (its ``runs.csv`` row).
    controller : str
        The run's controller type.

    Returns
    -------
    hosedrogue.results.run.RunResult
    """
    from ..scenarios import scenario_from_dict
    from ..scenarios.runner import run

    scenario = scenario_from_dict(settings["scenario"]).with_overrides(seed=seed).with_controller(controller)
    return run(scenario)


def write_campaign_view(summary, out: str | Path, folders: str | Path | None = None, **options) -> tuple[Path, list[dict]]:
    """Run a campaign's :func:`representative_runs` again and write their viewer page.

    Parameters
    ----------
    summary : hosedrogue.studies.statistics.CampaignSummary
        The campaign.
    out : str or pathlib.Path
        The HTML file to write.
    folders : str or pathlib.Path, optional
        Also write each run's folder here (``run_XXXXX_<controller>/``: time series, run.json,
        hose.npz, figure), for ``hosedrogue view`` and any other reader.
    **options
        Options of :func:`hosedrogue.viewer.view_html` (default layout: side by side).

    Returns
    -------
    (pathlib.Path, list of dict)
        The page and the runs shown (:func:`representative_runs`, with ``folder`` when written).
    """
    from ..scenarios.runner import write

    picks = representative_runs(summary)
    views = []
    for p in picks:
        result = rerun(summary.settings, p["seed"], p["controller"])
        label = f"run {p['run']} {p['controller']} ({p['why']} {p['figure'].removesuffix('_m').replace('_', ' ')})"
        if folders is not None:
            folder = Path(folders) / f"run_{p['run']:05d}_{p['controller']}"
            write(result, folder)
            p["folder"] = str(folder)
        views.append(ViewRun.from_result(result, label=label))
    options.setdefault("layout", "side")
    return write_view(views, out, **options), picks
