"""Statistics over a campaign's runs: ``summary.json``, ``summary.csv`` and the figures.

Per controller and statistic: mean, standard deviation, 95 % confidence interval of the mean
(Student t), median, 5th and 95th percentiles, count; and the fraction of runs that completed.
Statistics are over completed runs only (a run that stopped early has no displacement record for
the rest of its window); ``count`` says how many. Rows are sorted by controller order and run
index first, so the statistics do not depend on the order in which runs finished.
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import jsonio
from ..errors import ParameterError
from ..results.statistics import statistic_units
from .store import check_rows, csv_line, is_actuated, is_engagement, read_runs, read_settings, run_columns, write_atomic

#: Order of the engagement results in ``by_result`` (:meth:`hosedrogue.results.run.EngagementResult.capture_category`)
RESULTS = ("captured", "miss", "failed latch", "no contact", "stopped")


@dataclass(frozen=True)
class CampaignSummary:
    """What a campaign produced.

    ``statistics[controller][column]`` holds ``mean``, ``std``, ``ci95_mean`` (low, high),
    ``median``, ``p05``, ``p95``, ``count`` and ``unit`` (None where undefined, e.g. the standard
    deviation of one run); ``completed_fraction[controller]`` the fraction of runs that completed.
    """

    out_dir: Path  #: the campaign folder
    settings: dict  #: content of campaign.json
    runs: Any  #: pandas.DataFrame of runs.csv sorted by (controller, run)
    statistics: dict  #: controller -> column -> statistics (see above), in the column's unit
    completed_fraction: dict  #: controller -> fraction of its runs that completed [-]
    files: tuple  #: the files written (summary.json, summary.csv, figures)
    new_runs: int  #: runs executed by this call (the rest were resumed from runs.csv)
    #: engagement campaigns: rate, Wilson ci95, runs, by_result (:func:`capture_summary`); else None
    capture: dict | None = None
    #: summary.json's "verification" (:func:`hosedrogue.studies.campaign_verify.campaign_verification`); None: left out
    verification: dict | None = None

    def to_dict(self) -> dict:
        """The content of summary.json."""
        out = {} if self.capture is None else {"capture": self.capture}
        out |= {} if self.verification is None else {"verification": self.verification}
        return out | {
            "campaign": self.settings,
            "controllers": {
                c: {
                    "runs": int((self.runs["controller"] == c).sum()),
                    "completed_fraction": self.completed_fraction[c],
                    "statistics": self.statistics[c],
                }
                for c in self.settings["controllers"]
            },
        }


def describe(values: np.ndarray, confidence: float = 0.95) -> dict:
    """Mean, sample standard deviation, Student-t confidence interval of the mean, median, 5th and
    95th percentiles and count of the finite values (None where undefined).

    Parameters
    ----------
    values : array
        Sample, in any unit; non-finite values are ignored.
    confidence : float
        Confidence level of the interval [-].

    Returns
    -------
    dict
        ``count``, ``mean``, ``std``, ``ci95_mean`` ([low, high]), ``median``, ``p05``, ``p95``,
        in the unit of ``values``.
    """
    from scipy import stats

    x = np.asarray(values, dtype=np.float64)
    x = x[np.isfinite(x)]
    n = int(x.size)
    out: dict[str, Any] = {"count": n, "mean": None, "std": None, "ci95_mean": [None, None],
                           "median": None, "p05": None, "p95": None}
    if n == 0:
        return out
    mean = float(np.mean(x))
    out.update(mean=mean, median=float(np.median(x)), p05=float(np.percentile(x, 5)),
               p95=float(np.percentile(x, 95)))
    if n >= 2:
        std = float(np.std(x, ddof=1))
        half = float(stats.t.ppf(0.5 + confidence / 2, n - 1)) * std / math.sqrt(n)
        out.update(std=std, ci95_mean=[mean - half, mean + half])
    return out


def wilson_interval(successes: int, n: int, confidence: float = 0.95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion.

    From its definition: the proportions p whose score test ``|k/n - p| <= z sqrt(p (1 - p) / n)``
    does not reject, z the two-sided normal quantile. Squaring gives a quadratic in p with roots
    ``(phat + z^2/(2n) +- z sqrt(phat (1 - phat)/n + z^2/(4 n^2))) / (1 + z^2/n)``.

    Parameters
    ----------
    successes : int
        Number of successes k [-], 0 <= k <= n.
    n : int
        Number of trials [-], >= 1.
    confidence : float
        Confidence level [-], in (0, 1).

    Returns
    -------
    (float, float)
        Lower and upper bound of the proportion [-].
    """
    from scipy import stats

    if not (isinstance(n, (int, np.integer)) and n >= 1 and 0 <= successes <= n):
        raise ParameterError(f"successes, n = {successes!r}, {n!r}: need integers 0 <= successes <= n, n >= 1")
    z = float(stats.norm.ppf(0.5 + confidence / 2))
    phat = successes / n
    denom = 1.0 + z * z / n
    centre = (phat + z * z / (2 * n)) / denom
    half = z / denom * math.sqrt(phat * (1.0 - phat) / n + z * z / (4.0 * n * n))
    return max(0.0, centre - half), min(1.0, centre + half)


def intervals_overlap(a, b) -> bool:
    """Whether two confidence intervals overlap (share at least one point).

    As a significance test of two proportions, "the 95 % intervals do not overlap" is
    conservative: two independent rates whose intervals just touch differ at a level well below
    5 %, and for cells on the same seeds (common random numbers) a paired test would be sharper
    still. The docking studies call a difference significant only when the intervals are apart.

    Parameters
    ----------
    a, b : (float, float)
        The intervals' (low, high) bounds, in one unit (e.g. a rate [-]).

    Returns
    -------
    bool
        False when one interval lies wholly above the other.
    """
    (a_lo, a_hi), (b_lo, b_hi) = a, b
    return not (a_lo > b_hi or b_lo > a_hi)


def capture_summary(results) -> dict:
    """The ``"capture"`` block of an engagement campaign's summary.json.

    Parameters
    ----------
    results : sequence of str
        Each run's ``result`` (:data:`RESULTS`).

    Returns
    -------
    dict
        ``rate`` (captured / runs [-]), ``ci95`` (Wilson, [low, high] [-]), ``runs`` and
        ``by_result`` (result -> count).
    """
    results = list(results)
    n = len(results)
    by = {r: results.count(r) for r in RESULTS}
    by.update({r: results.count(r) for r in sorted(set(results) - set(RESULTS))})
    if n == 0:
        return {"rate": None, "ci95": [None, None], "runs": 0, "by_result": by}
    k = by["captured"]
    return {"rate": k / n, "ci95": list(wilson_interval(k, n)), "runs": n, "by_result": by}


def summarize_campaign(out_dir: str | Path, settings: dict | None = None, new_runs: int = 0,
                       plots: bool = True, verification: dict | None = None) -> CampaignSummary:
    """Compute the statistics from ``out_dir/runs.csv`` and write summary.json, summary.csv and the
    figures (histograms.png, cdf.png).

    Parameters
    ----------
    out_dir : str or Path
        The campaign folder.
    settings : dict, optional
        The campaign's settings (default: read campaign.json).
    new_runs : int
        Runs executed by the calling campaign (recorded in the summary).
    plots : bool
        Also write the figures.
    verification : dict, optional
        summary.json's ``"verification"`` block (:mod:`hosedrogue.studies.campaign_verify`);
        default: the block of the folder's summary.json, if it has one (summarizing a finished
        campaign again, e.g. to draw the figures of a campaign run with ``plots=False``, keeps
        what its run found).

    Returns
    -------
    CampaignSummary
    """
    import pandas as pd

    out = Path(out_dir)
    settings = settings if settings is not None else read_settings(out)
    if settings is None:
        raise ParameterError(f"out = {str(out)!r}: no campaign.json; not a campaign folder")
    if verification is None:
        verification = _previous_verification(out)
    radii = settings["capture_radii_m"]
    controllers = settings["controllers"]
    units = statistic_units(radii)
    engagement = is_engagement(settings)
    actuated = is_actuated(settings)
    rows = read_runs(out / "runs.csv", radii, engagement, actuated)
    check_rows(out / "runs.csv", rows, settings)  # a row not of this campaign is named, never counted
    order = {c: k for k, c in enumerate(controllers)}
    rows.sort(key=lambda r: (order[r["controller"]], r["run"]))
    table = pd.DataFrame(rows, columns=run_columns(radii, engagement, actuated))

    statistics, completed = {}, {}
    csv_rows = []
    for c in controllers:
        sub = table[table["controller"] == c]
        ok = sub[sub["completed"].astype(bool)]
        completed[c] = float(len(ok) / len(sub)) if len(sub) else None
        statistics[c] = {}
        for col, unit in units.items():
            d = {"unit": unit, **describe(ok[col].to_numpy(dtype=np.float64))}
            statistics[c][col] = d
            csv_rows.append({"controller": c, "statistic": col, "unit": unit, "count": d["count"],
                             "mean": d["mean"], "std": d["std"], "ci95_low": d["ci95_mean"][0],
                             "ci95_high": d["ci95_mean"][1], "median": d["median"], "p05": d["p05"],
                             "p95": d["p95"], "completed_fraction": completed[c]})
    files = []
    capture = capture_summary(table["result"]) if engagement else None
    summary = CampaignSummary(out, settings, table, statistics, completed, (), new_runs, capture, verification)
    write_atomic(out / "summary.json", jsonio.dumps(summary.to_dict(), indent=2) + "\n")
    files.append(out / "summary.json")
    columns = list(csv_rows[0]) if csv_rows else []
    text = csv_line(columns) + "".join(
        csv_line("" if r[k] is None else r[k] for k in columns) for r in csv_rows)
    write_atomic(out / "summary.csv", text)
    files.append(out / "summary.csv")
    if plots and len(table):
        # matplotlib on first use: a campaign's worker processes import this module and draw nothing
        from ..plotting.campaign import plot_cdf, plot_histograms
        from ..plotting.figures import save_figure

        files.append(save_figure(plot_histograms(table, controllers, radii), out / "histograms.png"))
        files.append(save_figure(plot_cdf(table, controllers, radii), out / "cdf.png"))
        if engagement:
            files.append(save_figure(_miss_figure(table, settings, capture), out / "miss_cdf.png"))
    return dataclasses.replace(summary, files=tuple(files))


def _previous_verification(out: Path) -> dict | None:
    """The ``"verification"`` block of ``out/summary.json`` (None: no summary, or none in it)."""
    try:
        return json.loads((out / "summary.json").read_text()).get("verification")
    except (OSError, ValueError, AttributeError):
        return None


def _miss_figure(table, settings: dict, capture: dict):
    """The miss-distance CDF of an engagement campaign, its capture radius from the scenario."""
    from ..plotting.campaign import plot_miss_cdf
    from ..spec.sections import Probe

    probe = settings["scenario"].get("probe") or {}
    radius = probe.get("capture_radius_m", Probe().capture_radius_m)
    lo, hi = capture["ci95"]
    title = (f"capture rate {capture['rate']:.3f} (Wilson 95 %: {lo:.3f}-{hi:.3f}) over {capture['runs']} runs"
             if capture["runs"] else "")
    return plot_miss_cdf(table["miss_distance_m"].to_numpy(dtype=np.float64), radius, title)
