"""The "Docking" section's force-limit study: the capture rate of approach-moderate and
approach-severe (bow wave on) with the paper's PID and LQR drogue controllers when the actuator's
force is limited (``[actuator] max_force_n``), against that limit (docs/engagement.md, "Docking
statistics").

The cells are :func:`hosedrogue.studies.docking_grid.force_specs`: each limit a campaign whose
scenario's actuator has the limit, which the control law applies per axis (each of the lateral and
vertical commands clipped to +-limit, so the force's magnitude can reach sqrt(2) times it;
docs/engagement.md, "Drogue controller during the approach"). The unlimited point of each
controller and the no-controller rate of each level are the main grid's
``<level>-<controller>-bow-on`` campaigns (:func:`hosedrogue.studies.docking.run_grid` runs a
scenario once). The limit does not change the scenario's duration or turbulence window, so run
``i`` sees the same gust record in every cell of a level (common random numbers).

The table, the saturation rule and the findings are
:mod:`hosedrogue.studies.docking_statistics`' (``force_table``, ``saturated``,
``force_findings``); this module writes the CSVs, the figure, the HTML and
``report.json["docking"]["force_limit"]`` from them.
"""

from __future__ import annotations

import math

import numpy as np

from ..studies.docking_statistics import PEAK_FORCE, PEAK_FORCE_Y, PEAK_FORCE_Z, SATURATION_TOLERANCE, saturated
from .docking_cells import capture_cells, capture_record
from .markup import figure_html, fmt, html_table

__all__ = ["force_html", "force_record", "write_force_outputs"]

#: The study's CSVs and figure, relative to the report folder.
TABLE_CSV, RUNS_CSV, FIGURE_PNG = ("docking_force_limit.csv", "docking_force_limit_runs.csv",
                                   "fig_docking_force_limit.png")


def _rate(d: dict) -> str:
    return f"{d['rate']:.3f} [{d['ci95'][0]:.3f}, {d['ci95'][1]:.3f}]"


def _finding_text(f: dict) -> str:
    who = f"{f['level']}, {f['controller'].upper()}"
    if not f["overlap_reached"]:
        overlap = "the largest limit's interval does not overlap the unlimited one"
    elif f["overlap_from_n"] == f["smallest_n"]:
        overlap = "every limit's interval, down to the smallest, overlaps the unlimited one"
    else:
        overlap = (f"from {f['overlap_from_n']:g} N up every limit's interval overlaps the unlimited one "
                   f"({100 * f['overlap_saturated_fraction']:.1f} % of the runs saturated at {f['overlap_from_n']:g} N)")
    sv = f["smallest_vs_none"]
    rel = "above" if sv["higher"] else "not above"
    sig = "intervals apart" if sv["significant"] else "overlapping intervals"
    return (f"{who}: unlimited {_rate(f['unlimited'])}; {overlap}; at {f['smallest_n']:g} N "
            f"{_rate(f['smallest'])} with {100 * f['smallest_saturated_fraction']:.1f} % of the runs saturated, "
            f"{rel} no controller's {_rate(f['none'])} ({sig}).")


def _prose(df, findings: dict) -> str:
    limits = sorted(set(df.loc[np.isfinite(df["max_force_n"]), "max_force_n"]))
    levels = list(dict.fromkeys(df["level"]))
    controllers = [c for c in dict.fromkeys(df["controller"]) if c != "none"]
    runs = int(df["runs"].iloc[0])
    return (
        f"<p><b>Force limit.</b> approach-{', approach-'.join(levels)} with the bow wave on and the "
        f"{' and '.join(c.upper() for c in controllers)} controller{'s' if len(controllers) > 1 else ''}, the force "
        "limited per axis to "
        f"{', '.join(f'{f:g}' for f in limits)} N (<code>[actuator] max_force_n</code>: the lateral and the "
        "vertical command are each clipped, so the force's magnitude can reach √2 times the limit), "
        f"{runs} runs per cell on the grid's seeds (the same gust records at every limit). The unlimited point and "
        "the no-controller rate are the main grid's campaigns, not new ones. A run counts as saturated when its "
        f"larger per-axis peak force (<code>{PEAK_FORCE_Y}</code>, <code>{PEAK_FORCE_Z}</code> of runs.csv: max |u| of "
        f"the applied force over the run; <code>{PEAK_FORCE}</code> is the magnitude, which a per-axis limit does not "
        f"bound) is within {100 * SATURATION_TOLERANCE:g} % of the limit. "
        + " ".join(_finding_text(f) for f in findings.values())
        + " The overlap of the intervals is a conservative test for cells on the same seeds; a paired test is "
        "not made.</p>")


def force_html(df, findings: dict) -> str:
    """The study's prose, table and figure.

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`hosedrogue.studies.docking_statistics.force_table`.
    findings : dict
        :func:`hosedrogue.studies.docking_statistics.force_findings`.

    Returns
    -------
    str
        HTML.
    """
    rows = []
    for _, r in df.iterrows():
        limit = f"{r['max_force_n']:g}" if math.isfinite(r["max_force_n"]) else "unlimited"
        rows.append((r["level"], r["controller"], limit if r["controller"] != "none" else "-",
                     *capture_cells(r, df.columns), fmt(r["saturated_fraction"], 3),
                     " / ".join(f"{r[k]:.0f}" for k in ("peak_axis_force_median_n", "peak_axis_force_p95_n",
                                                        "peak_axis_force_max_n"))))
    table = html_table(["turbulence", "controller", "force limit per axis [N]", "campaign", "runs",
                        "capture rate [-]", "Wilson 95 % interval [-]", "by result", "saturated runs [-]",
                        "peak per-axis force: median / 95th percentile / max [N]"],
                       rows, table_id="table-docking-force-limit")
    return (_prose(df, findings) + table
            + figure_html("fig-docking-force-limit", FIGURE_PNG, "Capture rate against the force limit",
                          "Bow wave on. Left: capture rate with Wilson 95 % intervals against the actuator's force "
                          "limit per axis (log scale; the unlimited controller, the main grid's campaign, at the "
                          "right edge), one colour per turbulence level, one line style per controller; the band "
                          "of each level's colour is the no-controller rate's interval. Right: the fraction of "
                          "runs whose force saturated.", (TABLE_CSV, RUNS_CSV)))


def force_record(df, findings: dict) -> dict:
    """``report.json["docking"]["force_limit"]``.

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`hosedrogue.studies.docking_statistics.force_table`.
    findings : dict
        :func:`hosedrogue.studies.docking_statistics.force_findings`.

    Returns
    -------
    dict
        levels, controllers, limits [N], saturation tolerance [-], cells ("<level>-<controller>-f<limit>",
        "-unlimited" or "<level>-none" -> campaign, limited, rate, ci95, runs, by_result, largest per-axis
        peak [N], and where limited the limit [N] and the saturated fraction), findings.
    """
    cells = {}
    for _, r in df.iterrows():
        finite = math.isfinite(r["max_force_n"])
        key = f"{r['level']}-{r['controller']}" + ("" if r["controller"] == "none" else
                                                   f"-f{r['max_force_n']:g}" if finite else "-unlimited")
        cells[key] = {**capture_record(r, df.columns), "limited": finite,
                      "peak_axis_force_max_n": float(r["peak_axis_force_max_n"])}
        if finite:  # report.json holds no nulls or infinities: the limit's keys only where there is one
            cells[key].update(max_force_n=float(r["max_force_n"]), saturated_fraction=float(r["saturated_fraction"]))
    return {"levels": list(dict.fromkeys(df["level"])), "bow_wave": True,
            "controllers": [c for c in dict.fromkeys(df["controller"]) if c != "none"],
            "limits_n": sorted(float(f) for f in set(df["max_force_n"]) if math.isfinite(f)),
            "saturation_tolerance": SATURATION_TOLERANCE, "cells": cells, "findings": findings}


def write_force_outputs(out, df, specs, cells) -> None:
    """The table's CSV, the runs' CSV (with a ``saturated`` column) and the figure.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    df : pandas.DataFrame
        :func:`hosedrogue.studies.docking_statistics.force_table`.
    specs : sequence of hosedrogue.studies.docking_grid.CellSpec
        The study's cells.
    cells : sequence of hosedrogue.studies.docking.CampaignCell
        Their campaigns.
    """
    import pandas as pd

    from ..studies.docking_figures import plot_force_limit

    out.csv(df, TABLE_CSV)
    frames = []
    for spec, c in zip(specs, cells):
        f = c.runs[["run", "seed", "result", "miss_distance_m", PEAK_FORCE_Y, PEAK_FORCE_Z, PEAK_FORCE]].copy()
        limit = math.inf if spec.max_force_n is None else float(spec.max_force_n)
        f["saturated"] = saturated(c.runs, limit)
        f.insert(0, "campaign", c.name)
        f.insert(0, "max_force_n", limit)
        f.insert(0, "controller", spec.controller)
        f.insert(0, "level", spec.level)
        frames.append(f)
    out.csv(pd.concat(frames, ignore_index=True), RUNS_CSV)
    out.figure(plot_force_limit(df), FIGURE_PNG)
