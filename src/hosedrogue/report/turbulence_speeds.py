"""Report section "Fig. 4": the drogue in turbulence at the paper's four airspeeds, controller off."""

from __future__ import annotations

from typing import TYPE_CHECKING

import math

import numpy as np

from ..spec.paper import FIG4_AIRSPEEDS_M_S
from .markup import figure_html, html_table
from .runs import peak_offsets_m, rms_offsets_m, run_named_scenario, turbulence_window_s

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["build"]


def _runs(settings):
    """One turbulence run per airspeed (same seed); returns (params of the last, results)."""
    runs = []
    for v in FIG4_AIRSPEEDS_M_S:
        sc, res = run_named_scenario(f"paper-turbulence-{v}", settings.run_duration_s)
        runs.append(res)
    return sc.params, runs


def _statistics(runs, window) -> dict:
    """Peak and RMS offsets per airspeed (the ``report.json`` entry)."""
    head = {}
    for v, res in zip(FIG4_AIRSPEEDS_M_S, runs):
        py, pz = peak_offsets_m(res)
        ry, rz = rms_offsets_m(res, window)
        head[str(v)] = {"peak_lateral_m": py, "peak_vertical_m": pz, "rms_lateral_m": ry, "rms_vertical_m": rz,
                        "completed": bool(res.completed)}
    return head


def _write_csv(out, runs) -> None:
    import pandas as pd

    cols = {"t_s": runs[0].t_s}
    for v, res in zip(FIG4_AIRSPEEDS_M_S, runs):
        n = min(res.t_s.size, runs[0].t_s.size)
        cols[f"dy_{v}_m_s_m"] = np.pad(res.drogue_offset_m[:n, 1], (0, runs[0].t_s.size - n), constant_values=np.nan)
        cols[f"dz_{v}_m_s_m"] = np.pad(res.drogue_offset_m[:n, 2], (0, runs[0].t_s.size - n), constant_values=np.nan)
    out.csv(pd.DataFrame(cols), "fig04_turbulence_speeds.csv")


def _html(params, window, head: dict, radial, falls: bool) -> str:
    tb = params.turbulence
    rows = [(f"{v}", *(f"{head[str(v)][k]:.3f}" for k in ("peak_lateral_m", "peak_vertical_m", "rms_lateral_m",
                                                         "rms_vertical_m")),
             "yes" if head[str(v)]["completed"] else "NO") for v in FIG4_AIRSPEEDS_M_S]
    return (
        '<section id="fig4"><h2>Fig. 4: drogue displacement in turbulence at several airspeeds</h2>'
        f"<p>The paper's turbulence case (isotropic Dryden, {tb.sigma_m_s[0]:g} m/s, {tb.scale_length_m[0]:g} m, "
        f"on from {window[0]:g} s to {window[1]:g} s, {params.flight.altitude_m:g} m) at four airspeeds, "
        f"controller off, the same "
        f"turbulence seed at every airspeed. The paper states that the displacement falls as the "
        f"airspeed rises (the gust is a smaller fraction of the airspeed). Here the RMS radial "
        f"displacement in the turbulence window is {' / '.join(f'{r:.3f}' for r in radial)} m at "
        f"{' / '.join(str(v) for v in FIG4_AIRSPEEDS_M_S)} m/s: "
        f"{'it falls monotonically, as the paper says' if falls else 'NOT monotonic, unlike the paper'}. "
        f"Peaks of one realisation are noisier than RMS values. The drogue keeps swinging after the "
        f"gusts stop (lightly damped pendulum modes), as in the paper's figure.</p>"
        + html_table(["airspeed [m/s]", "peak |dy| [m]", "peak |dz| [m]", "RMS dy in window [m]",
                      "RMS dz in window [m]", "completed"], rows, table_id="table-fig4")
        + figure_html("fig04", "fig04_turbulence_speeds.png", "Fig. 4 (paper Fig. 4)",
                      "Lateral (top) and vertical (bottom, positive down) drogue displacement from the "
                      f"balance position in turbulence at four airspeeds, {params.flight.altitude_m:g} m; the grey "
                      "band is the turbulence window.", ("fig04_turbulence_speeds.csv",))
        + "</section>"
    )


def build(out: ReportFolder, settings: ReportSettings) -> None:
    """Run the paper's turbulence case at the Fig. 4 airspeeds; write CSV, figure and section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Run length of the turbulence runs [s].

    Returns
    -------
    None
    """
    from ..plotting.figures import plot_turbulence_speeds

    params, runs = _runs(settings)
    window = turbulence_window_s(params)
    head = _statistics(runs, window)
    radial = [math.hypot(head[str(v)]["rms_lateral_m"], head[str(v)]["rms_vertical_m"]) for v in FIG4_AIRSPEEDS_M_S]
    falls = bool(np.all(np.diff(radial) < 0))

    _write_csv(out, runs)
    out.figure(plot_turbulence_speeds(runs, FIG4_AIRSPEEDS_M_S, window_s=window), "fig04_turbulence_speeds.png")
    out.section("fig4", "Fig. 4", _html(params, window, head, radial, falls))
    out.record("turbulence_speeds", {**head, "rms_radial_falls_with_airspeed": falls})
    return None
