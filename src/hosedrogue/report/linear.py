"""Report section "Table 2" and "Figs. 5-8": the linearized model, its balanced truncations and
the paper's Table 2 models.

The linear models come from the library (``analysis.linearize``, ``analysis.reduction``,
``analysis.responses``, ``controllers.design``). The Figs. 5-8 part is in
:mod:`.linear_responses`; the section's result, :class:`.section_results.LinearResult`, is shared
by both and the controllers' section.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..analysis.reduction import second_order_characteristics
from ..analysis.responses import freq_response
from ..spec.paper import CHANNELS, TABLE2
from ..spec.params import PAPER
from .linear_responses import responses_section
from .markup import fmt, html_table, ratio
from .section_results import LinearResult

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .sweep import SteadyResult
    from .writer import ReportFolder

__all__ = ["LinearResult", "build"]

#: The paper's note on every Table 2 comparison row.
_CONDITION_NOTE = (f"the paper's linearization flight condition is not stated; ours is {PAPER.flight.airspeed_m_s:g} m/s, "
                   f"{PAPER.flight.altitude_m:g} m, wake on (see the linearization-condition table)")


def _models(equilibrium) -> LinearResult:
    from ..analysis.linearize import linearize
    from ..controllers.design import reduced_channels

    lm = linearize(PAPER, equilibrium)
    return LinearResult(lm, reduced_channels(lm, None), reduced_channels(lm, 6), reduced_channels(lm, 2))


def _table2(m: LinearResult):
    """Table 2 side by side: (HTML rows of transfer functions, HTML rows and CSV rows of coefficients)."""
    from ..analysis.reduction import format_tf, table2_form

    t2_rows, coeff_rows, csv_rows = [], [], []
    for o in (6, 2):
        for ch in CHANNELS:
            num, den = table2_form(getattr(m.sixth if o == 6 else m.second, ch))
            pnum, pden = (np.asarray(v, float) for v in TABLE2[(ch, o)])
            t2_rows.append((f"{o}th order" if o == 6 else "2nd order", ch, format_tf(pnum, pden), format_tf(num, den)))
            for which, a, b in (("num", pnum, num), ("den", pden, den)):
                deg = a.size - 1
                bb = np.concatenate([np.zeros(max(0, a.size - b.size)), b])[-a.size:] if b.size <= a.size else b[-a.size:]
                for k in range(a.size):
                    pw = deg - k
                    r = ratio(bb[k], a[k])
                    coeff_rows.append((f"{o}", ch, which, f"s^{pw}", fmt(a[k]), fmt(bb[k]), fmt(r, 3)))
                    csv_rows.append(dict(order=o, channel=ch, polynomial=which, power=pw, paper=a[k], ours=bb[k], ratio=r))
    return t2_rows, coeff_rows, csv_rows


_CHARACTERISTICS = (("dc_gain_m_n", "DC gain", "m/N"), ("natural_frequency_rad_s", "natural frequency", "rad/s"),
                    ("damping_ratio", "damping ratio", "-"), ("zero_1_s", "zero", "1/s"))


def _characteristics(m: LinearResult, comparison):
    """2nd-order characteristics, ours vs the paper's; adds the Table 2 comparison rows.

    Returns (HTML rows, CSV rows, the ``report.json`` entry).
    """
    from ..analysis.reduction import table2_form

    char_rows, char_csv, head = [], [], {}
    for ch in CHANNELS:
        pc = second_order_characteristics(*TABLE2[(ch, 2)])
        oc = second_order_characteristics(*table2_form(getattr(m.second, ch)))
        head[ch] = {}
        for key, label, unit in _CHARACTERISTICS:
            r = ratio(oc[key], pc[key])
            char_rows.append((ch, label, unit, fmt(pc[key]), fmt(oc[key]), fmt(r, 3)))
            char_csv.append(dict(channel=ch, quantity=key, paper=pc[key], ours=oc[key], ratio=r))
            head[ch].update({f"{key}_paper": pc[key], f"{key}_ours": oc[key], f"{key}_ratio": r})
            if key != "zero_1_s":
                comparison.add("Table 2", f"2nd-order {ch} {label}", unit, pc[key], oc[key], _CONDITION_NOTE)
        dc6_p = TABLE2[(ch, 6)][0][-1] / TABLE2[(ch, 6)][1][-1]
        n6, d6 = table2_form(getattr(m.sixth, ch))
        comparison.add("Table 2", f"6th-order {ch} DC gain", "m/N", dc6_p, n6[-1] / d6[-1],
                       "as for the 2nd-order models: different (unstated) linearization condition")
    return char_rows, char_csv, head


def _reduction_errors(m: LinearResult, w):
    """A-priori H-infinity bound of each truncation vs its error on the frequency grid ``w`` [rad/s]."""
    import control

    from ..analysis.reduction import hankel_singular_values, truncation_error_bound

    red_rows, red_csv = [], []
    for ch in CHANNELS:
        g = getattr(m.full, ch)
        hsv = hankel_singular_values(g)
        gfull = freq_response(g, w)
        dc = abs(float(np.real(control.dcgain(g))))
        peak = float(np.max(np.abs(gfull)))
        for o, red in ((6, m.sixth), (2, m.second)):
            bound = truncation_error_bound(hsv, o)
            err = float(np.max(np.abs(gfull - freq_response(getattr(red, ch), w))))
            red_rows.append((ch, o, fmt(bound), fmt(err), fmt(err / peak, 3)))
            red_csv.append(dict(channel=ch, order=o, hinf_bound_m_n=bound, max_error_on_grid_m_n=err,
                                full_dc_gain_m_n=dc, full_peak_gain_m_n=peak, hsv_1=hsv[0],
                                hsv_3=hsv[2] if hsv.size > 2 else np.nan))
    return red_rows, red_csv


def _sensitivity(settings):
    """The 2nd-order models at other linearization conditions, with their log-distance to the
    paper's (DC gain and natural frequency, both channels). Returns (DataFrame, HTML rows)."""
    import pandas as pd

    from ..analysis.linearize import linearize
    from ..analysis.reduction import table2_form
    from ..controllers.design import reduced_channels

    p_lat = second_order_characteristics(*TABLE2[("lateral", 2)])
    p_ver = second_order_characteristics(*TABLE2[("vertical", 2)])
    rows = []
    for h in settings.sensitivity_altitudes_m:
        for v in settings.sensitivity_airspeeds_m_s:
            c2 = reduced_channels(linearize(PAPER.replace(flight={"altitude_m": h, "airspeed_m_s": v})), 2)
            cl = second_order_characteristics(*table2_form(c2.lateral))
            cv = second_order_characteristics(*table2_form(c2.vertical))
            dist = math.sqrt(sum(math.log(a[k] / b[k]) ** 2 for a, b in ((cl, p_lat), (cv, p_ver))
                                 for k in ("dc_gain_m_n", "natural_frequency_rad_s")))
            rows.append(dict(altitude_m=h, airspeed_m_s=v,
                             lateral_dc_gain_m_n=cl["dc_gain_m_n"], lateral_wn_rad_s=cl["natural_frequency_rad_s"],
                             lateral_zeta=cl["damping_ratio"], vertical_dc_gain_m_n=cv["dc_gain_m_n"],
                             vertical_wn_rad_s=cv["natural_frequency_rad_s"], vertical_zeta=cv["damping_ratio"],
                             log_distance_to_paper=dist))
    sens = pd.DataFrame(rows)
    html_rows = [(f"{r.altitude_m:g}", f"{r.airspeed_m_s:g}", fmt(r.lateral_dc_gain_m_n), fmt(r.lateral_wn_rad_s),
                  fmt(r.lateral_zeta, 3), fmt(r.vertical_dc_gain_m_n), fmt(r.vertical_wn_rad_s), fmt(r.vertical_zeta, 3),
                  fmt(r.log_distance_to_paper, 3)) for r in sens.itertuples()]
    html_rows.append(("paper", "(not stated)", fmt(p_lat["dc_gain_m_n"]), fmt(p_lat["natural_frequency_rad_s"]),
                      fmt(p_lat["damping_ratio"], 3), fmt(p_ver["dc_gain_m_n"]), fmt(p_ver["natural_frequency_rad_s"]),
                      fmt(p_ver["damping_ratio"], 3), "0"))
    return sens, html_rows


def _html(m: LinearResult, head: dict, best, w, tables: dict) -> str:
    fl = PAPER.flight
    r = {(ch, k): head[ch][f"{k}_ratio"] for ch in CHANNELS for k in ("dc_gain_m_n", "natural_frequency_rad_s")}
    return (
        '<section id="table2"><h2>Table 2: reduced transfer functions</h2>'
        f"<p>This project's model linearized about its balance position at <b>{fl.airspeed_m_s:g} m/s, "
        f"{fl.altitude_m:g} m, wake on</b> "
        f"(the flight condition of Fig. 12; {m.model.A.shape[0]} states), each channel balanced-truncated to "
        f"6th and 2nd order, beside the paper's Table 2. <b>The paper does not state the flight condition "
        f"of its linearization</b>, so the two need not match. They do not: our 2nd-order DC gain is "
        f"{r['lateral', 'dc_gain_m_n']:.2f} x (lateral) and {r['vertical', 'dc_gain_m_n']:.2f} x (vertical) the "
        f"paper's and our natural frequency "
        f"{r['lateral', 'natural_frequency_rad_s']:.2f} x and {r['vertical', 'natural_frequency_rad_s']:.2f} x. "
        f"The pendulum frequency of the towed hose scales roughly with "
        f"airspeed and the square root of air density, the gain with their inverse squares, so the "
        f"linearization condition matters by factors of 2-3 across the envelope (table below). In "
        f"this grid the condition nearest to the paper's 2nd-order models (smallest log-distance of "
        f"DC gain and natural frequency over both channels) is <b>{best.altitude_m:g} m, "
        f"{best.airspeed_m_s:g} m/s</b>: an observation, not a fit; every other result here uses "
        f"{fl.airspeed_m_s:g} m/s, {fl.altitude_m:g} m.</p>"
        + html_table(["model", "channel", "paper Table 2 [m/N]", "this project [m/N]"], tables["tf"], table_id="table-2")
        + "<h3>2nd-order models: DC gain, natural frequency, damping</h3>"
        + html_table(["channel", "quantity", "unit", "paper", "this project", "ratio"], tables["characteristics"],
                     table_id="table-2-characteristics")
        + "<details><summary>Every Table 2 coefficient, paper vs this project</summary>"
        + html_table(["order", "channel", "polynomial", "power", "paper", "this project", "ratio"],
                     tables["coefficients"], table_id="table-2-coefficients")
        + "</details>"
        + "<h3>Sensitivity of the 2nd-order model to the linearization condition</h3>"
        + html_table(["altitude [m]", "airspeed [m/s]", "lat. DC gain [m/N]", "lat. w_n [rad/s]", "lat. zeta [-]",
                      "vert. DC gain [m/N]", "vert. w_n [rad/s]", "vert. zeta [-]", "log-distance to paper [-]"],
                     tables["sensitivity"], table_id="table-linearization-conditions")
        + "<h3>Balanced truncation error</h3><p>The a-priori H-infinity bound of balanced truncation "
          "(twice the sum of the discarded Hankel singular values) and the largest error actually seen on "
          f"the frequency grid of Fig. 7 ({w[0]:g} to {w[-1]:g} rad/s; a lower estimate of the H-infinity norm).</p>"
        + html_table(["channel", "order", "bound 2 sum(sigma) [m/N]", "max |G - G_r| on grid [m/N]",
                      "relative to the full model's peak gain [-]"], tables["reduction"], table_id="table-reduction-error")
        + '<p class=data>Data: <a href="table2.csv">table2.csv</a>, <a href="table2_characteristics.csv">'
          'table2_characteristics.csv</a>, <a href="linearization_conditions.csv">linearization_conditions.csv</a>, '
          '<a href="reduction_error.csv">reduction_error.csv</a>.</p></section>'
    )


def build(out: ReportFolder, settings: ReportSettings, *, sweep: SteadyResult) -> LinearResult:
    """Linearize, reduce, compare with Table 2; write Table 2 and Figs. 5-8 with their data.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Frequency points of Fig. 7 and the linearization conditions of the sensitivity table.
    sweep : hosedrogue.report.sweep.SteadyResult
        The balance position to linearize about.

    Returns
    -------
    LinearResult
        The linear model and its reductions.
    """
    import pandas as pd

    m = _models(sweep.equilibrium)
    w = np.logspace(-2, 2, settings.bode_points)
    t2_rows, coeff_rows, t2_csv = _table2(m)
    char_rows, char_csv, head = _characteristics(m, out.comparison)
    red_rows, red_csv = _reduction_errors(m, w)
    sens, sens_rows = _sensitivity(settings)
    best = sens.loc[sens["log_distance_to_paper"].idxmin()]

    out.csv(pd.DataFrame(t2_csv), "table2.csv")
    out.csv(pd.DataFrame(char_csv), "table2_characteristics.csv")
    out.csv(pd.DataFrame(red_csv), "reduction_error.csv")
    out.csv(sens, "linearization_conditions.csv")
    tables = {"tf": t2_rows, "characteristics": char_rows, "coefficients": coeff_rows, "sensitivity": sens_rows,
              "reduction": red_rows}
    out.section("table2", "Table 2", _html(m, head, best, w, tables))
    linear_model = responses_section(out, m, w, head)
    out.summarize("Table 2 (linearization condition not stated in the paper): our 2nd-order DC gain is "
                  f"{head['lateral']['dc_gain_m_n_ratio']:.2f} x / {head['vertical']['dc_gain_m_n_ratio']:.2f} x and "
                  f"natural frequency {head['lateral']['natural_frequency_rad_s_ratio']:.2f} x / "
                  f"{head['vertical']['natural_frequency_rad_s_ratio']:.2f} x the paper's (lateral / vertical).")
    out.record("table2", {**head, "nearest_linearization_condition": {"altitude_m": float(best.altitude_m),
                                                                      "airspeed_m_s": float(best.airspeed_m_s)}})
    out.record("linear_model", linear_model)
    return m
