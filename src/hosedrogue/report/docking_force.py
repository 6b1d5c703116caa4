"""The "Docking" section's force-limit study: the capture rate of approach-moderate and
approach-severe (bow wave on) with the paper's PID and LQR drogue controllers when the actuator's
force is limited (``[actuator] max_force_n``), against that limit (docs/engagement.md, "Docking
statistics").

Each limit is a campaign of the grid (:class:`.docking_runs.CellSpec` with ``max_force_n``): the
scenario's ``[actuator]`` table gets the limit, which the control law applies per axis (each of
the lateral and vertical commands clipped to +-limit, so the force's magnitude can reach sqrt(2)
times it; docs/engagement.md, "Drogue controller during the approach"). The unlimited point of
each controller and the no-controller rate of each level are the main grid's
``<level>-<controller>-bow-on`` campaigns: their specs are in :func:`force_specs` and
:func:`.docking_runs.run_grid` runs a scenario once, so they are not recomputed. The limit does not
change the scenario's duration or turbulence window, so run ``i`` sees the same gust record in
every cell of a level (common random numbers).

Saturation is read from ``runs.csv``: ``peak_u_y_n`` and ``peak_u_z_n`` are ``max |u_y|`` and
``max |u_z|`` of the applied (clipped) force over the turbulence window, which here is the whole
run, and ``peak_u_n`` is ``max hypot(u_y, u_z)``, the magnitude. A per-axis limit is reached by a
per-axis peak, not by the magnitude (a magnitude above the limit can have neither axis clipped), so
a run counts as saturated when ``max(peak_u_y_n, peak_u_z_n) >= (1 - SATURATION_TOLERANCE)``
times the limit.
"""

from __future__ import annotations

import math

import numpy as np

from .docking_cells import capture_cells, capture_record
from .docking_runs import CellSpec
from .markup import figure_html, fmt, html_table

__all__ = ["FORCE_LIMITS_N", "FAST_FORCE_LIMITS_N", "FORCE_LEVELS", "FAST_FORCE_LEVELS", "FORCE_CONTROLLERS",
           "FAST_FORCE_CONTROLLERS", "SATURATION_TOLERANCE", "force_specs", "force_frame", "force_findings",
           "force_html", "force_record", "write_force_outputs"]

#: Force limits per axis of the study [N]: from well below the PID's median peak in moderate
#: turbulence (92 N unlimited) to about its largest there (231 N), in factors of two.
FORCE_LIMITS_N = (25.0, 50.0, 100.0, 200.0)

#: The fast version's limits [N]: the smallest and the middle one.
FAST_FORCE_LIMITS_N = (25.0, 100.0)

#: Turbulence levels of the study (light is captured by either controller with 77 N at most).
FORCE_LEVELS = ("moderate", "severe")

#: The fast version's level.
FAST_FORCE_LEVELS = ("moderate",)

#: Drogue controllers of the study.
FORCE_CONTROLLERS = ("pid", "lqr")

#: The fast version's controller.
FAST_FORCE_CONTROLLERS = ("pid",)

#: A run's force saturated when its per-axis peak is within this fraction below the limit [-].
SATURATION_TOLERANCE = 1e-3

#: The study's CSVs and figure, relative to the report folder.
TABLE_CSV, RUNS_CSV, FIGURE_PNG = ("docking_force_limit.csv", "docking_force_limit_runs.csv",
                                   "fig_docking_force_limit.png")


def force_specs(limits=FORCE_LIMITS_N, levels=FORCE_LEVELS, controllers=FORCE_CONTROLLERS) -> list[CellSpec]:
    """The study's cells per level: no controller (the grid's), then per controller each limit and
    the unlimited one (the grid's), all with the bow wave on.

    Parameters
    ----------
    limits : sequence of float
        Force limits per axis [N].
    levels : sequence of str
        Turbulence levels.
    controllers : sequence of str
        Drogue controller types.

    Returns
    -------
    list of CellSpec
    """
    specs = []
    for level in levels:
        specs.append(CellSpec(level, "none", True))
        for c in controllers:
            specs += [CellSpec(level, c, True, max_force_n=float(f)) for f in limits]
            specs.append(CellSpec(level, c, True))
    return specs


def _saturated(runs, limit: float) -> np.ndarray:
    """Which runs' per-axis peak force reached ``limit`` [N] within :data:`SATURATION_TOLERANCE`."""
    axis = np.maximum(runs["peak_u_y_n"].to_numpy(dtype=float), runs["peak_u_z_n"].to_numpy(dtype=float))
    return axis >= (1.0 - SATURATION_TOLERANCE) * limit


def force_frame(specs, cells):
    """One row per cell: level, controller, limit (inf: unlimited; for "none" the rate of no
    controller), the campaign, its capture block, the saturated fraction and the peak forces.

    Parameters
    ----------
    specs : sequence of CellSpec
        The cells of :func:`force_specs`.
    cells : sequence of docking_runs.CampaignCell
        Their campaigns, in the same order.

    Returns
    -------
    pandas.DataFrame
        Columns level, controller, max_force_n [N] (inf: unlimited), campaign, runs, rate,
        ci95_low, ci95_high, n_<result>, saturated_fraction [-] (NaN unlimited),
        peak_axis_force_{median,p95,max}_n (per-axis peak, max of the two axes) [N] and
        peak_force_max_n (magnitude) [N].
    """
    import pandas as pd

    rows = []
    for spec, c in zip(specs, cells):
        cap, runs = c.capture, c.runs
        limit = math.inf if spec.max_force_n is None else float(spec.max_force_n)
        axis = np.maximum(runs["peak_u_y_n"].to_numpy(dtype=float), runs["peak_u_z_n"].to_numpy(dtype=float))
        rows.append(dict(level=spec.level, controller=spec.controller, max_force_n=limit, campaign=c.name,
                         runs=cap["runs"], rate=cap["rate"], ci95_low=cap["ci95"][0], ci95_high=cap["ci95"][1],
                         **{f"n_{k.replace(' ', '_')}": v for k, v in cap["by_result"].items()},
                         saturated_fraction=float(np.mean(_saturated(runs, limit))) if math.isfinite(limit) else np.nan,
                         peak_axis_force_median_n=float(np.median(axis)),
                         peak_axis_force_p95_n=float(np.percentile(axis, 95)),
                         peak_axis_force_max_n=float(np.max(axis)),
                         peak_force_max_n=float(np.max(runs["peak_u_n"].to_numpy(dtype=float)))))
    df = pd.DataFrame(rows)
    if not (df[[k for k in df.columns if k.startswith("n_")]].sum(axis=1) == df["runs"]).all():
        raise RuntimeError("docking force limit: the result counts do not add up to the runs of every cell")
    return df


def _overlap(a, b) -> bool:
    return not (a["ci95_low"] > b["ci95_high"] or b["ci95_low"] > a["ci95_high"])


def _rate_of(r) -> dict:
    return {"rate": float(r["rate"]), "ci95": [float(r["ci95_low"]), float(r["ci95_high"])]}


def force_findings(df) -> dict:
    """Per level and controller: the unlimited and no-controller rates, the smallest limit from
    which every larger limit's interval overlaps the unlimited rate's, and the smallest limit's
    rate against no controller.

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`force_frame`.

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
            free = sub[~np.isfinite(sub["max_force_n"])].iloc[0]
            lim = sub[np.isfinite(sub["max_force_n"])].sort_values("max_force_n").reset_index(drop=True)
            ok = [_overlap(r, free) for _, r in lim.iterrows()]
            first = next((i for i in range(len(ok)) if all(ok[i:])), None)
            low = lim.iloc[0]
            out[f"{level}-{c}"] = {
                "level": level, "controller": c, "unlimited": _rate_of(free), "none": _rate_of(none),
                "overlap_reached": first is not None,  # report.json holds no nulls: the two keys below only then
                **({} if first is None else {"overlap_from_n": float(lim.iloc[first]["max_force_n"]),
                                             "overlap_saturated_fraction": float(lim.iloc[first]["saturated_fraction"])}),
                "smallest_n": float(low["max_force_n"]), "smallest": _rate_of(low),
                "smallest_saturated_fraction": float(low["saturated_fraction"]),
                "smallest_vs_none": {"higher": bool(low["rate"] > none["rate"]),
                                     "significant": not _overlap(low, none)},
                "unlimited_p95_axis_force_n": float(free["peak_axis_force_p95_n"])}
    return out


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
        "larger per-axis peak force (<code>peak_u_y_n</code>, <code>peak_u_z_n</code> of runs.csv: max |u| of "
        "the applied force over the run; <code>peak_u_n</code> is the magnitude, which a per-axis limit does not "
        f"bound) is within {100 * SATURATION_TOLERANCE:g} % of the limit. "
        + " ".join(_finding_text(f) for f in findings.values())
        + " The overlap of the intervals is a conservative test for cells on the same seeds; a paired test is "
        "not made.</p>")


def force_html(df, findings: dict) -> str:
    """The study's prose, table and figure.

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`force_frame`.
    findings : dict
        :func:`force_findings`.

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
        :func:`force_frame`.
    findings : dict
        :func:`force_findings`.

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
        :func:`force_frame`.
    specs : sequence of CellSpec
        The study's cells.
    cells : sequence of docking_runs.CampaignCell
        Their campaigns.
    """
    import pandas as pd

    from ..plotting.docking import plot_force_limit

    out.csv(df, TABLE_CSV)
    frames = []
    for spec, c in zip(specs, cells):
        f = c.runs[["run", "seed", "result", "miss_distance_m", "peak_u_y_n", "peak_u_z_n", "peak_u_n"]].copy()
        limit = math.inf if spec.max_force_n is None else float(spec.max_force_n)
        f["saturated"] = _saturated(c.runs, limit)
        f.insert(0, "campaign", c.name)
        f.insert(0, "max_force_n", limit)
        f.insert(0, "controller", spec.controller)
        f.insert(0, "level", spec.level)
        frames.append(f)
    out.csv(pd.concat(frames, ignore_index=True), RUNS_CSV)
    out.figure(plot_force_limit(df), FIGURE_PNG)
