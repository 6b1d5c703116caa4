"""Report section "Whip loads": the whip's loads against the hose's axial stiffness and the
probe's closure speed for the three reel laws (:mod:`hosedrogue.studies.whip_loads`).

The study runs in the library (:func:`hosedrogue.studies.whip_loads.whip_load_study`); this module
writes its rows as CSV, the figure through :func:`hosedrogue.studies.whip_loads_figures.plot_whip_loads`,
the HTML with the numbers read from the rows and ``report.json["whip_loads"]``. The fast version
runs a smaller grid on the report settings' coarser mesh (``whip_*`` fields) and says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .markup import esc, figure_html, fmt, html_table

__all__ = ["WhipLoadsResult", "build"]

CSV, FIGURE = "whip_loads.csv", "fig_whip_loads.png"


@dataclass(frozen=True)
class WhipLoadsResult:
    """The study's rows.

    Parameters
    ----------
    rows : list of hosedrogue.studies.whip_loads.WhipLoadRow
        One per scenario, axial stiffness [N] and closure speed [m/s].
    """

    rows: list  #: the study's rows


def _cell(r, key: str) -> str:
    return fmt(r.peaks[key], 4) + ("" if r.converged[key] else "*")


def _tables(rows) -> str:
    parts = []
    speeds = sorted({r.closure_speed_m_s for r in rows})
    for law in dict.fromkeys(r.law for r in rows):
        body = []
        for ea in sorted({r.stiffness_n for r in rows}):
            sel = {r.closure_speed_m_s: r for r in rows if r.law == law and r.stiffness_n == ea}
            body.append((f"{ea:.0e}", fmt(next(iter(sel.values())).damping_n_s, 3),
                         *(f"{_cell(sel[v], 'peak_tension_rise_n')} / {_cell(sel[v], 'peak_probe_load_n')}"
                           if sel[v].result == "captured" else esc(sel[v].result) for v in speeds)))
        parts.append(html_table(["EA [N]", "c_a [N s]", *(f"{v:g} m/s" for v in speeds)], body,
                                table_id=f"table-whip-{law}",
                                caption=f"{law}: exit-tension rise [N] / peak probe load [N] (* not converged)"))
    return "".join(parts)


def _prose(rows, settings) -> str:
    from ..studies.whip_loads import study_scenario

    speed = max({r.closure_speed_m_s for r in rows}, key=lambda v: (v == 1.5, v))  # the shipped 1.5 m/s if run
    resp = sorted((r for r in rows if r.law == "response" and r.closure_speed_m_s == speed and r.result == "captured"),
                  key=lambda r: r.stiffness_n)
    scale = ""
    if resp:
        mu = study_scenario("engage-response", resp[0].stiffness_n, speed).params.hose.mass_per_length_kg_m
        pairs = "; ".join(f"EA {r.stiffness_n:.0e} N: v sqrt(EA mu) {fmt(speed * math.sqrt(r.stiffness_n * mu), 3)} N, "
                          f"rise {fmt(r.peaks['peak_tension_rise_n'], 3)} N" for r in resp)
        scale = (f" The wave equation's tension behind a snap front of speed v is v sqrt(EA mu); with the closure "
                 f"speed {speed:g} m/s as v, against the responsive reel's exit-tension rise: {pairs}. The snap is "
                 "slower than the probe's closure and the axial damping (the same loss factor at every EA) smooths "
                 "the wave on its way to the exit, so the load grows far less than sqrt(EA).")
    fast = ('<p class=diff id="whip-fast">FAST VERSION of this section: a smaller grid on '
            f"{settings.whip_links} links; the full report runs the shipped 160 links.</p>") if settings.fast else ""
    return (fast + "<p>The three engagement scenarios with the hose's axial stiffness EA and the probe's closure speed "
            "varied (the axial damping c_a = 0.1 EA / omega_1 keeps the shipped loss factor at the first axial mode; "
            "the latch window opened to 0.3 m/s for the slowest probe; each run lasts until 5 s after the probe "
            "stops; docs/engagement.md, \"Whip loads\"). The peaks are taken at every step; a * marks a peak the "
            "run does not call converged (the locked reel's flailing loop)." + scale + "</p>")


def build(out, settings) -> WhipLoadsResult:
    """Run the whip-load study and write its section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        ``whip_stiffnesses_n`` [N], ``whip_closure_speeds_m_s`` [m/s], ``whip_links`` and
        ``whip_step_s`` [s] (None: the scenarios' mesh and step).

    Returns
    -------
    WhipLoadsResult
    """
    import pandas as pd

    from ..studies.whip_loads_figures import plot_whip_loads
    from ..studies.whip_loads import whip_load_study

    rows = whip_load_study(settings.whip_stiffnesses_n, settings.whip_closure_speeds_m_s,
                           links=settings.whip_links, step_s=settings.whip_step_s,
                           progress=lambda text: out.status(f"whip loads: {text}"))
    out.csv(pd.DataFrame([r.to_dict() for r in rows]), CSV)
    out.figure(plot_whip_loads(rows), FIGURE)
    html = ('<section id="whip-loads"><h2>Beyond the paper: whip loads against the axial stiffness and the '
            "closure speed</h2>" + _prose(rows, settings) + _tables(rows)
            + figure_html("fig-whip-loads", FIGURE, "Whip loads",
                          "Rise of the exit tension above the trail tension and peak probe load against the closure "
                          "speed, one line per axial stiffness; hollow markers: not converged.", (CSV,))
            + "</section>")
    out.section("whip-loads", "whip loads", html)
    resp = [r for r in rows if r.law == "response" and r.result == "captured"]
    if resp:
        top = max(resp, key=lambda r: r.peaks["peak_tension_rise_n"])
        out.summarize(f"Whip loads: the responsive reel's largest exit-tension rise is {top.peaks['peak_tension_rise_n']:.0f} N "
                      f"(EA {top.stiffness_n:.0e} N, {top.closure_speed_m_s:g} m/s).")
    out.record("whip_loads", {"fast": settings.fast, "links": settings.whip_links, "rows": [r.to_dict() for r in rows]})
    return WhipLoadsResult(rows=rows)
