"""Report section "Accuracy per cost" (docs/convergence.md, docs/benchmarks.md): the link
model against the continuous hose for both mass lumpings, the step of the shipped
``paper-turbulence`` scenario, and the time-to-accuracy benchmark (quoted, not run).

The studies are library code (:mod:`hosedrogue.studies.accuracy`,
:func:`hosedrogue.analysis.continuum.solve_continuum`, imported in :func:`_studies` only). The
"Convergence" section (:mod:`.convergence`) keeps the paper's case (aft lumping, the paper's
bending and inertia); this one measures every count against the continuum instead, and each
section links to the other.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .markup import figure_html, html_table
from .settings import FULL

if TYPE_CHECKING:
    from .convergence import ConvergenceResult
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["AccuracyResult", "BENCHMARK", "build"]

#: The lumpings compared: the well-converging one first, then the paper's.
LUMPINGS = ("split", "aft")
#: Steady-drogue tolerances of the time-to-accuracy benchmark [m].
TOLERANCES_M = (1e-2, 1e-3)
#: Largest acceptable drogue error of the scenario's step [m] (docs/convergence.md).
STEP_TOLERANCE_M = 1e-4

#: The time-to-accuracy figures of docs/benchmarks.md ("Accuracy per cost", measured 2026-11-30 by
#: ``benchmarks/time_to_accuracy.py`` on the 2-core CI machine under load, with MoorDyn 2.7.2):
#: model, links for 1 cm, wall of a 60 s run [s], its step [s], links for 1 mm, wall [s], step [s],
#: whether the 1 mm figures are estimates, note. Quoted only: the report never runs MoorDyn.
BENCHMARK = (
    ("hosedrogue split", 3, 0.025, 0.02, 9, 0.032, 0.02, False, ""),
    ("hosedrogue aft (paper)", 158, 1.7, 3.2e-3, 1580, 850.0, float("nan"), True,
     "1 mm figures estimated (order-1 error, cost ~ n^2)"),
    ("MoorDyn 2.7.2, RK2", 3, 0.14, 3.6e-3, 5, 1.2, 3.8e-4, False,
     "EA 5e6 N at 1 cm (5.8 mm); EA 1e8 N at 1 mm (0.59 mm), axial stretch is its own error"),
)


@dataclass(frozen=True)
class AccuracyResult:
    """Headline numbers of the section.

    Parameters
    ----------
    links : tuple of int
        Link counts of the study.
    split_error_m, aft_error_m : tuple of float
        Steady drogue distance from the continuum per link count [m].
    split_order, aft_order : float
        Observed order of that error at the two finest counts [-].
    step_error_m : float
        Drogue error of ``paper-turbulence`` at its 0.02 s step against the reference step [m].
    """

    links: tuple
    split_error_m: tuple
    aft_error_m: tuple
    split_order: float
    aft_order: float
    step_error_m: float


def _studies(settings):
    """Continuum, both lumpings (with dynamics), the scenario step study and the live fewest-links check."""
    from ..analysis.continuum import solve_continuum
    from ..studies.accuracy import STUDY_BASE, fewest_links, lumping_convergence, scenario_step_study

    cont = solve_continuum(STUDY_BASE)
    lumps = {k: lumping_convergence(k, settings.accuracy_links, continuum=cont) for k in LUMPINGS}
    step = scenario_step_study(steps_s=settings.accuracy_steps_s, reference_step_s=settings.accuracy_reference_step_s)
    # the benchmark's case (wake off: MoorDyn has none): is its 'split' link count reproduced?
    bench = STUDY_BASE.replace(wake={"enabled": False}, turbulence={"enabled": False})
    bench_cont = solve_continuum(bench)
    fewest = {tol: fewest_links("split", tol, base=bench, continuum=bench_cont) for tol in TOLERANCES_M}
    return cont, lumps, step, fewest


def _write_csv(out, cont, lumps, step) -> None:
    import pandas as pd

    rows = []
    for name, st in lumps.items():
        order = np.concatenate([[np.nan], st.position_orders])
        for k, n in enumerate(st.links):
            x, y, z = st.drogue_position_m[k]
            rows.append(dict(lumping=name, links=int(n), drogue_x_m=x, drogue_y_m=y, drogue_z_m=z,
                             error_vs_continuum_m=st.position_error_m[k], observed_order=order[k],
                             lowest_lateral_rad_s=st.frequencies.lateral_rad_s[k],
                             lowest_vertical_rad_s=st.frequencies.vertical_rad_s[k],
                             rms_lateral_m=st.rms_response_m[k, 0], rms_vertical_m=st.rms_response_m[k, 1],
                             turbulence_run_wall_s=st.turbulence_wall_s[k]))
    out.csv(pd.DataFrame(rows), "accuracy_links.csv")
    crows = [dict(solution="continuum", x_m=cont.drogue_position_m[0], y_m=cont.drogue_position_m[1],
                  z_m=cont.drogue_position_m[2], distance_from_continuum_m=0.0, shooting_residual_m=cont.position_error_m)]
    for name, st in lumps.items():
        e = st.extrapolated_m
        crows.append(dict(solution=f"Richardson limit, {name}", x_m=e[0], y_m=e[1], z_m=e[2],
                          distance_from_continuum_m=float(np.linalg.norm(e - st.continuum_m)),
                          shooting_residual_m=np.nan))
    out.csv(pd.DataFrame(crows), "accuracy_continuum.csv")
    out.csv(pd.DataFrame({"step_s": step.steps_s, "max_error_m": step.max_error_m,
                          "reference_step_s": step.reference_step_s, "duration_s": step.duration_s,
                          "reading_change_m": step.reading_change_m}), "accuracy_step.csv")
    cols = ["model", "links_1cm", "wall_60s_1cm_s", "step_1cm_s", "links_1mm", "wall_60s_1mm_s", "step_1mm_s",
            "estimated_1mm", "note"]
    out.csv(pd.DataFrame([dict(zip(cols, r)) for r in BENCHMARK]), "accuracy_time_to_accuracy.csv")


def _orders(values) -> str:
    return " / ".join(f"{o:.2f}" for o in values) if len(values) else "-"


def _link_tables(lumps) -> str:
    """Position error, lowest modes and turbulence RMS against the link count, one row per lumping."""
    links = next(iter(lumps.values())).links
    head = [f"{int(n)}" for n in links]
    pos = [(name, *(f"{1e3 * e:.3g}" for e in st.position_error_m), _orders(st.position_orders))
           for name, st in lumps.items()]
    t_pos = html_table(["lumping", *(f"{h} links [mm]" for h in head), "observed orders"], pos,
                       table_id="table-accuracy-position",
                       caption="Steady drogue distance from the continuous hose")
    modes = [(f"{name}, {ch}", *(f"{w:.4f}" for w in ws), _orders(orders))
             for name, st in lumps.items()
             for ch, ws, orders in (("lateral", st.frequencies.lateral_rad_s, st.frequencies.lateral_orders),
                                    ("vertical", st.frequencies.vertical_rad_s, st.frequencies.vertical_orders))]
    t_modes = html_table(["lumping, mode", *(f"{h} links [rad/s]" for h in head), "orders (3 doublings)"], modes,
                         table_id="table-accuracy-modes", caption="Lowest lateral / vertical mode frequencies")
    rms = [(name, *(f"{1e3 * r[0]:.2f} / {1e3 * r[1]:.2f}" for r in st.rms_response_m),
            " / ".join(f"{w:.2f}" for w in st.turbulence_wall_s)) for name, st in lumps.items()]
    t_rms = html_table(["lumping", *(f"{h} links: lat / ver [mm]" for h in head), "wall per 60 s run [s]"], rms,
                       table_id="table-accuracy-rms",
                       caption="RMS drogue offset in the paper's turbulence case (60 s, seed 2018, RK4 0.005 s)")
    return t_pos + t_modes + t_rms


def _limit_table(cont, lumps) -> str:
    rows = [("continuum (shooting)", *(f"{v:.6f}" for v in cont.drogue_position_m),
             f"residual {cont.position_error_m:.1e}")]
    for name, st in lumps.items():
        e = st.extrapolated_m
        rows.append((f"Richardson limit of {name} ({int(st.links[-2])}/{int(st.links[-1])} links)",
                     *(f"{v:.6f}" for v in e), f"{1e3 * np.linalg.norm(e - st.continuum_m):.2g}"))
    return html_table(["solution", "drogue x [m]", "drogue y [m]", "drogue z [m]", "distance from continuum [mm]"],
                      rows, table_id="table-accuracy-continuum",
                      caption="Continuum limit against the extrapolated link model")


def _step_table(step) -> str:
    rows = [(f"{h:g}", f"{1e3 * e:.3g}", "yes" if e < STEP_TOLERANCE_M else "no")
            for h, e in zip(step.steps_s, step.max_error_m)]
    return html_table(["RK4 step [s]", f"max drogue error vs {step.reference_step_s:g} s [mm]",
                       f"within {1e3 * STEP_TOLERANCE_M:g} mm"], rows, table_id="table-accuracy-step",
                      caption=f"Shipped scenario paper-turbulence ({step.duration_s:g} s)")


def _cost_table() -> str:
    def wall(w, h):
        return f"{w:g} s" + (f" (h {h:g} s)" if np.isfinite(h) else "")

    rows = [(m, f"{n1}", wall(w1, h1), ("~" if est else "") + f"{n2}", ("~" if est else "") + wall(w2, h2), note)
            for m, n1, w1, h1, n2, w2, h2, est, note in BENCHMARK]
    return html_table(["model", "1 cm: links", "1 cm: wall of 60 s", "1 mm: links", "1 mm: wall of 60 s", "note"],
                      rows, table_id="table-accuracy-cost",
                      caption="Time to accuracy (benchmark figures quoted from docs/benchmarks.md, not run here)")


def _at(st, n: int, values):
    """``values`` at link count ``n`` (or the nearest count of the study)."""
    return values[int(np.argmin(np.abs(st.links - n)))]


def _prose(settings, cont, lumps, step, fewest, convergence) -> str:
    """Findings, every number read from the studies; links to the convergence section."""
    sp, af = lumps["split"], lumps["aft"]
    fine = int(sp.links[-1])
    n = 20 if 20 in sp.links and fine > 20 else int(sp.links[-2])  # compared with the finest count
    rel = lambda st, w: abs(_at(st, n, w) / w[-1] - 1) * 100  # noqa: E731
    d_rms = lambda st: 1e3 * np.abs(_at(st, n, st.rms_response_m) - st.rms_response_m[-1])  # noqa: E731
    n20 = int(_at(sp, 20, sp.links))
    h = float(step.steps_s[int(np.argmin(np.abs(step.steps_s - 0.02)))])
    e_h = float(step.max_error_m[int(np.argmin(np.abs(step.steps_s - 0.02)))])
    conv_z = abs(convergence.continuum_z_m - cont.drogue_position_m[2]) * 1e3
    fast = (f'<p class=diff id="accuracy-fast">FAST VERSION of this section: {"/".join(str(int(k)) for k in sp.links)} '
            f"links (full: {'/'.join(str(k) for k in FULL.accuracy_links)}), step {'/'.join(f'{h:g}' for h in step.steps_s)} s "
            f"against {step.reference_step_s:g} s (full: {'/'.join(f'{h:g}' for h in FULL.accuracy_steps_s)} s against "
            f"{FULL.accuracy_reference_step_s:g} s).</p>" if settings.fast else "")
    return (
        fast +
        "<p>Every link count is measured here against the <b>continuous hose</b> (the towed-cable boundary-value "
        "problem solved by shooting, <code>hosedrogue steady --continuum</code>) at the paper's flight condition, "
        "wake on, bending off (the continuum neglects it; the hose's E I hardly matters) and rod link inertia "
        "(m l<sup>2</sup>/12, so that the frequencies have a limit), for both mass lumpings: <code>aft</code>, the "
        "paper's (each link's mass at its aft joint), and <code>split</code> (half at each end). The paper's own "
        'case, with its bending force and fixed link inertia, is the <a href="#convergence">convergence section</a>.</p>'
        f"<p><b>Steady drogue.</b> At {n20} links <code>split</code> is {1e3 * _at(sp, n20, sp.position_error_m):.3g} mm "
        f"from the continuum and converges at order {sp.position_orders[-1]:.2f}; the paper's <code>aft</code> is "
        f"{1e3 * _at(af, n20, af.position_error_m):.3g} mm off, order {af.position_orders[-1]:.2f}. The Richardson "
        f"limits at {int(sp.links[-2])}/{fine} links (order 2 and 1) are "
        f"{1e3 * np.linalg.norm(sp.extrapolated_m - cont.drogue_position_m):.2g} mm and "
        f"{1e3 * np.linalg.norm(af.extrapolated_m - cont.drogue_position_m):.2g} mm from the continuum: the link "
        "model and the independently solved continuum agree, and the paper's lumping is what costs the "
        f"centimetres. The convergence section's first-order estimate of the limit (paper's lumping, bending off, "
        f"z &asymp; {convergence.continuum_z_m:.3f} m) is {conv_z:.2g} mm from the continuum's "
        f"z = {cont.drogue_position_m[2]:.4f} m.</p>"
        f"<p><b>Dynamics.</b> At {n} links the lowest lateral / vertical frequencies are within "
        f"{rel(sp, sp.frequencies.lateral_rad_s):.2g} / {rel(sp, sp.frequencies.vertical_rad_s):.2g} % of their "
        f"{fine}-link values with <code>split</code>, {rel(af, af.frequencies.lateral_rad_s):.2g} / "
        f"{rel(af, af.frequencies.vertical_rad_s):.2g} % with <code>aft</code>; the RMS turbulence response within "
        f"{d_rms(sp)[0]:.2g} / {d_rms(sp)[1]:.2g} mm (<code>split</code>) and {d_rms(af)[0]:.2g} / "
        f"{d_rms(af)[1]:.2g} mm (<code>aft</code>). This is why the <code>converged</code> preset uses "
        f'<code>split</code> at 20 links (<a href="#long-runs">long-runs section</a>).</p>'
        f"<p><b>Step.</b> The shipped <code>paper-turbulence</code> scenario steps RK4 at {h:g} s (cubic gust "
        f"reading averaged over 0.02 s): its drogue error against {step.reference_step_s:g} s is "
        f"<b>{1e3 * e_h:.3g} mm</b>, {'within' if e_h < STEP_TOLERANCE_M else 'ABOVE'} "
        f"{1e3 * STEP_TOLERANCE_M:g} mm; at {step.reference_step_s:g} s its gust reading and the paper's linear "
        f"reading differ by {1e3 * step.reading_change_m:.3g} mm (the paper's case in the rest of "
        "this report keeps the paper's reading at 0.005 s, whose step study is in the convergence section).</p>"
        f"<p><b>Cost.</b> The time-to-accuracy figures below come from <code>benchmarks/time_to_accuracy.py</code> "
        "(docs/benchmarks.md, measured 2026-11-30 on the 2-core CI machine under load, MoorDyn 2.7.2); they "
        "are quoted, not rerun (the report does not run MoorDyn). Recomputed here in the benchmark's case "
        f"(wake off): <code>split</code> needs {fewest[1e-2]} links for 1 cm and {fewest[1e-3]} for 1 mm "
        f"(benchmark: {BENCHMARK[0][1]} and {BENCHMARK[0][4]}). At 1 mm <code>split</code> is "
        f"{BENCHMARK[2][5] / BENCHMARK[0][5]:.0f} x faster than MoorDyn.</p>"
    )


def _html(prose: str, tables: str, limit: str, step: str, cost: str) -> str:
    return (
        '<section id="accuracy"><h2>Accuracy per cost: links against the continuous hose</h2>'
        + prose + tables + limit
        + figure_html("fig-accuracy", "fig_accuracy.png", "Accuracy against the number of links",
                      "(a) Steady drogue distance from the continuous hose for both mass lumpings, with order-1 "
                      "and order-2 guides and the 1 cm / 1 mm lines; (b) lowest lateral (solid) and vertical "
                      "(dashed) mode frequencies; (c) RMS drogue offset in the paper's turbulence case.",
                      ("accuracy_links.csv", "accuracy_continuum.csv"))
        + step + cost + "</section>"
    )


def build(out: ReportFolder, settings: ReportSettings, *, convergence: ConvergenceResult) -> AccuracyResult:
    """Run the accuracy studies; write their CSV files, figure and section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Link counts, steps [s] and reference step [s] of the studies.
    convergence : hosedrogue.report.convergence.ConvergenceResult
        Its continuum estimate [m] is compared with the continuum solution.

    Returns
    -------
    AccuracyResult
        Headline numbers.
    """
    from ..studies.accuracy_figures import plot_accuracy

    cont, lumps, step, fewest = _studies(settings)
    _write_csv(out, cont, lumps, step)
    out.figure(plot_accuracy(list(lumps.values()), tolerances_m=TOLERANCES_M), "fig_accuracy.png")
    out.section("accuracy", "accuracy per cost", _html(_prose(settings, cont, lumps, step, fewest, convergence),
                                                       _link_tables(lumps), _limit_table(cont, lumps),
                                                       _step_table(step), _cost_table()))
    sp, af = lumps["split"], lumps["aft"]
    i20 = int(np.argmin(np.abs(sp.links - 20)))
    i_step = int(np.argmin(np.abs(step.steps_s - 0.02)))
    res = AccuracyResult(links=tuple(int(n) for n in sp.links), split_error_m=tuple(sp.position_error_m),
                         aft_error_m=tuple(af.position_error_m), split_order=float(sp.position_orders[-1]),
                         aft_order=float(af.position_orders[-1]), step_error_m=float(step.max_error_m[i_step]))
    out.summarize(f"Accuracy per cost: at {int(sp.links[i20])} links the steady drogue is "
                  f"{1e3 * sp.position_error_m[i20]:.2g} mm from the continuous hose with 'split' lumping (order "
                  f"{res.split_order:.1f}) and {1e3 * af.position_error_m[i20]:.0f} mm with the paper's 'aft' (order "
                  f"{res.aft_order:.1f}); paper-turbulence at 0.02 s is {1e3 * res.step_error_m:.2g} mm from a fine step.")
    out.record("accuracy", {
        "continuum_drogue_m": cont.drogue_position_m.tolist(),
        **{name: {k: v for k, v in st.to_dict().items() if k != "lumping"} for name, st in lumps.items()},
        "extrapolated_distance_m": {name: float(np.linalg.norm(st.extrapolated_m - cont.drogue_position_m))
                                    for name, st in lumps.items()},
        "convergence_section_limit_z_error_m": abs(convergence.continuum_z_m - cont.drogue_position_m[2]),
        "step": {"steps_s": step.steps_s.tolist(), "max_error_m": step.max_error_m.tolist(),
                 "reference_step_s": step.reference_step_s, "reading_change_m": step.reading_change_m},
        "fewest_links_split_wake_off": {f"{1e3 * tol:g}_mm": n for tol, n in fewest.items()},
        "benchmark_quoted": {"source": "docs/benchmarks.md (benchmarks/time_to_accuracy.py, 2026-11-30)",
                             "split_1mm_wall_60s_s": BENCHMARK[0][5], "moordyn_1mm_wall_60s_s": BENCHMARK[2][5],
                             "split_speedup_at_1mm": BENCHMARK[2][5] / BENCHMARK[0][5]},
    })
    return res
