"""Tables and findings over the docking campaigns (:func:`hosedrogue.studies.docking.run_grid`):
the capture table of the main grid and its comparisons, the closure-speed study's table and
findings, the force-limit study's table, saturation and findings, and the actuated-drogue study's
table (docs/engagement.md, "Docking statistics").

Every table has one row per cell with the campaign's capture block (``runs``, ``rate``,
``ci95_low``, ``ci95_high``, ``n_<result>`` counts) and is checked to count every run once. A
difference of two rates is called significant when their Wilson 95 % intervals are apart
(:func:`hosedrogue.studies.statistics.intervals_overlap`: conservative).

Saturation (force-limit study) is read from runs.csv: the two per-axis peaks of
:data:`hosedrogue.results.statistics.FORCE_STATISTICS` are ``max |u_y|`` and ``max |u_z|`` of the applied
(clipped) force over the turbulence window, which in the docking cells is the whole run, and the
third is ``max hypot(u_y, u_z)``, the magnitude. A per-axis limit is reached by a per-axis peak,
not by the magnitude (a magnitude above the limit can have neither axis clipped), so a run counts
as saturated when its larger per-axis peak is at least ``1 - SATURATION_TOLERANCE`` times the limit.
"""

from __future__ import annotations

import math

import numpy as np

from ..results.statistics import FORCE_STATISTICS
from .docking_grid import CONTROLLERS, LEVELS, PILOT
from .statistics import intervals_overlap

__all__ = ["SATURATION_TOLERANCE", "PEAK_FORCE_Y", "PEAK_FORCE_Z", "PEAK_FORCE", "capture_columns", "capture_table",
           "compare", "comparisons", "speed_table", "speed_findings", "axis_peaks", "saturated", "force_table",
           "force_findings", "actuator_table"]

#: runs.csv columns of the per-axis peak forces (lateral, vertical) and of the magnitude's peak [N].
PEAK_FORCE_Y, PEAK_FORCE_Z, PEAK_FORCE = (name for name, _unit in FORCE_STATISTICS)

#: A run's force saturated when its per-axis peak is within this fraction below the limit [-].
SATURATION_TOLERANCE = 1e-3


def capture_columns(capture: dict) -> dict:
    """A campaign's capture block as table columns: runs, rate, ci95_low, ci95_high, n_<result>.

    Parameters
    ----------
    capture : dict
        The summary's capture block (rate [-], ci95 [-], runs, by_result).

    Returns
    -------
    dict
    """
    return dict(runs=capture["runs"], rate=capture["rate"], ci95_low=capture["ci95"][0], ci95_high=capture["ci95"][1],
                **{f"n_{k.replace(' ', '_')}": v for k, v in capture["by_result"].items()})


def _checked(df, what: str):
    """``df`` after checking that its ``n_<result>`` counts add up to the runs of every row."""
    if not (df[[k for k in df.columns if k.startswith("n_")]].sum(axis=1) == df["runs"]).all():
        raise RuntimeError(f"{what}: the result counts do not add up to the runs of every cell")
    return df


def capture_table(cells):
    """One row per campaign of the main grid: the cell, its capture block, the median miss and the
    runs' peak control force (the controllers' forces are unlimited there: what the rate costs).

    Parameters
    ----------
    cells : sequence of hosedrogue.studies.docking.CampaignCell
        The campaigns.

    Returns
    -------
    pandas.DataFrame
        Columns campaign, level, sigma_m_s [m/s], controller, pilot, bow_wave, runs, rate [-],
        ci95_low, ci95_high [-], n_<result>, median_miss_m [m] and {median,p95,max}_peak_force_n [N].
    """
    import pandas as pd

    rows = []
    for c in cells:
        miss, force = c.runs["miss_distance_m"], c.runs[PEAK_FORCE]
        rows.append(dict(campaign=c.name, level=c.level, sigma_m_s=c.sigma_m_s, controller=c.controller,
                         pilot=c.pilot, bow_wave=c.bow_wave, **capture_columns(c.capture),
                         median_miss_m=float(np.nanmedian(miss)) if np.isfinite(miss).any() else float("nan"),
                         median_peak_force_n=float(np.median(force)), p95_peak_force_n=float(np.percentile(force, 95)),
                         max_peak_force_n=float(np.max(force))))
    return _checked(pd.DataFrame(rows), "docking")


def _pair(a, b) -> dict:
    """The rates and intervals of two table rows, and whether the intervals are apart."""
    ci_a, ci_b = [float(a["ci95_low"]), float(a["ci95_high"])], [float(b["ci95_low"]), float(b["ci95_high"])]
    return {"rate_a": float(a["rate"]), "ci95_a": ci_a, "rate_b": float(b["rate"]), "ci95_b": ci_b,
            "significant": not intervals_overlap(ci_a, ci_b)}


def _row(df, sel: dict):
    """The first row of ``df`` whose columns have the values of ``sel`` (None if there is none)."""
    m = np.ones(len(df), bool)
    for k, v in sel.items():
        m &= (df[k] == v).to_numpy()
    return df[m].iloc[0] if m.any() else None


def compare(df, a: dict, b: dict) -> dict:
    """The rates of two cells of a table, their intervals and whether they differ significantly.

    Parameters
    ----------
    df : pandas.DataFrame
        A table of :func:`capture_table`.
    a, b : dict
        Column -> value selecting one row each (the first that matches).

    Returns
    -------
    dict
        ``rate_a``, ``ci95_a``, ``rate_b``, ``ci95_b`` [-], ``a_higher`` and ``significant`` (the
        intervals apart).

    Raises
    ------
    ParameterError
        When no row matches ``a`` or ``b``.
    """
    from ..errors import ParameterError

    ra, rb = _row(df, a), _row(df, b)
    for name, sel, r in (("a", a, ra), ("b", b, rb)):
        if r is None:
            raise ParameterError(f"{name} = {sel!r}: no such cell in the table")
    pair = _pair(ra, rb)
    return {**{k: pair[k] for k in ("rate_a", "ci95_a", "rate_b", "ci95_b")}, "a_higher": bool(ra["rate"] > rb["rate"]),
            "significant": pair["significant"]}


def _statements(df) -> list:
    """The (key, a, b) selections of :func:`comparisons`, in order."""
    levels = [lev for lev in LEVELS if lev in set(df["level"])]
    mid = "moderate" if "moderate" in levels else levels[0]

    def cell(level, controller="none", bow_wave=True, pilot=False):
        return dict(level=level, controller=controller, bow_wave=bow_wave, pilot=pilot)

    out = [("light_vs_severe", cell(levels[0]), cell(levels[-1]))] if len(levels) > 1 else []
    out += [(f"{c}_vs_none_{mid}", cell(mid, c), cell(mid)) for c in CONTROLLERS[1:]]
    out.append((f"bow_off_vs_on_{mid}", cell(mid, bow_wave=False), cell(mid)))
    out += [(f"{PILOT}_vs_none_{lev}", cell(lev, pilot=True), cell(lev)) for lev in levels]
    return out


def comparisons(df) -> dict:
    """The grid's statements whose two cells are in the table: the lightest against the severest
    level (no controller), each controller against none in moderate turbulence (else the lightest
    level of the table), the bow wave off against on there, and the pilot against the
    straight-line probe per level (all with the bow wave on but the one it is off in).

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`capture_table` of a grid of :func:`hosedrogue.studies.docking_grid.grid_specs`.

    Returns
    -------
    dict
        ``"light_vs_severe"``, ``"<controller>_vs_none_<level>"``, ``"bow_off_vs_on_<level>"``,
        ``"pilot_vs_none_<level>"`` -> :func:`compare`.
    """
    return {key: compare(df, a, b) for key, a, b in _statements(df)
            if _row(df, a) is not None and _row(df, b) is not None}


def speed_table(specs, cells):
    """One row per (controller, speed): the campaign, its capture block, the failed-latch fraction
    and the closure speed at the coupler over the runs that reached it.

    Parameters
    ----------
    specs : sequence of hosedrogue.studies.docking_grid.CellSpec
        The cells of :func:`hosedrogue.studies.docking_grid.speed_specs`.
    cells : sequence of hosedrogue.studies.docking.CampaignCell
        Their campaigns, in the same order.

    Returns
    -------
    pandas.DataFrame
        Columns controller, probe_speed_m_s [m/s], duration_s [s], campaign, runs, rate, ci95_low,
        ci95_high [-], n_<result>, failed_latch_fraction [-], coupler_speed_{p05,median,p95}_m_s
        [m/s], coupler_to_probe_speed (median ratio) [-], median_miss_m [m].
    """
    import pandas as pd

    rows = []
    for spec, c in zip(specs, cells):
        cap = c.capture
        vc = c.runs["closure_speed_m_s"].to_numpy(dtype=float)
        vc = vc[np.isfinite(vc)]
        p05, med, p95 = np.percentile(vc, [5, 50, 95]) if vc.size else (np.nan,) * 3
        miss = c.runs["miss_distance_m"].to_numpy(dtype=float)
        rows.append(dict(controller=spec.controller, probe_speed_m_s=c.closure_speed_m_s, duration_s=c.duration_s,
                         campaign=c.name, **capture_columns(cap),
                         failed_latch_fraction=cap["by_result"]["failed latch"] / cap["runs"],
                         coupler_speed_p05_m_s=p05, coupler_speed_median_m_s=med, coupler_speed_p95_m_s=p95,
                         coupler_to_probe_speed=med / c.closure_speed_m_s,
                         median_miss_m=float(np.nanmedian(miss)) if np.isfinite(miss).any() else np.nan))
    return _checked(pd.DataFrame(rows), "docking closure speed")


def _trend(rates) -> str:
    steps = np.diff(rates)
    return ("rises at every step" if np.all(steps > 0) else
            "never falls" if np.all(steps >= 0) else "does not change monotonically")


def speed_findings(df, min_latch_m_s: float, reference_m_s: float = 1.0) -> dict:
    """What the closure speed does, per controller: the slowest speed's failed latches and
    coupler speed against the latch minimum, the slowest and fastest speed against the reference,
    the rate's trend with speed, and the coupler-to-probe speed ratio's range.

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`speed_table`.
    min_latch_m_s : float
        The latch window's minimum closure speed at the coupler [m/s].
    reference_m_s : float
        The reference speed [m/s] (the study's speed nearest it; the shipped scenarios' 1 m/s).

    Returns
    -------
    dict
        controller -> findings (rates [-], speeds [m/s], counts, "significant" flags).
    """
    out = {}
    for c, sub in df.groupby("controller", sort=False):
        sub = sub.sort_values("probe_speed_m_s").reset_index(drop=True)
        slow, fast = sub.iloc[0], sub.iloc[-1]
        ref = sub.iloc[int(np.argmin(np.abs(sub["probe_speed_m_s"] - reference_m_s)))]
        out[c] = {"slowest_m_s": float(slow["probe_speed_m_s"]), "fastest_m_s": float(fast["probe_speed_m_s"]),
                  "reference_m_s": float(ref["probe_speed_m_s"]),
                  "slowest_failed_latches": int(slow["n_failed_latch"]), "runs": int(slow["runs"]),
                  "slowest_coupler_median_m_s": float(slow["coupler_speed_median_m_s"]),
                  "slowest_below_latch_minimum": bool(slow["coupler_speed_median_m_s"] < min_latch_m_s),
                  "slowest_vs_reference": _pair(slow, ref), "fastest_vs_reference": _pair(fast, ref),
                  "trend": _trend(sub["rate"].to_numpy()),
                  "coupler_to_probe_range": [float(sub["coupler_to_probe_speed"].min()),
                                             float(sub["coupler_to_probe_speed"].max())]}
    return out


def axis_peaks(runs) -> np.ndarray:
    """Each run's larger per-axis peak control force [N]: ``max(max |u_y|, max |u_z|)``.

    Parameters
    ----------
    runs : pandas.DataFrame
        A campaign's runs.csv.

    Returns
    -------
    numpy.ndarray
        One value per run [N].
    """
    return np.maximum(runs[PEAK_FORCE_Y].to_numpy(dtype=float), runs[PEAK_FORCE_Z].to_numpy(dtype=float))


def saturated(runs, limit_n: float) -> np.ndarray:
    """Which runs' per-axis peak force reached the limit within :data:`SATURATION_TOLERANCE`.

    Parameters
    ----------
    runs : pandas.DataFrame
        A campaign's runs.csv.
    limit_n : float
        The force limit per axis [N] (inf: none saturates).

    Returns
    -------
    numpy.ndarray of bool
        One flag per run.
    """
    return axis_peaks(runs) >= (1.0 - SATURATION_TOLERANCE) * limit_n


def force_table(specs, cells):
    """One row per cell: level, controller, limit (inf: unlimited; for "none" the rate of no
    controller), the campaign, its capture block, the saturated fraction and the peak forces.

    Parameters
    ----------
    specs : sequence of hosedrogue.studies.docking_grid.CellSpec
        The cells of :func:`hosedrogue.studies.docking_grid.force_specs`.
    cells : sequence of hosedrogue.studies.docking.CampaignCell
        Their campaigns, in the same order.

    Returns
    -------
    pandas.DataFrame
        Columns level, controller, max_force_n [N] (inf: unlimited), campaign, runs, rate,
        ci95_low, ci95_high [-], n_<result>, saturated_fraction [-] (NaN unlimited),
        peak_axis_force_{median,p95,max}_n (per-axis peak, max of the two axes) [N] and
        peak_force_max_n (magnitude) [N].
    """
    import pandas as pd

    rows = []
    for spec, c in zip(specs, cells):
        runs = c.runs
        limit = math.inf if spec.max_force_n is None else float(spec.max_force_n)
        axis = axis_peaks(runs)
        rows.append(dict(level=spec.level, controller=spec.controller, max_force_n=limit, campaign=c.name,
                         **capture_columns(c.capture),
                         saturated_fraction=float(np.mean(saturated(runs, limit))) if math.isfinite(limit) else np.nan,
                         peak_axis_force_median_n=float(np.median(axis)),
                         peak_axis_force_p95_n=float(np.percentile(axis, 95)),
                         peak_axis_force_max_n=float(np.max(axis)),
                         peak_force_max_n=float(np.max(runs[PEAK_FORCE].to_numpy(dtype=float)))))
    return _checked(pd.DataFrame(rows), "docking force limit")


def _rate_of(r) -> dict:
    return {"rate": float(r["rate"]), "ci95": [float(r["ci95_low"]), float(r["ci95_high"])]}


def _overlap(a, b) -> bool:
    return intervals_overlap((a["ci95_low"], a["ci95_high"]), (b["ci95_low"], b["ci95_high"]))


def _limit_findings(sub, none) -> dict:
    """One controller at one level: its limited cells against the unlimited and the no-controller one."""
    free = sub[~np.isfinite(sub["max_force_n"])].iloc[0]
    lim = sub[np.isfinite(sub["max_force_n"])].sort_values("max_force_n").reset_index(drop=True)
    ok = [_overlap(r, free) for _, r in lim.iterrows()]
    first = next((i for i in range(len(ok)) if all(ok[i:])), None)
    low = lim.iloc[0]
    return {
        "unlimited": _rate_of(free), "none": _rate_of(none),
        "overlap_reached": first is not None,  # report.json holds no nulls: the two keys below only then
        **({} if first is None else {"overlap_from_n": float(lim.iloc[first]["max_force_n"]),
                                     "overlap_saturated_fraction": float(lim.iloc[first]["saturated_fraction"])}),
        "smallest_n": float(low["max_force_n"]), "smallest": _rate_of(low),
        "smallest_saturated_fraction": float(low["saturated_fraction"]),
        "smallest_vs_none": {"higher": bool(low["rate"] > none["rate"]), "significant": not _overlap(low, none)},
        "unlimited_p95_axis_force_n": float(free["peak_axis_force_p95_n"])}


def force_findings(df) -> dict:
    """Per level and controller: the unlimited and no-controller rates, the smallest limit from
    which every larger limit's interval overlaps the unlimited rate's, and the smallest limit's
    rate against no controller.

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`force_table`.

    Returns
    -------
    dict
        ``"<level>-<controller>"`` -> findings (rates [-], limits [N], saturated fractions [-],
        "significant" flags).
    """
    out = {}
    for level, lev in df.groupby("level", sort=False):
        none = lev[lev["controller"] == "none"].iloc[0]
        for c, sub in lev[lev["controller"] != "none"].groupby("controller", sort=False):
            out[f"{level}-{c}"] = {"level": level, "controller": c, **_limit_findings(sub, none)}
    return out


def actuator_table(specs, cells):
    """One row per cell of the actuated-drogue study: level, controller, deflection limit [deg]
    and servo bandwidth [Hz] (inf, inf: the ideal force), the campaign, its capture block, the
    fraction of runs in which some surface reached its deflection limit, the median fraction of
    the run it spent there, and the peak forces.

    Parameters
    ----------
    specs : sequence of hosedrogue.studies.docking_grid.CellSpec
        The cells of :func:`hosedrogue.studies.docking_grid.actuator_specs`.
    cells : sequence of hosedrogue.studies.docking.CampaignCell
        Their campaigns, in the same order.

    Returns
    -------
    pandas.DataFrame
        Columns level, controller, max_deflection_deg, bandwidth_hz, campaign, runs, rate, ci95_low,
        ci95_high [-], n_<result>, saturated_runs_fraction [-] (NaN ideal), saturated_time_median [-],
        rate_saturated_runs_fraction [-], peak_axis_force_{median,p95}_n [N], stopped (runs that
        stopped early: a diverging loop).
    """
    import pandas as pd

    rows = []
    for spec, c in zip(specs, cells):
        runs = c.runs
        s = spec.surfaces
        axis = axis_peaks(runs)
        row = dict(level=spec.level, controller=spec.controller,
                   max_deflection_deg=math.inf if s is None else s.max_deflection_deg,
                   bandwidth_hz=math.inf if s is None else s.bandwidth_hz, campaign=c.name,
                   **capture_columns(c.capture), peak_axis_force_median_n=float(np.median(axis)),
                   peak_axis_force_p95_n=float(np.percentile(axis, 95)),
                   stopped=int((~runs["completed"].astype(bool)).sum()))
        if s is None or "deflection_saturated_frac" not in runs:
            row.update(saturated_runs_fraction=math.nan, saturated_time_median=math.nan,
                       rate_saturated_runs_fraction=math.nan)
        else:
            sat = runs["deflection_saturated_frac"].to_numpy(dtype=float)
            row.update(saturated_runs_fraction=float(np.mean(sat > 0)), saturated_time_median=float(np.median(sat)),
                       rate_saturated_runs_fraction=float(np.mean(runs["rate_saturated_frac"].to_numpy(dtype=float) > 0)))
        rows.append(row)
    return _checked(pd.DataFrame(rows), "docking actuated drogue")
