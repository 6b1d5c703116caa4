"""The "Docking" section's closure-speed study: the capture rate of approach-moderate (bow wave on)
against the probe's closure speed, without a drogue controller and with the paper's PID
(docs/engagement.md, "Docking statistics").

The cells are :func:`hosedrogue.studies.docking_grid.speed_specs`: each speed a campaign whose
scenario lasts :func:`hosedrogue.studies.docking_grid.approach_duration_s`, the shipped 4.5 s at
1 m/s, so that cell *is* the main grid's ``moderate-<controller>-bow-on`` campaign
(:func:`hosedrogue.studies.docking.run_grid` runs a scenario once). The table and the findings are
:func:`hosedrogue.studies.docking_statistics.speed_table` and ``speed_findings``; this module
writes the CSVs, the figure, the HTML and ``report.json["docking"]["closure_speed"]`` from them.

The turbulence window follows the duration, and the gust record of a seed depends on its length
(the generator draws each axis's noise for the whole window before the next axis), so run ``i``
sees different lateral and vertical gusts at different speeds: the speeds compare as independent
samples, the two controllers at one speed on common records.
"""

from __future__ import annotations

from ..studies.docking_grid import SPEED_CONTROLLERS, SPEED_LEVEL
from ..studies.docking_statistics import PEAK_FORCE
from .docking_cells import capture_cells, capture_record
from .markup import figure_html, fmt, html_table

__all__ = ["speed_html", "speed_record", "write_speed_outputs"]

#: The speed study's CSVs and figure, relative to the report folder.
TABLE_CSV, RUNS_CSV, FIGURE_PNG = ("docking_closure_speed.csv", "docking_closure_speed_runs.csv",
                                   "fig_docking_closure_speed.png")


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
        :func:`hosedrogue.studies.docking_statistics.speed_table`.
    findings : dict
        :func:`hosedrogue.studies.docking_statistics.speed_findings`.
    probe : hosedrogue.spec.sections.Probe
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
        :func:`hosedrogue.studies.docking_statistics.speed_table`.
    findings : dict
        :func:`hosedrogue.studies.docking_statistics.speed_findings`.

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
        :func:`hosedrogue.studies.docking_statistics.speed_table`.
    specs : sequence of hosedrogue.studies.docking_grid.CellSpec
        The study's cells.
    cells : sequence of hosedrogue.studies.docking.CampaignCell
        Their campaigns.
    min_latch_m_s : float
        The latch minimum [m/s], drawn in the figure.
    """
    import pandas as pd

    from ..studies.docking_figures import plot_closure_speed

    out.csv(df, TABLE_CSV)
    frames = []
    for spec, c in zip(specs, cells):
        f = c.runs[["run", "seed", "result", "miss_distance_m", "closure_speed_m_s", PEAK_FORCE]].copy()
        f.insert(0, "campaign", c.name)
        f.insert(0, "probe_speed_m_s", c.closure_speed_m_s)
        f.insert(0, "controller", spec.controller)
        frames.append(f)
    out.csv(pd.concat(frames, ignore_index=True), RUNS_CSV)
    out.figure(plot_closure_speed(df, SPEED_CONTROLLERS, min_latch_m_s), FIGURE_PNG)
