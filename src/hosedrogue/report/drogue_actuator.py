"""Report section "Actuated drogue" (beyond the paper): the paper's controllers commanding a drogue
that steers itself with control surfaces, against the ideal force the paper assumes
(docs/model.md, "Actuated drogue"; docs/docking-results.md, "Actuated drogue").

The computations are :mod:`hosedrogue.studies.drogue_actuator`'s (servo margins, convergence to the
ideal force, the claims cases) and the docking cells of
:func:`hosedrogue.studies.docking_grid.actuator_specs` (capture rate against deflection limit and
servo bandwidth, :func:`hosedrogue.studies.docking_statistics.actuator_table`); this module writes
the CSVs, the figures (:mod:`hosedrogue.studies.drogue_actuator_figures`), the HTML with the statement of
where the paper's "within 1 cm" holds, the comparison rows and ``report.json["drogue_actuator"]``.
The campaigns are kept in ``drogue_actuator/campaigns/<cell>/``, rewritten at every build.
"""

from __future__ import annotations

import shutil
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..spec.paper import SEC33_DISPLACEMENT_M
from ..spec.sections import DrogueActuator
from ..studies import drogue_actuator as study
from .docking_cells import CAMPAIGNS as DOCKING_CAMPAIGNS
from .docking_cells import capture_cells, capture_record
from .markup import figure_html, fmt, html_table
from .shared import campaign_execution, campaign_share

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["DrogueActuatorResult", "build"]

#: The capture campaigns' folder inside the report folder (one subfolder per cell).
CAMPAIGNS = "drogue_actuator/campaigns"


@dataclass(frozen=True)
class DrogueActuatorResult:
    """The paper's PID case with the ideal force and with the surfaces, and where 1 cm holds."""

    paper_case: dict  #: "ideal", "actuated" -> peak_dy_m, peak_dz_m, rms_dy_m, rms_dz_m [m], peak_u_n [N]
    within_one_cm: dict  #: :func:`hosedrogue.studies.drogue_actuator.within_one_cm`
    wall_time_s: float  #: the section's wall time [s]


def _paper_case(out, settings):
    """The paper's turbulence case with the paper's PID, ideal force and the surfaces' defaults."""
    from ..scenarios import load_scenario
    from ..scenarios.runner import run

    runs = {}
    for key, name in (("ideal", "paper-turbulence-pid"), ("actuated", "paper-turbulence-pid-actuated")):
        out.status(f"actuated drogue: {name}")
        runs[key] = run(load_scenario(name).with_overrides(duration_s=settings.run_duration_s))
    keys = ("peak_dy_m", "peak_dz_m", "rms_dy_m", "rms_dz_m", "peak_u_y_n", "peak_u_z_n", "peak_u_n")
    stats = {k: {**{c: float(r.statistics()[c]) for c in keys}, **r.surface_statistics(),
                 "completed": bool(r.completed)} for k, r in runs.items()}
    return runs, stats


def _add_comparisons(comparison, stats: dict) -> None:
    """The paper's Fig. 12 range beside the actuated PID's peaks, the ideal force's in the note."""
    ideal, act = stats["ideal"], stats["actuated"]
    for axis, key in (("lateral", "dy"), ("vertical", "dz")):
        d = DrogueActuator()
        note = (f"the drogue's surfaces ([drogue_actuator] defaults: {d.max_deflection_deg:g} deg, {d.max_rate_deg_s:g} "
                f"deg/s, {d.bandwidth_hz:g} Hz servos) make the "
                f"paper's PID force: peak {1000 * act[f'peak_{key}_m']:.2f} mm, RMS {1000 * act[f'rms_{key}_m']:.2f} mm "
                f"against the ideal force's {1000 * ideal[f'peak_{key}_m']:.2f} mm and "
                f"{1000 * ideal[f'rms_{key}_m']:.2f} mm (same gusts)")
        comparison.add("Fig. 12", f"peak {axis} displacement, PID on, drogue steered by its surfaces", "m",
                       SEC33_DISPLACEMENT_M["on"], act[f"peak_{key}_m"], note)


def _margins_html(margins) -> str:
    rows = []
    for r in margins.itertuples():
        bw = "ideal force" if not np.isfinite(r.bandwidth_hz) else f"{r.bandwidth_hz:g}"
        rows.append((r.controller.upper(), bw, f"{r.lateral_margin_deg:.1f} at {r.lateral_crossover_hz:.2f} Hz",
                     f"{r.vertical_margin_deg:.1f} at {r.vertical_crossover_hz:.2f} Hz", "yes" if r.stable else "NO"))
    return html_table(["controller", "servo bandwidth [Hz]", "lateral phase margin [deg] at crossover",
                       "vertical phase margin [deg] at crossover", "closed loop stable"], rows,
                      table_id="table-servo-margins")


def _convergence_html(conv) -> str:
    rows = [(f"{r.bandwidth_hz:g}", f"{1e6 * r.max_offset_difference_m:.2f}", f"{r.max_force_difference_n:.3f}",
             "-" if not np.isfinite(r.order) else f"{r.order:.3f}", f"{1000 * r.bandwidth_x_difference_m_hz:.3f}")
            for r in conv.itertuples()]
    return html_table(["servo bandwidth f [Hz]", "largest drogue offset difference [um]", "largest force difference [N]",
                       "order p (difference ~ f^-p)", "f x difference [mm Hz]"], rows, table_id="table-actuator-convergence")


def _claims_html(table) -> str:
    rows = []
    for r in table.itertuples():
        worst = max(r.peak_dy_m_max, r.peak_dz_m_max)
        sat = "-" if r.force == "ideal" else (f"{fmt(r.deflection_saturated_frac_median, 3)} / "
                                             f"{fmt(r.deflection_saturated_frac_max, 3)}")
        rate = "-" if r.force == "ideal" else f"{fmt(r.rate_saturated_frac_max, 3)}"
        rows.append((r.level, r.controller.upper(), r.force, r.seeds, f"{r.completed_fraction:.2f}",
                     f"{1000 * worst:.2f}" if np.isfinite(worst) else "-",
                     f"{1000 * r.rms_radial_m_median:.2f}" if np.isfinite(r.rms_radial_m_median) else "-",
                     f"{r.peak_u_n_max:.0f}" if np.isfinite(r.peak_u_n_max) else "-", sat, rate,
                     f"{r.within_1cm_fraction:.2f}"))
    return html_table(["turbulence", "controller", "drogue", "seeds", "completed", "largest peak |dy|,|dz| [mm]",
                       "median RMS radial [mm]", "largest peak force [N]", "time at the deflection limit: median / max [-]",
                       "time at the rate limit: max [-]", "seeds within 1 cm [-]"], rows, table_id="table-actuator-claims")


def _statement(one_cm: dict, margins) -> str:
    """Where the paper's "within 1 cm" holds and where it does not, read from the claims."""
    def levels(x):
        return ", ".join(x) if x else "none"

    parts = []
    for key, v in one_cm.items():
        worst = "; ".join(f"{lev} {1000 * m:.1f} mm" if m < 1.0 else f"{lev} {m:.2f} m"
                          for lev, m in v["worst_peak_m"].items())
        parts.append(f"<li><b>{key}</b>: holds in {levels(v['holds'])}; not in {levels(v['fails'])} "
                     f"(largest peak: {worst}).</li>")
    unstable = margins[(margins["controller"] == "pid") & ~margins["stable"]]["bandwidth_hz"]
    cliff = (f"With a servo of {', '.join(f'{b:g}' for b in unstable)} Hz the paper's PID is unstable (table above): "
             "there the claim fails in every case, the surfaces swinging between their limits."
             if len(unstable) else "")
    return ("<p><b>Where the paper's \"within 1 cm\" holds.</b> Per controller and drogue (ideal force, the "
            "surfaces' defaults, a quarter of their authority, a 12 Hz servo at the PID's stability edge), the "
            "turbulence cases in which every seed kept both peak offsets below 1 cm:</p><ul>" + "".join(parts)
            + f"</ul><p>{cliff}</p>")


def _capture_html(table) -> str:
    rows = []
    for _, r in table.iterrows():
        ideal = not np.isfinite(r["max_deflection_deg"])
        (kind, link), *cells = capture_cells(r, table.columns)  # the link into this section's campaigns
        rows.append((r["level"], r["controller"].upper(), "ideal" if ideal else f"{r['max_deflection_deg']:g}",
                     "ideal" if ideal else f"{r['bandwidth_hz']:g}", (kind, link.replace(DOCKING_CAMPAIGNS, CAMPAIGNS)),
                     *cells, "-" if ideal else fmt(r["saturated_runs_fraction"], 3),
                     "-" if ideal else fmt(r["saturated_time_median"], 3), int(r["stopped"])))
    return html_table(["turbulence", "controller", "deflection limit [deg]", "servo [Hz]", "campaign", "runs",
                       "capture rate [-]", "Wilson 95 % interval [-]", "by result", "runs saturated [-]",
                       "median time saturated [-]", "runs stopped"], rows, table_id="table-actuator-capture")


def _html(st) -> str:
    d = DrogueActuator()
    ideal, act = st["paper"]["ideal"], st["paper"]["actuated"]
    fast = " (fast version: fewer seeds, runs and cells)" if st["fast"] else ""
    return (
        '<section id="actuated-drogue"><h2>Actuated drogue: the paper\'s controllers through control surfaces'
        f"{fast}</h2><p>The paper's controllers apply an ideal force at the drogue. Here the drogue makes it with "
        f"{d.surfaces} control surfaces (deflection limit {d.max_deflection_deg:g} deg, rate limit "
        f"{d.max_rate_deg_s:g} deg/s, second-order servos of {d.bandwidth_hz:g} Hz and damping {d.damping:g}, "
        f"C_F,delta = {d.force_slope_per_rad:g} /rad per surface on {d.reference_area_m2:g} m^2, drag increment "
        f"{d.drag_slope_per_rad2:g} /rad^2): the force is q S C_F,delta delta from the dynamic pressure of the air at "
        "the drogue (wake, turbulence, bow wave), the controller's force command is mixed to the surfaces at the "
        "measured q, and the PID's integrator (the LQR's observer) is conditioned on the force the clipped "
        "surfaces make (anti-windup). Where each number comes from: docs/model.md, \"Actuated drogue\".</p>"
        "<p><b>What sizes the servo.</b> The paper's PID crosses over at 8.0 Hz (lateral) and 6.2 Hz (vertical), far "
        "above the drogue's 0.4-0.5 Hz pendulum modes, so a servo of a few hertz destabilizes it; the LQR crosses "
        "over at 3.3 and 2.7 Hz. Phase margins of each loop with the servo (linearized hose, every state):</p>"
        + _margins_html(st["margins"])
        + "<p><b>Convergence to the ideal force.</b> With limits far beyond the force and no drag increment the "
          "surfaces approach the ideal force at first order in 1 / bandwidth (the servo's lag 2 zeta s / omega): "
          f"2 s of the paper's turbulence with the paper's PID (drogue motion {1000 * st['convergence']['ideal_motion_m'].iloc[0]:.2f} mm):</p>"
        + _convergence_html(st["convergence"])
        + f"<p><b>The paper's turbulence case.</b> The paper's PID, ideal force: peak {1000 * ideal['peak_dy_m']:.2f} / "
          f"{1000 * ideal['peak_dz_m']:.2f} mm, RMS {1000 * ideal['rms_dy_m']:.2f} / {1000 * ideal['rms_dz_m']:.2f} mm "
          f"(lateral / vertical), peak force {ideal['peak_u_n']:.0f} N; through the surfaces: peak "
          f"{1000 * act['peak_dy_m']:.2f} / {1000 * act['peak_dz_m']:.2f} mm, RMS {1000 * act['rms_dy_m']:.2f} / "
          f"{1000 * act['rms_dz_m']:.2f} mm, peak force {act['peak_u_n']:.0f} N, largest deflection "
          f"{act['peak_deflection_deg']:.2f} deg, at the deflection limit {100 * act['deflection_saturated_frac']:.1f} % "
          f"and at the rate limit {100 * act['rate_saturated_frac']:.1f} % of the window.</p>"
        + figure_html("fig-actuated-run", "fig_actuated_paper_case.png", "The paper's PID, ideal force and surfaces",
                      "The paper's turbulence case (window shaded): drogue offsets, control forces, the four surfaces' "
                      "deflections (limits dashed) and the dynamic pressure at the drogue.", ("actuated_paper_case.csv",))
        + f"<p><b>The claims in light, moderate and severe turbulence</b> (MIL-F-8785C at 8000 m, the paper's 20 s "
          f"window), {st['seeds']} seed(s) per case, the same gusts for every drogue of a case:</p>"
        + _claims_html(st["claims"])
        + figure_html("fig-actuated-claims", "fig_actuated_claims.png", "Peaks against the paper's 1 cm",
                      "Largest lateral or vertical peak offset over the seeds per case and drogue; dashed: the paper's "
                      "1 cm.", ("actuated_claims.csv", "actuated_claims_runs.csv"))
        + _statement(st["one_cm"], st["margins"])
        + f"<p><b>Capture rate against authority and bandwidth.</b> The approach scenarios with the bow wave on and the "
          f"paper's PID commanding the surfaces, {st['runs']} runs per cell on the docking grid's seeds; the ideal "
          "force's cell is the docking grid's campaign. A run counts as saturated when some surface spent time within "
          "1 % of its deflection limit before contact.</p>"
        + _capture_html(st["capture"])
        + figure_html("fig-actuated-capture", "fig_actuated_capture.png", "Capture rate against the surfaces",
                      "Capture rate (Wilson 95 %) against the deflection limit at the default servo and against the "
                      "servo bandwidth at the default limit; bands: the ideal force's rate.", ("actuated_capture.csv",))
        + "</section>")


def _study(out, settings) -> dict:
    from ..studies.docking import run_grid
    from ..studies.docking_grid import actuator_specs
    from ..studies.docking_statistics import actuator_table

    out.status("actuated drogue: servo margins")
    margins = study.servo_margins((float("inf"),) + study.MARGIN_BANDWIDTHS_HZ)
    convergence = study.convergence_table()
    runs, paper = _paper_case(out, settings)
    claim_runs = study.claims_runs(settings.actuator_seeds, settings.run_duration_s, settings.actuator_levels,
                                   status=out.status)
    claims = study.claims_table(claim_runs)
    specs = actuator_specs(settings.actuator_deflections_deg, settings.actuator_bandwidths_hz,
                           settings.actuator_capture_levels)
    folder = out.dir / CAMPAIGNS
    shutil.rmtree(folder, ignore_errors=True)  # the report's campaigns are its own: never resumed
    cells = run_grid(specs, settings.actuator_runs, folder, status=out.status, share=campaign_share(), plots=False,
                     **campaign_execution(settings.docking_workers))
    return {"margins": margins, "convergence": convergence, "paper": paper, "claim_runs": claim_runs,
            "claims": claims, "one_cm": study.within_one_cm(claims), "capture": actuator_table(specs, cells),
            "seeds": settings.actuator_seeds, "runs": settings.actuator_runs, "fast": settings.fast,
            "paper_runs": runs, "newtons_per_deg": study.authority_n(DrogueActuator(max_deflection_deg=1.0))}


def _write(out, st: dict) -> None:
    import pandas as pd

    from ..studies.drogue_actuator_figures import plot_actuated_run, plot_capture_vs_surfaces, plot_claims

    ideal, act = st["paper_runs"]["ideal"], st["paper_runs"]["actuated"]
    cols = {"t_s": act.t_s, **{f"ideal_{k}": v for k, v in ideal.columns().items() if k in ("drogue_dy_m", "drogue_dz_m",
                                                                                        "u_y_n", "u_z_n")}}
    cols.update({k: v for k, v in act.columns().items() if k != "t_s" and (k.startswith(("deflection", "drogue_q", "u_"))
                                                                         or k in ("drogue_dy_m", "drogue_dz_m"))})
    out.csv(pd.DataFrame(cols), "actuated_paper_case.csv")
    out.csv(st["margins"], "actuated_servo_margins.csv")
    out.csv(st["convergence"], "actuated_convergence.csv")
    out.csv(st["claims"], "actuated_claims.csv")
    out.csv(st["claim_runs"], "actuated_claims_runs.csv")
    out.csv(st["capture"], "actuated_capture.csv")
    from ..scenarios import load_scenario

    window = load_scenario("paper-turbulence-pid").params.turbulence
    out.figure(plot_actuated_run(ideal, act, (window.start_s, window.start_s + window.duration_s),
                                 DrogueActuator().max_deflection_deg), "fig_actuated_paper_case.png")
    out.figure(plot_claims(st["claims"]), "fig_actuated_claims.png")
    out.figure(plot_capture_vs_surfaces(st["capture"], st["newtons_per_deg"]), "fig_actuated_capture.png")


def _finite(record: dict) -> dict:
    """The entries of a record that are not non-finite numbers (report.json holds no nulls: an
    ideal force has no bandwidth or deflection limit, a first row no convergence order)."""
    return {k: v for k, v in record.items() if not (isinstance(v, float) and not np.isfinite(v))}


def _record(st: dict) -> dict:
    cap = st["capture"]
    one_cm = {k: {**v, "worst_peak_m": _finite(v["worst_peak_m"])} for k, v in st["one_cm"].items()}
    return {"paper_case": st["paper"], "within_1cm": one_cm,
            "servo_margins": [_finite(r) for r in st["margins"].to_dict(orient="records")],
            "convergence": [_finite(r) for r in st["convergence"].to_dict(orient="records")],
            "claims": [_finite(r) for r in st["claims"].to_dict(orient="records")],
            "capture": {r["campaign"]: _finite({**capture_record(r, cap.columns),
                                                "max_deflection_deg": r["max_deflection_deg"],
                                                "bandwidth_hz": r["bandwidth_hz"],
                                                "saturated_runs_fraction": r["saturated_runs_fraction"]})
                        for _, r in cap.iterrows()}}


def build(out: ReportFolder, settings: ReportSettings) -> DrogueActuatorResult:
    """Run the actuated-drogue studies and write the section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        ``run_duration_s`` [s] of the turbulence runs, ``actuator_seeds``, ``actuator_levels``, the
        capture study's ``actuator_runs``, ``actuator_deflections_deg`` [deg],
        ``actuator_bandwidths_hz`` [Hz], ``actuator_capture_levels``, and ``docking_workers``.

    Returns
    -------
    DrogueActuatorResult
    """
    t0 = time.perf_counter()
    st = _study(out, settings)
    _write(out, st)
    _add_comparisons(out.comparison, st["paper"])
    ideal, act = st["paper"]["ideal"], st["paper"]["actuated"]
    out.section("actuated-drogue", "actuated drogue", _html(st))
    d, m = DrogueActuator(), st["margins"]
    pid = m[(m["controller"] == "pid") & np.isfinite(m["bandwidth_hz"])]
    unstable = pid.loc[~pid["stable"], "bandwidth_hz"]
    edge = (f"; with a servo of {unstable.max():g} Hz it is unstable (stable from "
            f"{pid.loc[pid['stable'], 'bandwidth_hz'].min():g} Hz)" if len(unstable) else "")
    out.summarize(f"Actuated drogue (surfaces of {d.max_deflection_deg:g} deg, {d.bandwidth_hz:g} Hz servos): the paper's "
                  f"PID in its turbulence case peaks at {1000 * act['peak_dy_m']:.2f} / {1000 * act['peak_dz_m']:.2f} mm "
                  f"(ideal force {1000 * ideal['peak_dy_m']:.2f} / {1000 * ideal['peak_dz_m']:.2f} mm), RMS "
                  f"{1000 * act['rms_dy_m']:.2f} / {1000 * act['rms_dz_m']:.2f} mm (ideal {1000 * ideal['rms_dy_m']:.2f} / "
                  f"{1000 * ideal['rms_dz_m']:.2f} mm){edge}.")
    out.record("drogue_actuator", _record(st))
    return DrogueActuatorResult(paper_case=st["paper"], within_one_cm=st["one_cm"],
                                wall_time_s=time.perf_counter() - t0)
