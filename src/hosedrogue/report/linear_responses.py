"""Figs. 5-8 of the report: step, pole-zero and frequency responses of the linearized model,
its reductions and the paper's Table 2 models (part of the linear-model section)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..analysis.responses import freq_response, step_response
from ..spec.paper import CHANNELS, table2_transfer_function
from .markup import figure_html

if TYPE_CHECKING:
    from .section_results import LinearResult
    from .writer import ReportFolder

__all__ = ["responses_section"]

#: Time grid of Figs. 5 and 8 [s].
_T_STEP_S = np.arange(0.0, 40.0 + 1e-9, 0.02)


def _ours(m) -> dict:
    return {"full": m.full, "6th order": m.sixth, "2nd order": m.second}


def _paper_label(o: int) -> str:
    return "paper 6th order" if o == 6 else "paper 2nd order"


def _fig5(out, m) -> float:
    """Fig. 5: full-model steps, both inputs to both outputs; returns the cross-coupling ratio."""
    import pandas as pd

    from ..analysis.responses import step_outputs
    from ..plotting.figures import plot_linear_steps

    t5 = _T_STEP_S
    y5 = np.stack([step_outputs(m.model.ss, t5, k) for k in range(m.model.ss.ninputs)], axis=1)  # (outputs, inputs, N)
    out.csv(pd.DataFrame({"t_s": t5, "P_ny_from_u_hor_m": y5[0, 0], "P_ny_from_u_ver_m": y5[0, 1],
                          "P_nz_from_u_hor_m": y5[1, 0], "P_nz_from_u_ver_m": y5[1, 1]}), "fig05_linear_steps.csv")
    out.figure(plot_linear_steps(t5, y5), "fig05_linear_steps.png")
    return max(np.max(np.abs(y5[0, 1])), np.max(np.abs(y5[1, 0]))) / min(np.max(np.abs(y5[0, 0])), np.max(np.abs(y5[1, 1])))


def _fig6(out, m, paper_tf) -> None:
    """Fig. 6: pole-zero maps of ours and the paper's models."""
    import pandas as pd

    from ..plotting.figures import plot_pole_zero

    pz = {label: {ch: (getattr(g, ch).poles(), getattr(g, ch).zeros()) for ch in CHANNELS}
          for label, g in _ours(m).items()}
    pz_ref = {label: {ch: (paper_tf[(ch, o)].poles(), paper_tf[(ch, o)].zeros()) for ch in CHANNELS}
              for label, o in (("6th order", 6), ("2nd order", 2))}
    rows = []
    for source, group in (("this project", pz), ("paper", pz_ref)):
        for label, chans in group.items():
            for ch, (poles, zeros) in chans.items():
                for kind, vals in (("pole", poles), ("zero", zeros)):
                    for z in np.asarray(vals, complex):
                        rows.append(dict(source=source, model=label, channel=ch, kind=kind, real_1_s=z.real, imag_rad_s=z.imag))
    out.csv(pd.DataFrame(rows), "fig06_pole_zero.csv")
    out.figure(plot_pole_zero(pz, reference=pz_ref), "fig06_pole_zero.png")


def _fig7(out, m, paper_tf, w) -> None:
    """Fig. 7: Bode diagrams of ours and the paper's models."""
    import pandas as pd

    from ..plotting.figures import plot_bode_compare

    bode = {label: {ch: freq_response(getattr(g, ch), w) for ch in CHANNELS} for label, g in _ours(m).items()}
    bode_ref = {_paper_label(o): {ch: freq_response(paper_tf[(ch, o)], w) for ch in CHANNELS} for o in (6, 2)}
    cols = {"omega_rad_s": w}
    for group in (bode, bode_ref):
        for label, chans in group.items():
            for ch, g in chans.items():
                key = label.replace(" ", "_")
                cols[f"{key}_{ch}_mag_db"] = 20 * np.log10(np.abs(g))
                cols[f"{key}_{ch}_phase_deg"] = np.degrees(np.unwrap(np.angle(g)))
    out.csv(pd.DataFrame(cols), "fig07_bode.csv")
    out.figure(plot_bode_compare(w, bode, reference=bode_ref), "fig07_bode.png")


def _fig8(out, m, paper_tf) -> None:
    """Fig. 8: open-loop steps of ours and the paper's models."""
    import pandas as pd

    from ..plotting.figures import plot_step_compare

    t = _T_STEP_S
    steps = {label: {ch: step_response(getattr(g, ch), t) for ch in CHANNELS} for label, g in _ours(m).items()}
    steps_ref = {_paper_label(o): {ch: step_response(paper_tf[(ch, o)], t) for ch in CHANNELS} for o in (6, 2)}
    cols = {"t_s": t}
    for group in (steps, steps_ref):
        for label, chans in group.items():
            for ch, y in chans.items():
                cols[f"{label.replace(' ', '_')}_{ch}_m"] = y
    out.csv(pd.DataFrame(cols), "fig08_step_compare.csv")
    out.figure(plot_step_compare(t, steps, reference=steps_ref), "fig08_step_compare.png")


def _html(m, coupling, max_real, slow, dc_err, dc_ratio) -> str:
    return (
        '<section id="fig5-8"><h2>Figs. 5-8: the linearized model and its reductions</h2>'
        + figure_html("fig05", "fig05_linear_steps.png", "Fig. 5 (paper Fig. 5)",
                      f"Step responses of the full linearized model ({m.model.A.shape[0]} states) to a 1 N force, "
                      f"both inputs to both outputs. The cross-coupling peaks are {100 * coupling:.1f} % of "
                      f"the direct responses: the channels are practically decoupled, as the paper finds, "
                      f"which justifies one SISO design per channel.", ("fig05_linear_steps.csv",))
        + figure_html("fig06", "fig06_pole_zero.png", "Fig. 6 (paper Fig. 6)",
                      f"Pole-zero maps per channel of the full model (minimal realization of each channel), "
                      f"its 6th- and 2nd-order balanced truncations (blue) and the paper's Table 2 models (grey). "
                      f"Every pole of the full model is stable (largest real part {max_real:.2g} 1/s: the "
                      f"higher hose modes are very lightly damped). The 2nd-order models keep the pendulum "
                      f"poles {slow['lateral'].real:.3f} &plusmn; {abs(slow['lateral'].imag):.3f}j (lateral) and "
                      f"{slow['vertical'].real:.3f} &plusmn; {abs(slow['vertical'].imag):.3f}j 1/s (vertical). Each "
                      f"channel's minimal realization keeps every mode; near-cancelling pole-zero pairs are "
                      f"the modes that channel barely sees.", ("fig06_pole_zero.csv",))
        + figure_html("fig07", "fig07_bode.png", "Fig. 7 (paper Fig. 7)",
                      "Frequency response of the full model and its 6th- and 2nd-order reductions (solid), "
                      "and of the paper's Table 2 models (dashed). The reductions follow the full model up to "
                      "and through the pendulum resonance; the paper's models resonate higher with a lower "
                      "gain (their linearization condition differs).", ("fig07_bode.csv",))
        + figure_html("fig08", "fig08_step_compare.png", "Fig. 8 (paper Fig. 8)",
                      "Open-loop response to a 1 N force step of the full and reduced models (solid) and the "
                      "paper's Table 2 models (dashed). The 6th-order model is hard to tell from the full one; "
                      "the 2nd-order model keeps the pendulum swing, but its final offset is "
                      f"{100 * dc_err['lateral']:+.1f} % (lateral) and {100 * dc_err['vertical']:+.1f} % (vertical) off "
                      "the full model's (balanced truncation does not preserve the DC gain). The paper's 2nd-order "
                      f"models settle at {1 / dc_ratio['lateral']:.2f} x (lateral) and {1 / dc_ratio['vertical']:.2f} x "
                      "(vertical) the offset of ours, with a faster swing.", ("fig08_step_compare.csv",))
        + "</section>"
    )


def responses_section(out: ReportFolder, m: LinearResult, w, table2_head: dict) -> dict:
    """Write Figs. 5-8 (CSV and PNG) and their section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    m : hosedrogue.report.section_results.LinearResult
        The linear model and its reductions.
    w : numpy.ndarray
        Angular frequencies of Fig. 7 [rad/s].
    table2_head : dict
        The Table 2 ``report.json`` entry (its DC-gain ratios ours / paper are quoted).

    Returns
    -------
    dict
        The ``linear_model`` entry of ``report.json``.
    """
    import control

    paper_tf = {(ch, o): table2_transfer_function(ch, o) for ch in CHANNELS for o in (6, 2)}
    # the pendulum poles each 2nd-order model keeps (upper half plane)
    slow = {ch: max(getattr(m.second, ch).poles(), key=lambda p: p.imag) for ch in CHANNELS}
    max_real = max(float(np.max(getattr(m.full, ch).poles().real)) for ch in CHANNELS)
    dc_err = {ch: float(np.real(control.dcgain(getattr(m.second, ch)))) / float(np.real(control.dcgain(getattr(m.full, ch)))) - 1.0
              for ch in CHANNELS}
    dc_ratio = {ch: table2_head[ch]["dc_gain_m_n_ratio"] for ch in CHANNELS}

    coupling = _fig5(out, m)
    _fig6(out, m, paper_tf)
    _fig7(out, m, paper_tf, w)
    _fig8(out, m, paper_tf)
    out.section("fig5-8", "Figs. 5-8", _html(m, coupling, max_real, slow, dc_err, dc_ratio))
    return {"states": int(m.model.A.shape[0]), "cross_coupling_ratio": float(coupling),
            "max_pole_real_part_1_s": max_real, "second_order_dc_gain_error_vs_full": dc_err}

