"""Report section "PID tuned for the plant": ``hosedrogue design pid`` tuning the PID to Table 3's step
figures on the paper's models and on this model, beside the paper's Eq. 33 gains.

The study (:func:`hosedrogue.studies.pid_tuning.pid_tuning_study`) tunes and evaluates; this
module arranges its numbers into a table, a figure of the steps and report.json.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import math

from ..spec.paper import TABLE3
from ..studies.pid_tuning import PLANTS
from .markup import figure_html, html_table

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["build"]

#: Below this smallest damping ratio [-] the text points at the lightly damped pole (as the CLI's note).
LIGHT_DAMPING = 0.2


def _cell(v, spec):
    return "-" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, spec)


def _table(rows) -> str:
    body = []
    for r in rows:
        ref = TABLE3[("PID", r["channel"])]
        body.append((PLANTS[r["plant"]], r["gains"], r["channel"],
                     f"{r['kp_n_per_m']:.5g} / {r['ki_n_per_m_s']:.5g} / {r['kd_n_s_per_m']:.5g} / "
                     f"{r['n_filter_rad_s']:.4g}",
                     _cell(r["min_damping"], ".3f"),
                     f"{r['rise_time_s']:.4f} / {r['settling_time_s']:.3f} / {r['overshoot_pct']:.2f}",
                     f"{ref['rise_time_s']:g} / {ref['settling_time_s']:g} / {ref['overshoot_pct']:g}",
                     (f"{r['larger_rise_time_s']:.4f} / {r['larger_settling_time_s']:.3f} / "
                      f"{r['larger_overshoot_pct']:.2f}") if not math.isnan(r["larger_rise_time_s"]) else "unstable",
                     _cell(1e3 * r["peak_offset_m"], ".1f")))
    return html_table(["plant", "gains", "channel", "K_P [N/m] / K_I [N/(m s)] / K_D [N s/m] / N [rad/s]",
                       "smallest closed-loop damping [-]", "2nd order: rise [s] / settling [s] / overshoot [%]",
                       "Table 3 (the bounds)", "larger model: rise / settling / overshoot",
                       "peak offset in turbulence [mm]"], body, table_id="table-pid-tuning")


def _html(study, rows, duration_s) -> str:
    p = study.params
    by = {(r["plant"], r["gains"], r["channel"]): r for r in rows}
    lat_t, lat_p = by[("model", "tuned", "lateral")], by[("model", "paper Eq. 33", "lateral")]
    ver_paper = by[("paper", "paper Eq. 33", "vertical")]
    miss = 100.0 * (ver_paper["settling_time_s"] / TABLE3[("PID", "vertical")]["settling_time_s"] - 1.0)
    ratios = [r["larger_rise_time_s"] / r["rise_time_s"] for r in rows if not math.isnan(r["larger_rise_time_s"])]
    over = [r["larger_overshoot_pct"] for r in rows if not math.isnan(r["larger_overshoot_pct"])]
    return (
        '<section id="pid-tuning"><h2>PID tuned for the plant</h2>'
        "<p><code>hosedrogue design pid</code> tunes the PID of each channel so that its unit step on the "
        "2nd-order design model meets the bounds (rise time, settling time and overshoot at most), Table 3's "
        "PID rows by default (docs/tuning.md: a global search for the least high-frequency gain K_P + K_D N "
        "that meets them). On the paper's models the tuned gains meet Table 3 where Eq. 33 "
        f"misses the vertical settling time by {miss:+.1f} %; they differ from Eq. 33 because bounds leave a "
        "region of gains and the cost picks its cheapest. On this model at "
        f"{p.flight.airspeed_m_s:g} m/s, {p.flight.altitude_m:g} m ({p.hose.length_m:g} m hose), where Eq. 33 "
        f"overshoots {lat_p['overshoot_pct']:.1f} %, the tuned gains meet the bounds too"
        + (f", but the lateral design's least damped closed-loop pole is damped only {lat_t['min_damping']:.3f}: "
           "the step's three figures do not show it, the response to gusts does."
           if lat_t["min_damping"] < LIGHT_DAMPING else ".")
        + f" In the paper's turbulence case ({duration_s:g} s, the nonlinear model) the tuned gains leave a peak "
        f"lateral offset of {1e3 * lat_t['peak_offset_m']:.1f} mm against Eq. 33's {1e3 * lat_p['peak_offset_m']:.1f} mm"
        + (": the targets' 1 s settling asks for weaker low-frequency action than Eq. 33 has on this plant."
           if lat_t["peak_offset_m"] > lat_p["peak_offset_m"] else ".")
        + " Closed around "
        f"the larger models both sets of gains rise in {min(ratios):.2f}-{max(ratios):.2f} of the time and "
        f"overshoot {min(over):.1f}-{max(over):.1f} %: the 2nd-order model leaves out the hose modes that a "
        "0.07 s rise reaches.</p>"
        + _table(rows)
        + figure_html("fig-pid-tuning", "pid_tuning_steps.png", "PID tuned for the plant",
                      "Unit reference steps with the tuned gains and with Eq. 33 on the 2nd-order design models "
                      "(solid) and on the larger models (dashed: the paper's 6th order, this model's full order), "
                      "on the paper's models (top) and this model (bottom); logarithmic time.",
                      ("pid_tuning.csv",))
        + "</section>"
    )


def build(out: ReportFolder, settings: ReportSettings) -> None:
    """Tune the PID to Table 3 on both plants, compare with Eq. 33: table, figure, report.json.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Length of the turbulence runs (``run_duration_s``).

    Returns
    -------
    None
    """
    import pandas as pd

    from ..studies.pid_tuning import pid_tuning_study

    study = pid_tuning_study(duration_s=settings.run_duration_s)
    rows = study.rows()
    out.csv(pd.DataFrame(rows), "pid_tuning.csv")
    out.figure(study.figures()["steps"], "pid_tuning_steps.png")
    duration = settings.run_duration_s or 60.0
    out.section("pid-tuning", "PID tuning", _html(study, rows, duration))
    # report.json holds finite numbers only: a figure that does not exist (no turbulence run on the
    # paper's models, an unstable loop around the larger model) is left out of its row
    out.record("pid_tuning", [{k: v for k, v in r.items() if not (isinstance(v, float) and not math.isfinite(v))}
                              for r in rows])
    return None
