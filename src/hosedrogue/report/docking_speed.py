"""The "Docking" section's closure-speed study: the capture rate of approach-moderate (bow wave on)
against the probe's closure speed, without a drogue controller and with the paper's PID
(docs/engagement.md, "Docking statistics").

Each speed is a campaign of the grid (:class:`.docking_runs.CellSpec` with ``closure_speed_m_s``)
whose scenario lasts :func:`.docking_runs.approach_duration_s`: the shipped 4.5 s at 1 m/s, so
that cell *is* the main grid's ``moderate-<controller>-bow-on`` campaign (:func:`.docking_runs.run_grid`
runs a scenario once). This module builds the table, the CSVs, the figure, the HTML and
``report.json["docking"]["closure_speed"]`` from those campaigns; every number on the page is read
from them.

The turbulence window follows the duration, and the gust record of a seed depends on its length
(the generator draws each axis's noise for the whole window before the next axis), so run ``i``
sees different lateral and vertical gusts at different speeds: the speeds compare as independent
samples, the two controllers at one speed on common records.
"""

from __future__ import annotations

import numpy as np

from .docking_cells import capture_cells, capture_record
from .docking_runs import CellSpec
from .markup import figure_html, fmt, html_table

__all__ = ["CLOSURE_SPEEDS_M_S", "FAST_CLOSURE_SPEEDS_M_S", "SPEED_LEVEL", "SPEED_CONTROLLERS", "speed_specs",
           "speed_frame", "speed_findings", "speed_html", "speed_record", "write_speed_outputs"]

#: Probe closure speeds of the study [m/s]: from the latch window's 0.5 m/s minimum up to 2 m/s,
#: the fastest at which the 1 m push still cruises before its 1 s stop.
CLOSURE_SPEEDS_M_S = (0.5, 0.75, 1.0, 1.5, 2.0)

#: The fast version's speeds [m/s]: the ends and the shipped speed.
FAST_CLOSURE_SPEEDS_M_S = (0.5, 1.0, 2.0)

#: Turbulence level of the study (the middle one: neither always nor never captured).
SPEED_LEVEL = "moderate"

#: Drogue controllers of the study.
SPEED_CONTROLLERS = ("none", "pid")

#: The speed study's CSVs and figure, relative to the report folder.
TABLE_CSV, RUNS_CSV, FIGURE_PNG = ("docking_closure_speed.csv", "docking_closure_speed_runs.csv",
                                   "fig_docking_closure_speed.png")


def speed_specs(speeds=CLOSURE_SPEEDS_M_S) -> list[CellSpec]:
    """The study's cells: approach-moderate, bow wave on, each controller x speed.

    Parameters
    ----------
    speeds : sequence of float
        Probe closure speeds [m/s].

    Returns
    -------
    list of CellSpec
    """
    return [CellSpec(SPEED_LEVEL, c, True, False, float(v)) for c in SPEED_CONTROLLERS for v in speeds]


def speed_frame(specs, cells):
    """One row per (controller, speed): the campaign, its capture block, the failed-latch fraction
    and the closure speed at the coupler over the runs that reached it.

    Parameters
    ----------
    specs : sequence of CellSpec
        The cells of :func:`speed_specs`.
    cells : sequence of docking_runs.CampaignCell
        Their campaigns, in the same order.

    Returns
    -------
    pandas.DataFrame
        Columns controller, probe_speed_m_s, duration_s, campaign, runs, rate, ci95_low, ci95_high,
        n_<result>, failed_latch_fraction, coupler_speed_{p05,median,p95}_m_s [m/s],
        coupler_to_probe_speed (median ratio) [-], median_miss_m [m].
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
                         campaign=c.name, runs=cap["runs"], rate=cap["rate"], ci95_low=cap["ci95"][0],
                         ci95_high=cap["ci95"][1],
                         **{f"n_{k.replace(' ', '_')}": v for k, v in cap["by_result"].items()},
                         failed_latch_fraction=cap["by_result"]["failed latch"] / cap["runs"],
                         coupler_speed_p05_m_s=p05, coupler_speed_median_m_s=med, coupler_speed_p95_m_s=p95,
                         coupler_to_probe_speed=med / c.closure_speed_m_s,
                         median_miss_m=float(np.nanmedian(miss)) if np.isfinite(miss).any() else np.nan))
    df = pd.DataFrame(rows)
    if not (df[[k for k in df.columns if k.startswith("n_")]].sum(axis=1) == df["runs"]).all():
        raise RuntimeError("docking closure speed: the result counts do not add up to the runs of every cell")
    return df


def _verdict(a, b) -> dict:
    overlap = not (a["ci95_low"] > b["ci95_high"] or b["ci95_low"] > a["ci95_high"])
    return {"rate_a": float(a["rate"]), "ci95_a": [float(a["ci95_low"]), float(a["ci95_high"])],
            "rate_b": float(b["rate"]), "ci95_b": [float(b["ci95_low"]), float(b["ci95_high"])],
            "significant": not overlap}


def speed_findings(df, min_latch_m_s: float) -> dict:
    """What the closure speed does, per controller: the slowest speed's failed latches and
    coupler speed against the latch minimum, the slowest and fastest speed against the shipped
    1 m/s, the rate's trend with speed, and the coupler-to-probe speed ratio's range.

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`speed_frame`.
    min_latch_m_s : float
        The latch window's minimum closure speed at the coupler [m/s].

    Returns
    -------
    dict
        controller -> findings (rates [-], speeds [m/s], counts, "significant" flags).
    """
    out = {}
    for c, sub in df.groupby("controller", sort=False):
        sub = sub.sort_values("probe_speed_m_s").reset_index(drop=True)
        slow, fast = sub.iloc[0], sub.iloc[-1]
        ref = sub.iloc[int(np.argmin(np.abs(sub["probe_speed_m_s"] - 1.0)))]
        rates = sub["rate"].to_numpy()
        out[c] = {"slowest_m_s": float(slow["probe_speed_m_s"]), "fastest_m_s": float(fast["probe_speed_m_s"]),
                  "reference_m_s": float(ref["probe_speed_m_s"]),
                  "slowest_failed_latches": int(slow["n_failed_latch"]), "runs": int(slow["runs"]),
                  "slowest_coupler_median_m_s": float(slow["coupler_speed_median_m_s"]),
                  "slowest_below_latch_minimum": bool(slow["coupler_speed_median_m_s"] < min_latch_m_s),
                  "slowest_vs_reference": _verdict(slow, ref), "fastest_vs_reference": _verdict(fast, ref),
                  "trend": ("rises at every step" if np.all(np.diff(rates) > 0) else
                            "never falls" if np.all(np.diff(rates) >= 0) else "does not change monotonically"),
                  "coupler_to_probe_range": [float(sub["coupler_to_probe_speed"].min()),
                                             float(sub["coupler_to_probe_speed"].max())]}
    return out


def _rate(r, ci) -> str:
    return f"{r:.3f} [{ci[0]:.3f}, {ci[1]:.3f}]"


def _compare_text(v: dict, a: str, b: str) -> str:
    rel = "higher than" if v["rate_a"] > v["rate_b"] else ("equal to" if v["rate_a"] == v["rate_b"] else "lower than")
    sig = "significant" if v["significant"] else "overlapping intervals: not significant"
    return f"{a} {_rate(v['rate_a'], v['ci95_a'])} is {rel} {b} {_rate(v['rate_b'], v['ci95_b'])} ({sig})"


def _prose(df, findings: dict, probe) -> str:
    min_latch_m_s = probe.min_closure_speed_m_s
    speeds = sorted(set(df["probe_speed_m_s"]))
    parts = []
    for c, f in findings.items():
        who = "no controller" if c == "none" else f"the {c.upper()} controller"
        below = "below" if f["slowest_below_latch_minimum"] else "above"
        slow, fast, ref = (f"{f[k]:g} m/s" for k in ("slowest_m_s", "fastest_m_s", "reference_m_s"))
        parts.append(
            f"With {who}: at {slow} the median closure speed at the coupler is "
            f"{f['slowest_coupler_median_m_s']:.3f} m/s, {below} the {min_latch_m_s:g} m/s latch minimum, and "
            f"{f['slowest_failed_latches']} of {f['runs']} runs fail to latch; "
            f"{_compare_text(f['slowest_vs_reference'], slow, ref)}; "
            f"{_compare_text(f['fastest_vs_reference'], fast, ref)}; from {slow} to {fast} the rate "
            f"{f['trend']}.")
    ref = df[df["probe_speed_m_s"] == next(iter(findings.values()))["reference_m_s"]].iloc[0]
    ref_v, ref_d = float(ref["probe_speed_m_s"]), float(ref["duration_s"])
    lo = min(f["coupler_to_probe_range"][0] for f in findings.values())
    hi = max(f["coupler_to_probe_range"][1] for f in findings.values())
    return (
        f"<p><b>Closure speed.</b> approach-{SPEED_LEVEL} with the bow wave on at probe closure speeds of "
        f"{', '.join(f'{v:g}' for v in speeds)} m/s ({', '.join(findings)}), each run as long as the probe's "
        f"path: {probe.standoff_m:g} m / v to the balance position, then the {probe.push_m:g} m push and its "
        f"{probe.stop_time_s:g} s stop (table: duration), so a drogue well ahead of its balance position is still "
        f"met (a run that is not is counted as no contact); at {ref_v:g} m/s that is the shipped {ref_d:g} s and the "
        "cell is the main grid's campaign, not a new one. The coupler sees "
        f"{lo:.3f}-{hi:.3f} times the probe's speed (median over the runs): the last link is inclined, so the "
        "probe's forward speed has a smaller component along it, and the drogue's own motion adds to it or "
        "takes from it. " + " ".join(parts) + f" The time to contact, {probe.standoff_m:g} m / v, is also the time "
        "the gusts have to swing the drogue off the probe's straight line. The gust record of a seed depends on the run's length, so the speeds compare as "
        "independent samples.</p>")


def speed_html(df, findings: dict, probe) -> str:
    """The study's prose, table and figure.

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`speed_frame`.
    findings : dict
        :func:`speed_findings`.
    probe : hosedrogue.engagement.spec.Probe
        The scenario's probe: standoff [m], push [m], stop time [s], latch minimum [m/s].

    Returns
    -------
    str
        HTML.
    """
    min_latch_m_s = probe.min_closure_speed_m_s
    rows = []
    for _, r in df.iterrows():
        rows.append((r["controller"], f"{r['probe_speed_m_s']:g}", f"{r['duration_s']:g}", *capture_cells(r, df.columns),
                     " / ".join(fmt(r[f"coupler_speed_{k}_m_s"], 3) for k in ("p05", "median", "p95")),
                     fmt(r["median_miss_m"], 3)))
    table = html_table(["controller", "probe closure speed [m/s]", "duration [s]", "campaign", "runs",
                        "capture rate [-]", "Wilson 95 % interval [-]", "by result",
                        "closure speed at the coupler: 5th percentile / median / 95th [m/s]", "median miss [m]"],
                       rows, table_id="table-docking-closure-speed")
    return (_prose(df, findings, probe) + table
            + figure_html("fig-docking-closure-speed", FIGURE_PNG, "Capture rate against closure speed",
                          f"approach-{SPEED_LEVEL}, bow wave on. Left: capture rate with Wilson 95 % intervals "
                          "(solid) and the fraction of failed latches (dotted) per controller. Right: the closure "
                          "speed at the coupler at contact (median, 5th-95th percentile bars) against the probe's, "
                          f"with the {min_latch_m_s:g} m/s latch minimum.", (TABLE_CSV, RUNS_CSV)))


def speed_record(df, findings: dict) -> dict:
    """``report.json["docking"]["closure_speed"]``.

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`speed_frame`.
    findings : dict
        :func:`speed_findings`.

    Returns
    -------
    dict
        level, bow_wave, speeds [m/s], cells ("<controller>-v<speed>" -> campaign, probe speed [m/s],
        duration [s], rate, ci95, runs, by_result, failed-latch fraction, median coupler speed [m/s]),
        findings.
    """
    cells = {}
    for _, r in df.iterrows():
        cells[f"{r['controller']}-v{r['probe_speed_m_s']:g}"] = {
            **capture_record(r, df.columns), "probe_speed_m_s": float(r["probe_speed_m_s"]),
            "duration_s": float(r["duration_s"]), "failed_latch_fraction": float(r["failed_latch_fraction"]),
            "coupler_speed_median_m_s": float(r["coupler_speed_median_m_s"])}
    return {"level": SPEED_LEVEL, "bow_wave": True, "controllers": list(SPEED_CONTROLLERS),
            "speeds_m_s": sorted(set(float(v) for v in df["probe_speed_m_s"])), "cells": cells, "findings": findings}


def write_speed_outputs(out, df, specs, cells, min_latch_m_s: float) -> None:
    """The table's CSV, the runs' CSV and the figure.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    df : pandas.DataFrame
        :func:`speed_frame`.
    specs : sequence of CellSpec
        The study's cells.
    cells : sequence of docking_runs.CampaignCell
        Their campaigns.
    min_latch_m_s : float
        The latch minimum [m/s], drawn in the figure.
    """
    import pandas as pd

    from ..plotting.docking import plot_closure_speed

    out.csv(df, TABLE_CSV)
    frames = []
    for spec, c in zip(specs, cells):
        f = c.runs[["run", "seed", "result", "miss_distance_m", "closure_speed_m_s", "peak_u_n"]].copy()
        f.insert(0, "campaign", c.name)
        f.insert(0, "probe_speed_m_s", c.closure_speed_m_s)
        f.insert(0, "controller", spec.controller)
        frames.append(f)
    out.csv(pd.concat(frames, ignore_index=True), RUNS_CSV)
    out.figure(plot_closure_speed(df, SPEED_CONTROLLERS, min_latch_m_s), FIGURE_PNG)
