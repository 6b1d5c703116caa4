"""Report section "Docking": the receiver's bow wave, the capture rate of the approach scenarios
against the turbulence intensity (campaigns per level x controller x bow wave, and the pilot model
flying the probe with the bow wave on), the miss-distance CDFs, one approach seen from behind and
the capture rate against the closure speed (:mod:`.docking_speed`) and against the controllers'
force limit (:mod:`.docking_force`; docs/engagement.md, "Bow wave",
"Approach scenarios", "Docking statistics").

The computations are the docking studies' (:mod:`hosedrogue.studies.docking`, the cells of
:mod:`hosedrogue.studies.docking_grid`, the tables and findings of
:mod:`hosedrogue.studies.docking_statistics`, :mod:`hosedrogue.studies.bow_wave`); this module
writes the CSVs, the figures (through :mod:`hosedrogue.studies.bow_wave_figures` and
:mod:`hosedrogue.studies.docking_figures`), the HTML section with every number read from the results, and
``report.json["docking"]``. The campaigns are kept in ``docking/campaigns/<cell>/`` of the report
folder (each a campaign folder: campaign.json with the cell's scenario, runs.csv, summary.json),
rewritten at every build. Runs per cell, the dask workers and the two studies' cells are the
report settings' (:class:`~hosedrogue.report.settings.ReportSettings`, ``docking_*``).
"""

from __future__ import annotations

import shutil
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..studies.bow_wave import FAR_M, LEVEL_M, NEAR_M, bow_wave_study
from ..studies.docking import APPROACH_RUNS, APPROACH_SEED, approach_path, approach_runs, run_grid
from ..studies.docking_grid import (CAMPAIGN_SEED, CONTROLLERS, LEVELS, PILOT, force_specs, grid_specs,
                                    speed_specs)
from ..studies.docking_statistics import (PEAK_FORCE, capture_table, comparisons, force_findings, force_table,
                                          speed_findings, speed_table)
from . import docking_force as force
from . import docking_speed as speed
from .docking_cells import CAMPAIGNS, by_result_text
from .markup import esc, figure_html, fmt, html_table, viewer_html
from .settings import FULL
from .shared import campaign_execution, campaign_share

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["DockingSectionResult", "build", "CONTROLLERS", "LEVELS"]

#: Public CFD figures of the drogue's bow-wave displacement inside 1 m of the probe [m].
PUBLIC_NEAR_M = (0.1, 0.4)

#: The section's viewer page: the approach runs in 3D (every output time: 20 links, 4.5 s).
VIEW_FILE = "view_docking_approach.html"


@dataclass(frozen=True)
class DockingSectionResult:
    """The capture table and the bow-wave numbers of the section."""

    capture: dict  #: cell name -> capture block (rate [-], ci95 [-], runs, by_result)
    runs_per_cell: int  #: runs per campaign
    bow_wave: dict  #: the ``report.json["docking"]["bow_wave"]`` block (mm and m in the keys)
    wall_time_s: float  #: the section's wall time [s]


def _runs_frame(cells):
    import pandas as pd

    frames = []
    for c in cells:
        df = c.runs[["run", "seed", "completed", "result", "miss_distance_m", "closure_speed_m_s", PEAK_FORCE]].copy()
        df.insert(0, "bow_wave", c.bow_wave)
        df.insert(0, "pilot", c.pilot)
        df.insert(0, "controller", c.controller)
        df.insert(0, "level", c.level)
        df.insert(0, "campaign", c.name)
        frames.append(df)
    return pd.concat(frames, ignore_index=True)


def _bow_wave_outputs(out, bw) -> None:
    import pandas as pd

    r = bw.distances_m + bw.source_ahead_of_tip_m
    disp = pd.DataFrame(dict(probe_distance_m=bw.distances_m, source_distance_m=r,
                             forward_m=bw.displacement_m[:, 0], right_m=bw.displacement_m[:, 1],
                             down_m=bw.displacement_m[:, 2], total_m=np.linalg.norm(bw.displacement_m, axis=1)))
    out.csv(disp, "docking_bow_wave_displacement.csv")
    out.csv(pd.DataFrame({"forebody_radius_m": bw.radii_m, f"total_at_{NEAR_M:g}_m_m": bw.radii_displacement_m[:, 0],
                          f"total_at_{FAR_M:g}_m_m": bw.radii_displacement_m[:, 1]}), "docking_bow_wave_radii.csv")
    X, Z = np.meshgrid(bw.x_m, bw.z_m)
    out.csv(pd.DataFrame(dict(x_m=X.ravel(), z_m=Z.ravel(), u_m_s=bw.velocity_m_s[..., 0].ravel(),
                              w_m_s=bw.velocity_m_s[..., 2].ravel())), "docking_bow_wave_field.csv")
    out.figure(bw.figures()["bow_wave"], "fig_docking_bow_wave.png")


def _approach_outputs(out, paths: dict, radius: float) -> None:
    import pandas as pd

    from ..studies.docking_figures import plot_approach_from_behind

    rows = [pd.DataFrame(dict(controller=c, t_s=p["t_s"], probe_y_m=p["probe_yz_m"][:, 0],
                              probe_z_m=p["probe_yz_m"][:, 1], drogue_y_m=p["drogue_yz_m"][:, 0],
                              drogue_z_m=p["drogue_yz_m"][:, 1])) for c, p in paths.items()]
    out.csv(pd.concat(rows, ignore_index=True), "docking_approach.csv")
    out.figure(plot_approach_from_behind(paths, radius), "fig_docking_approach.png")


def _rate(r: float, ci) -> str:
    return f"{r:.3f} [{ci[0]:.3f}, {ci[1]:.3f}]"


def _verdict(cmp: dict, a: str, b: str) -> str:
    rel = "higher than" if cmp["a_higher"] else ("equal to" if cmp["rate_a"] == cmp["rate_b"] else "lower than")
    sig = ("the 95 % intervals do not overlap: significant" if cmp["significant"]
           else "overlapping 95 % intervals: not significant")
    return (f"{a} {_rate(cmp['rate_a'], cmp['ci95_a'])} is {rel} {b} {_rate(cmp['rate_b'], cmp['ci95_b'])} ({sig})")


def _capture_html(df) -> str:
    rows = []
    for _, r in df.iterrows():
        link = f'<a href="{CAMPAIGNS}/{r["campaign"]}/summary.json">{esc(r["campaign"])}</a>'
        by = by_result_text(r, df.columns)
        who = f"{r['controller']}, {PILOT} flies the probe" if r["pilot"] else r["controller"]
        rows.append((("html", link), r["level"], fmt(r["sigma_m_s"], 3), who,
                     "on" if r["bow_wave"] else "off", f"{r['rate']:.3f}", f"{r['ci95_low']:.3f} - {r['ci95_high']:.3f}",
                     int(r["runs"]), by, fmt(r["median_miss_m"], 3),
                     " / ".join(f"{r[k]:.0f}" for k in ("median_peak_force_n", "p95_peak_force_n", "max_peak_force_n"))))
    return html_table(["campaign", "turbulence", "σ_w [m/s]", "controller", "bow wave", "capture rate [-]",
                       "Wilson 95 % interval [-]", "runs", "by result", "median miss [m]",
                       "peak control force: median / 95th percentile / max [N]"], rows,
                      table_id="table-docking-capture")


def _bow_html(bw) -> str:
    rows = [(fmt(R, 3), fmt(near * 1e3, 3), fmt(far * 1e3, 3))
            for R, (near, far) in zip(bw.radii_m, bw.radii_displacement_m)]
    table = html_table(["forebody radius R [m]", f"displacement at {NEAR_M:g} m [mm]",
                        f"displacement at {FAR_M:g} m [mm]"], rows, table_id="table-docking-radii")
    ratio = bw.radii_displacement_m[-1, 1] / bw.radii_displacement_m[0, 1]
    r2 = (bw.radii_m[-1] / bw.radii_m[0]) ** 2
    return (
        f"<p><b>Bow wave.</b> The receiver's forebody (Rankine half-body of radius {fmt(bw.radius_m, 3)} m, probe tip "
        f"{fmt(-bw.stagnation_m[0], 3)} m ahead of its nose) displaces the air ahead of it with the flux π R² V of a "
        f"source {fmt(bw.source_ahead_of_tip_m, 4)} m behind the tip. Held on the drogue's axis (150 m/s, 8000 m, wake "
        f"on, the approach scenarios' converged 20-link model), the probe moves the drogue's balance position by "
        f"{fmt(bw.near_m * 1e3, 3)} mm at {NEAR_M:g} m and {fmt(bw.far_m * 1e3, 3)} mm at {FAR_M:g} m. Far away the "
        "displacement follows the bow-wave speed at the drogue, which falls as R²/r² (r from the source): "
        f"from R = {fmt(bw.radii_m[0], 3)} m to {fmt(bw.radii_m[-1], 3)} m the displacement at {FAR_M:g} m grows "
        f"{ratio:.1f} times against R² = {r2:.1f} times. So the requirement of less than "
        f"{LEVEL_M * 1e3:g} mm at {FAR_M:g} m holds only for forebodies smaller than R = "
        f"{bw.radius_limit_m:.2f} m (here R = {fmt(bw.radius_m, 3)} m: "
        f"{'met' if bw.far_m < LEVEL_M else 'not met'}). The {fmt(bw.near_m * 1e3, 3)} mm at {NEAR_M:g} m is "
        f"{'below' if bw.near_m < PUBLIC_NEAR_M[0] else 'within'} the {PUBLIC_NEAR_M[0]:g}-{PUBLIC_NEAR_M[1]:g} m "
        "that public CFD studies report inside 1 m: their receivers carry the probe closer to a larger nose "
        "(docs/engagement.md, \"Bow wave\").</p>" + table)


def _approach_text(paths: dict) -> str:
    parts = []
    for c, p in paths.items():
        o = p["outcome"]
        parts.append(f"controller {esc(c)}: {esc(o['result'])}, miss {fmt(o.get('miss_distance_m'), 3)} m at "
                     f"t = {fmt(o.get('contact_time_s'), 3)} s")
    return "; ".join(parts) + "."


def _setup_text() -> str:
    """The approach scenarios' set-up, read from the shipped approach-moderate."""
    from ..scenarios import load_scenario

    sc = load_scenario("approach-moderate")
    p, probe = sc.params, sc.engagement.probe
    return (f" {p.flight.airspeed_m_s:g} m/s, {p.flight.altitude_m:g} m, tanker wake {'on' if p.wake.enabled else 'off'}, "
            f"MIL-F-8785C Dryden turbulence of the level at {p.flight.altitude_m:g} m, the link model at "
            f"{p.hose.links} links ({p.hose.mass_lumping} lumping, {p.hose.bending} bending), RK4 at {p.numerics.step_s * 1e3:g} ms; the probe closes at "
            f"{probe.closure_speed_m_s:g} m/s from {probe.standoff_m:g} m behind the drogue's balance position and is "
            f"captured within {probe.capture_radius_m:g} m")


def _prose(df, cmp: dict, runs: int, times: dict) -> str:
    mid = next(k.split("_vs_none_")[1] for k in cmp if "_vs_none_" in k)
    ctrl = "; ".join(_verdict(cmp[f"{c}_vs_none_{mid}"], c, "none") for c in CONTROLLERS[1:])
    levels = [lev for lev in LEVELS if lev in set(df["level"])]
    text = (
        f"<p><b>What was run.</b> Campaigns of the shipped approach scenarios (approach-{', approach-'.join(levels)}:"
        f"{_setup_text()}) for every drogue controller ({', '.join(CONTROLLERS)}) with the bow wave "
        f"on and off, and with the pilot model flying the probe ({PILOT}: no drogue controller, bow wave on): {runs} "
        f"runs per cell, run i with the turbulence seed run_seed({CAMPAIGN_SEED}, i) in every cell (the "
        "same records across controllers and bow-wave settings). Each campaign is kept in "
        f"<code>{CAMPAIGNS}/&lt;cell&gt;/</code>. Wall time: campaigns {times['campaigns_s']:.1f} s, bow-wave study "
        f"{times['bow_wave_s']:.1f} s, approach runs {times['approach_s']:.1f} s; the whole section {times['section_s']:.1f} s.</p>"
        f"<p><b>Turbulence.</b> Without a controller and with the bow wave on, "
        f"{_verdict(cmp['light_vs_severe'], levels[0], levels[-1])}.</p>"
        f"<p><b>Controllers in {mid} turbulence</b> (bow wave on): {ctrl}.")
    on = df[df["bow_wave"] & (df["controller"] != "none")]
    if len(on):
        worst = on.loc[on["p95_peak_force_n"].idxmax()]
        text += (" The controllers' forces are not limited (the scenarios have no <code>[actuator]</code> limits: the "
                 "paper's ideal force at the drogue): the 95th percentile of the runs' peak force reaches "
                 f"{worst['p95_peak_force_n']:.0f} N ({esc(worst['controller'])}, {esc(worst['level'])}; table). What an "
                 "actuator limit (<code>[actuator] max_force_n</code>) costs is the force-limit study below.")
    off = cmp[f"bow_off_vs_on_{mid}"]
    text += f" <b>Bow wave</b> ({mid}, no controller): {_verdict(off, 'off', 'on')}.</p>"
    pilot = [(k.split("_vs_none_")[1], v) for k, v in cmp.items() if k.startswith(f"{PILOT}_vs_none_")]
    if pilot:
        text += ("<p><b>Pilot.</b> The pilot model flying the probe toward the drogue it sees one reaction time "
                 "late (no drogue controller, bow wave on) against the straight-line probe on the same seeds: "
                 + "; ".join(_verdict(v, f"{lev}: pilot", "straight line") for lev, v in pilot) + ".</p>")
    return text


def _html(st: "_Study", view_mb: float) -> str:
    fast = (f'<p class=diff id="docking-fast">FAST VERSION of this section: {st.runs} runs per campaign, not '
            f"the full report's {FULL.docking_runs}; the rates and intervals are rough.</p>" if st.fast else "")
    radius = st.radius_m
    return (
        '<section id="docking"><h2>Beyond the paper: docking statistics and the bow wave</h2>' + fast
        + _bow_html(st.bow)
        + figure_html("fig-docking-bow-wave", "fig_docking_bow_wave.png", "The receiver's bow wave",
                      "Left: perturbation speed (colour, log scale) and velocity (arrows) in the vertical plane "
                      "through the probe (tip at the origin), the forebody's dividing streamline and its nose (the "
                      "stagnation point). Middle: the drogue's steady displacement against the probe distance, "
                      f"components and total, with the 1/r² asymptote and the {LEVEL_M * 1e3:g} mm level. Right: "
                      f"the displacement at {FAR_M:g} m against the forebody radius, with the R² scaling.",
                      ("docking_bow_wave_field.csv", "docking_bow_wave_displacement.csv", "docking_bow_wave_radii.csv"))
        + _prose(st.table, st.comparisons, st.runs, st.times)
        + _capture_html(st.table)
        + figure_html("fig-docking-capture", "fig_docking_capture.png", "Capture rate against turbulence intensity",
                      "One colour per controller, solid with the bow wave, dashed without, and the pilot model "
                      "flying the probe (no controller, bow wave on; squares); Wilson 95 % intervals (markers side "
                      "by side at each intensity).", ("docking_capture.csv",))
        + figure_html("fig-docking-miss", "fig_docking_miss_cdf.png", "Miss distance",
                      f"Empirical CDF of the radial miss at the coupler plane per turbulence level (bow wave on), "
                      f"one line per controller and the pilot; dashed: the capture radius {radius:g} m.",
                      ("docking_runs.csv",))
        + speed.speed_html(st.speed_table, st.speed_findings, st.probe)
        + force.force_html(st.force_table, st.force_findings)
        + figure_html("fig-docking-approach", "fig_docking_approach.png", "An approach seen from behind",
                      f"approach-moderate, seed {st.approach_seed}: the probe tip's and the drogue's paths in the "
                      "y-z plane (looking forward along x) from the start to contact, the capture circle around the "
                      f"drogue at contact and the contact point. {_approach_text(st.paths)}", ("docking_approach.csv",))
        + viewer_html("view-docking-approach", VIEW_FILE, "The same approaches in 3D",
                      f"approach-moderate, seed {st.approach_seed}, side by side: no controller, the PID "
                      "controller and the pilot model flying the probe; the camera starts behind the drogue, as "
                      "the receiver's pilot sees it. Every output time.", view_mb)
        + "</section>")


@dataclass(frozen=True)
class _Study:
    """What the section computed."""

    bow: object  #: studies.bow_wave.BowWaveStudy
    cells: list  #: studies.docking.CampaignCell per campaign of the main grid
    table: object  #: pandas.DataFrame, one row per campaign (studies.docking_statistics.capture_table)
    comparisons: dict  #: the section's statements (rates, intervals, significance)
    paths: dict  #: run label (controller or "pilot") -> approach path (studies.docking.approach_path)
    approaches: dict  #: run label -> the approach run (EngagementResult), for the 3D viewer
    runs: int  #: runs per campaign
    times: dict  #: wall times [s] of the parts
    radius_m: float  #: capture radius [m]
    approach_seed: int  #: turbulence seed of the approach figure
    fast: bool
    probe: object  #: the approach scenarios' hosedrogue.spec.sections.Probe
    speed_specs: list  #: studies.docking_grid.CellSpec of the closure-speed study
    speed_cells: list  #: their campaigns (the grid's where the scenario is the same)
    speed_table: object  #: studies.docking_statistics.speed_table
    speed_findings: dict  #: studies.docking_statistics.speed_findings
    force_specs: list  #: studies.docking_grid.CellSpec of the force-limit study
    force_cells: list  #: their campaigns (the grid's for the unlimited and no-controller cells)
    force_table: object  #: studies.docking_statistics.force_table
    force_findings: dict  #: studies.docking_statistics.force_findings


def _campaigns(out, settings):
    """The main grid's, the closure-speed study's and the force-limit study's campaigns, run afresh
    into the report's campaigns folder; returns the three (specs, cells) pairs and the wall time [s]."""
    grid = grid_specs()
    speeds = speed_specs(settings.docking_closure_speeds_m_s)
    forces = force_specs(settings.docking_force_limits_n, settings.docking_force_levels,
                         settings.docking_force_controllers)
    folder = out.dir / CAMPAIGNS
    shutil.rmtree(folder, ignore_errors=True)  # the report's campaigns are its own: never resumed
    t0 = time.perf_counter()
    every = run_grid(grid + speeds + forces, settings.docking_runs, folder, status=out.status, share=campaign_share(), plots=False,
                     **campaign_execution(settings.docking_workers))
    n, m = len(grid), len(grid) + len(speeds)
    return (grid, every[:n]), (speeds, every[n:m]), (forces, every[m:]), time.perf_counter() - t0


def _study(out, settings) -> _Study:
    from ..scenarios import load_scenario

    t0 = time.perf_counter()
    out.status("docking: bow wave")
    bow = bow_wave_study()
    t1 = time.perf_counter()
    (_, cells), (speeds, speed_cells), (forces, force_cells), campaigns_s = _campaigns(out, settings)
    t2 = time.perf_counter()
    out.status("docking: approach runs")
    approaches = approach_runs(runs=tuple(APPROACH_RUNS), seed=APPROACH_SEED)
    paths = {c: approach_path(r) for c, r in approaches.items()}
    t3 = time.perf_counter()
    table = capture_table(cells)
    probe = load_scenario("approach-moderate").engagement.probe
    times = {"bow_wave_s": t1 - t0, "campaigns_s": campaigns_s, "approach_s": t3 - t2}
    s_table, f_table = speed_table(speeds, speed_cells), force_table(forces, force_cells)
    return _Study(bow, cells, table, comparisons(table), paths, approaches, settings.docking_runs, times,
                  float(probe.capture_radius_m), APPROACH_SEED, settings.fast, probe, speeds, speed_cells, s_table,
                  speed_findings(s_table, probe.min_closure_speed_m_s), forces, force_cells, f_table,
                  force_findings(f_table))


def _figures(out, st: _Study) -> float:
    """The section's CSVs and figures and the approaches' viewer page; returns the page's size [MB]."""
    from ..studies.docking_figures import plot_capture_rates, plot_miss_cdfs

    _bow_wave_outputs(out, st.bow)
    out.csv(st.table, "docking_capture.csv")
    out.csv(_runs_frame(st.cells), "docking_runs.csv")
    levels = [lev for lev in LEVELS if lev in set(st.table["level"])]
    out.figure(plot_capture_rates(st.table, CONTROLLERS, levels), "fig_docking_capture.png")
    miss = {lev: {PILOT if c.pilot else c.controller: c.runs["miss_distance_m"].to_numpy(dtype=float) for c in st.cells
                  if c.level == lev and c.bow_wave} for lev in levels}
    out.figure(plot_miss_cdfs(miss, st.radius_m), "fig_docking_miss_cdf.png")
    _approach_outputs(out, st.paths, st.radius_m)
    speed.write_speed_outputs(out, st.speed_table, st.speed_specs, st.speed_cells, st.probe.min_closure_speed_m_s)
    force.write_force_outputs(out, st.force_table, st.force_specs, st.force_cells)
    return _viewer(out, st)


def _viewer(out, st: _Study) -> float:
    """The approach runs side by side in the viewer; returns its size [MB]."""
    from ..viewer import ViewRun, write_view

    runs = [ViewRun.from_result(r, label=label) for label, r in st.approaches.items()]
    path = write_view(runs, out.dir / VIEW_FILE, layout="side",
                      title=f"approach-moderate, seed {st.approach_seed}: three approaches")
    out.written(path)
    return path.stat().st_size / 1e6


def _record(st: _Study, view_mb: float) -> dict:
    bw = st.bow
    return {
        "fast": st.fast, "runs_per_cell": st.runs, "controllers": list(CONTROLLERS), "campaign_seed": CAMPAIGN_SEED,
        "bow_wave": {f"displacement_at_{NEAR_M:g}_m_mm": bw.near_m * 1e3, f"displacement_at_{FAR_M:g}_m_mm": bw.far_m * 1e3,
                     "forebody_radius_m": bw.radius_m,
                     f"radius_for_{LEVEL_M * 1e3:g}_mm_at_{FAR_M:g}_m_m": bw.radius_limit_m,
                     "radii_m": list(bw.radii_m), f"radii_displacement_at_{FAR_M:g}_m_mm": list(bw.radii_displacement_m[:, 1] * 1e3)},
        "capture": {c.name: {"sigma_m_s": c.sigma_m_s, **c.capture} for c in st.cells},
        "pilot_cells": [c.name for c in st.cells if c.pilot],
        "closure_speed": speed.speed_record(st.speed_table, st.speed_findings),
        "force_limit": force.force_record(st.force_table, st.force_findings),
        "comparisons": st.comparisons,
        "approach_viewer_size_mb": view_mb,
        "approach": {c: {k: p["outcome"][k] for k in ("miss_distance_m", "closure_speed_m_s", "contact_time_s")
                         if p["outcome"].get(k) is not None} | {"captured": p["outcome"]["result"] == "captured"}
                     for c, p in st.paths.items()},
        "wall_times_s": st.times,
    }


def _summary(st: _Study) -> str:
    cmp = st.comparisons["light_vs_severe"]
    return (f"Docking ({st.runs} runs per campaign{', fast version' if st.fast else ''}): without a controller the "
            f"capture rate is {cmp['rate_a']:.2f} in light and {cmp['rate_b']:.2f} in severe turbulence "
            f"({'significant' if cmp['significant'] else 'overlapping 95 % intervals'}); the bow wave moves the "
            f"drogue {st.bow.near_m * 1e3:.0f} mm at {NEAR_M:g} m and {st.bow.far_m * 1e3:.1f} mm at {FAR_M:g} m "
            f"(< {LEVEL_M * 1e3:g} mm at {FAR_M:g} m needs a forebody radius below {st.bow.radius_limit_m:.2f} m).")


def build(out: ReportFolder, settings: ReportSettings) -> DockingSectionResult:
    """Run the bow-wave study, the campaigns and the approach runs, and write the section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        ``docking_runs``: runs per campaign; ``docking_workers``: dask workers (None: this
        process); ``docking_closure_speeds_m_s`` and ``docking_force_*``: the two studies' cells;
        ``fast``: the section says it is the fast version.

    Returns
    -------
    DockingSectionResult
        The capture blocks per campaign, the runs per campaign, the bow-wave numbers and the
        section's wall time [s].
    """
    t0 = time.perf_counter()
    st = _study(out, settings)
    view_mb = _figures(out, st)
    st.times["section_s"] = time.perf_counter() - t0
    record = _record(st, view_mb)
    out.section("docking", "docking", _html(st, view_mb))
    out.summarize(_summary(st))
    out.record("docking", record)
    return DockingSectionResult(capture=record["capture"], runs_per_cell=st.runs, bow_wave=record["bow_wave"],
                                wall_time_s=record["wall_times_s"]["section_s"])
