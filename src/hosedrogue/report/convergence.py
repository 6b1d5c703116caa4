"""Report section "Convergence": the RK4 step and the number of links.

The studies themselves are library code (``hosedrogue.studies.convergence``, imported in
:func:`_studies` only); this module derives the report's findings from them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..spec.params import PAPER
from .markup import figure_html, html_table, slash_join

if TYPE_CHECKING:
    from .parameters import ParametersResult
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["ConvergenceResult", "build"]

#: Labels of the three bending models of the link study (CSV values and JSON keys).
PAPER_BENDING, BENDING_OFF, BENDING_MOMENT = "paper bending (Eq. 20)", "bending off", "bending 'moment'"

#: The step is called converged when the drogue-position error is below this [m].
STEP_TOLERANCE_M = 1e-4


@dataclass(frozen=True)
class ConvergenceResult:
    """The link-count finding, quoted by the differences section.

    Parameters
    ----------
    paper_links : tuple of int
        Link counts with the paper's bending force.
    paper_z_m : tuple of float
        Drogue balance z for those counts [m].
    consistent_links : tuple of int
        Link counts with bending off and with the "moment" option.
    off_z_m : tuple of float
        Drogue balance z with bending off [m].
    moment_z_m : tuple of float
        Drogue balance z with the "moment" option [m].
    paper_converges : bool
        Whether the paper's bending force converges with the link count.
    continuum_z_m : float
        Richardson estimate of the continuum drogue z (bending off) [m].
    """

    paper_links: tuple
    paper_z_m: tuple
    consistent_links: tuple
    off_z_m: tuple
    moment_z_m: tuple
    paper_converges: bool
    continuum_z_m: float


def _studies(settings):
    """Run the step study (three cases) and the link study (three bending models)."""
    from ..studies.convergence import STEP_CASES, link_convergence, step_convergence

    studies = [step_convergence(c, settings.steps_s, settings.reference_step_s) for c in STEP_CASES]
    link_studies = {
        PAPER_BENDING: link_convergence(settings.links_paper_bending),
        BENDING_OFF: link_convergence(settings.links_consistent, params=PAPER.replace(hose={"bending": "off"})),
        BENDING_MOMENT: link_convergence(settings.links_consistent, params=PAPER.replace(hose={"bending": "moment"})),
    }
    return studies, link_studies


def _zs(ls) -> np.ndarray:
    return ls.drogue_position_m[:, 2]


def _link_finding(link_studies) -> ConvergenceResult:
    """Whether each bending model converges, and the continuum estimate."""
    paper_ls, off_ls, mom_ls = (link_studies[k] for k in (PAPER_BENDING, BENDING_OFF, BENDING_MOMENT))
    d_paper = np.abs(np.diff(_zs(paper_ls)))
    paper_converges = bool(d_paper[-1] < 0.7 * d_paper[0]) if d_paper.size > 1 else False
    # first-order Richardson estimate of the continuum limit from the two finest bending-off runs
    n1, n2 = off_ls.links[-2], off_ls.links[-1]
    z_off = _zs(off_ls)
    z_limit = float(z_off[-1] + (z_off[-1] - z_off[-2]) * n1 / (n2 - n1))
    return ConvergenceResult(
        paper_links=tuple(paper_ls.links), paper_z_m=tuple(_zs(paper_ls)), consistent_links=tuple(off_ls.links),
        off_z_m=tuple(z_off), moment_z_m=tuple(_zs(mom_ls)), paper_converges=paper_converges, continuum_z_m=z_limit)


def _write_csv(out, studies, link_studies) -> None:
    import pandas as pd

    rows = []
    for st in studies:
        order = np.concatenate([[np.nan], st.observed_order])
        for h, e, o in zip(st.steps_s, st.max_error_m, order):
            rows.append(dict(case=st.case, step_s=h, max_error_m=e, observed_order=o,
                             reference_step_s=st.reference_step_s, duration_s=st.duration_s))
    out.csv(pd.DataFrame(rows), "convergence_steps.csv")
    lrows = []
    for label, ls in link_studies.items():
        for k, n in enumerate(ls.links):
            x, y, z = ls.drogue_position_m[k]
            lrows.append(dict(bending=label, links=int(n), drogue_x_m=x, drogue_y_m=y, drogue_z_m=z,
                              lowest_lateral_rad_s=ls.lowest_lateral_rad_s[k],
                              lowest_vertical_rad_s=ls.lowest_vertical_rad_s[k]))
    out.csv(pd.DataFrame(lrows), "convergence_links.csv")


def _tables(settings, studies, link_studies) -> tuple[str, str]:
    step_rows = [(st.case, *[f"{1000 * e:.3g}" for e in st.max_error_m],
                  " / ".join(f"{o:.2f}" for o in st.observed_order)) for st in studies]
    step_table = html_table(["case", *[f"h = {h:g} s: error [mm]" for h in settings.steps_s], "observed order"],
                            step_rows, table_id="table-step-convergence")
    link_rows = [(label, slash_join((int(n) for n in ls.links), "d"), slash_join(_zs(ls), ".2f"),
                  " / ".join(f"{w:.3f}" for w in ls.lowest_lateral_rad_s),
                  " / ".join(f"{w:.3f}" for w in ls.lowest_vertical_rad_s)) for label, ls in link_studies.items()]
    link_table = html_table(["bending model", "links", "drogue z [m]", "lowest lateral mode [rad/s]",
                             "lowest vertical mode [rad/s]"], link_rows, table_id="table-link-convergence")
    return step_table, link_table


def _link_prose(f: ConvergenceResult, link_studies, bending_stiffness_n_m2: float) -> str:
    d_paper = np.abs(np.diff(f.paper_z_m))
    d_off = np.abs(np.diff(f.off_z_m))
    off_converges = bool(np.all(d_off[1:] < 0.7 * d_off[:-1])) if d_off.size > 1 else False
    n = PAPER.hose.links
    z20 = {label: float(_zs(ls)[list(ls.links).index(n)]) for label, ls in link_studies.items() if n in list(ls.links)}
    shift_cm = abs(z20.get(PAPER_BENDING, np.nan) - z20.get(BENDING_OFF, np.nan)) * 100
    links = lambda ns: slash_join((int(n) for n in ns), "d")  # noqa: E731
    return (
        f"<p>The link-count study solves the balance position and linearizes it for several link "
        f"counts. <b>Finding:</b> with the paper's equivalent bending force (Eq. 20, 8 E I &gamma; / l<sup>2</sup>) "
        f"the balance position does <b>{'' if f.paper_converges else 'not '}converge</b> as links are added: "
        f"drogue z = {slash_join(f.paper_z_m, '.2f')} m for {links(f.paper_links)} links, the changes "
        f"({' / '.join(f'{d:.3f}' for d in d_paper)} m) {'shrink' if f.paper_converges else 'do not shrink'}. "
        f"For a given hose shape the bend angle per joint is &gamma; &asymp; &kappa; l, so the force per joint is "
        f"&asymp; 8 E I &kappa; / l: it grows as 1/l as the links get shorter, instead of tending to the "
        f"distributed load of a beam. The equivalent force is not a consistent discretization of "
        f"bending. With bending off, or with the conservative <code>moment</code> option (restoring "
        f"moment E I &gamma; / l = E I &kappa;), the position converges: z = {slash_join(f.off_z_m, '.2f')} m (off) and "
        f"{slash_join(f.moment_z_m, '.2f')} m (moment) for {links(f.consistent_links)} links, the changes "
        f"({' / '.join(f'{d:.4f}' for d in d_off)} m) {'halving with each doubling (first order in l)' if off_converges else 'not yet regular'}; "
        f"a Richardson estimate of the continuum limit is z &asymp; {f.continuum_z_m:.3f} m (the "
        f'<a href="#accuracy">accuracy-per-cost section</a> measures every link count against the continuous hose '
        f"itself, for the paper's and a second-order mass lumping). The real hose's "
        f"bending stiffness (E I &asymp; {bending_stiffness_n_m2:.1f} N m<sup>2</sup>) hardly matters: "
        f"bending off and 'moment' agree to millimetres. At the paper's {n} links the paper force moves "
        f"the drogue by {shift_cm:.1f} cm "
        f"relative to bending off, so the results at {n} links are little affected; the lowest mode "
        f"frequencies change by a few per cent.</p>"
    )


def _html(settings, h0, worst, tables, link_prose) -> str:
    step_table, link_table = tables
    verdict = "below" if worst < STEP_TOLERANCE_M else "above"
    return (
        '<section id="convergence"><h2>Convergence: integration step and number of links</h2>'
        f"<p>The RK4 step study runs three cases (a strong free swing, the paper's turbulence case, "
        f"and the same with the paper's PID in the loop) at several steps and compares the drogue "
        f"position with a run at {settings.reference_step_s:g} s. At the default step "
        f"<b>{h0:g} s</b> the largest drogue-position error over the three cases is "
        f"<b>{1000 * worst:.3g} mm</b>, {verdict} {1000 * STEP_TOLERANCE_M:g} mm: the default step is converged for every "
        f"result in this report. The observed order is about 4 for the smooth swing (RK4); with "
        f"turbulence it is irregular because the gust record is interpolated between its "
        f"{PAPER.turbulence.sample_time_s:g} s samples, but the errors stay small.</p>"
        + step_table + link_prose + link_table
        + figure_html("fig-convergence", "fig_convergence.png", "Convergence study",
                      "(a) Largest drogue-position error against the RK4 step for the three cases, with "
                      "a 4th-order guide and the 0.1 mm line; (b) drogue balance height against the "
                      "number of links for the three bending models; (c) lowest lateral (solid) and "
                      "vertical (dashed) mode frequencies against the number of links.",
                      ("convergence_steps.csv", "convergence_links.csv"))
        + "</section>"
    )


def build(out: ReportFolder, settings: ReportSettings, *, parameters: ParametersResult) -> ConvergenceResult:
    """Run both convergence studies; write their CSV files, figure and section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Steps, reference step and link counts of the studies.
    parameters : hosedrogue.report.parameters.ParametersResult
        Provides the hose's bending stiffness [N m^2] quoted in the prose.

    Returns
    -------
    ConvergenceResult
        The link-count finding.
    """
    from ..studies.convergence_figures import plot_convergence

    studies, link_studies = _studies(settings)
    finding = _link_finding(link_studies)
    h0 = PAPER.numerics.step_s
    at_default = {st.case: float(st.max_error_m[np.argmin(np.abs(st.steps_s - h0))]) for st in studies}
    worst = max(at_default.values())

    _write_csv(out, studies, link_studies)
    out.figure(plot_convergence(studies, link_studies), "fig_convergence.png")
    prose = _link_prose(finding, link_studies, parameters.bending_stiffness_n_m2)
    out.section("convergence", "convergence", _html(settings, h0, worst, _tables(settings, studies, link_studies), prose))
    out.summarize(f"RK4 at the default step {h0:g} s: drogue error at most {1000 * worst:.3g} mm. The paper's "
                  f"equivalent bending force {'converges' if finding.paper_converges else 'does not converge'} with "
                  "the link count (it scales as 1/l); bending off / 'moment' converge.")
    out.record("convergence", {
        "default_step_s": h0,
        "max_drogue_error_at_default_step_m": at_default,
        "worst_error_at_default_step_m": worst,
        "links": {label: {"links": [int(n) for n in ls.links], "drogue_z_m": _zs(ls).tolist(),
                          "lowest_lateral_rad_s": ls.lowest_lateral_rad_s.tolist(),
                          "lowest_vertical_rad_s": ls.lowest_vertical_rad_s.tolist()}
                  for label, ls in link_studies.items()},
        "paper_bending_converges": finding.paper_converges,
        "continuum_drogue_z_estimate_m": finding.continuum_z_m,
    })
    return finding
