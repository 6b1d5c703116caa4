"""Figures of the steady state and of the drogue in turbulence (paper Sec. 2.3: Figs. 3 and 4)."""

from __future__ import annotations

from typing import Sequence

from matplotlib.figure import Figure

from .base import _grid, _shade_window, new_figure


def plot_displacement(result, labels: Sequence[str] | None = None, others: Sequence = (), title: str = ""):
    """Lateral and vertical drogue displacement from the balance position [m] against time [s].

    Parameters
    ----------
    result : SimulationResult
        The run.
    labels : sequence of str, optional
        Legend labels of ``result`` and ``others``, in that order; no legend if None.
    others : sequence of SimulationResult
        Further results drawn on the same axes (e.g. controller off vs on).
    title : str
        Figure title; none if empty.

    Returns
    -------
    Figure
    """
    fig, (ax_y, ax_z) = new_figure(2, 1, size=(7.0, 5.0), sharex=True)
    results = [result, *others]
    labels = list(labels) if labels is not None else [None] * len(results)
    for res, lab in zip(results, labels):
        off = res.drogue_offset_m
        ax_y.plot(res.t_s, off[:, 1], lw=1.0, label=lab)
        ax_z.plot(res.t_s, off[:, 2], lw=1.0, label=lab)
    ax_y.set_ylabel("lateral displacement y [m]")
    ax_z.set_ylabel("vertical displacement z [m]\n(positive down)")
    ax_y.set_xlabel("time t [s]")
    ax_z.set_xlabel("time t [s]")
    for ax in (ax_y, ax_z):
        ax.grid(True, alpha=0.3)
    if any(labels):
        ax_y.legend(loc="upper right")
    if title:
        fig.suptitle(title)
    return fig



def plot_sweep(sweep_result) -> Figure:
    """Paper Fig. 3: drogue drag [N] and balance ratio D = V_D / L_H [-] against airspeed [m/s],
    one curve per altitude.

    Parameters
    ----------
    sweep_result : hosedrogue.analysis.sweep.SweepResult
        Points that did not converge are left out of the curves.

    Returns
    -------
    Figure
    """
    df = sweep_result.to_dataframe()
    fig, (ax_d, ax_r) = new_figure(1, 2, size=(10.0, 4.0))
    for alt, g in df.groupby("altitude_m", sort=True):
        g = g[g["converged"].astype(bool)].sort_values("airspeed_m_s")
        label = f"{alt:,.0f} m"
        ax_d.plot(g["airspeed_m_s"], g["drogue_drag_n"], marker="o", ms=3, lw=1.2, label=label)
        ax_r.plot(g["airspeed_m_s"], g["balance_ratio"], marker="o", ms=3, lw=1.2, label=label)
    ax_d.set_xlabel("airspeed V [m/s]")
    ax_d.set_ylabel("drogue drag |D_dro| [N]")
    ax_d.set_title("(a) steady drogue drag")
    ax_r.set_xlabel("airspeed V [m/s]")
    ax_r.set_ylabel("balance ratio D = V_D / L_H [-]")
    ax_r.set_title("(b) balance position")
    for ax in (ax_d, ax_r):
        _grid(ax)
    ax_r.legend(title="altitude", fontsize=8)
    return fig


def plot_turbulence_speeds(results: Sequence, airspeeds: Sequence[float], window_s=None) -> Figure:
    """Paper Fig. 4: lateral and vertical drogue displacement [m] against time [s] in
    turbulence, one curve per airspeed.

    Parameters
    ----------
    results : sequence of SimulationResult
        One run per airspeed (controller off).
    airspeeds : sequence of float
        The airspeed of each run [m/s], for the legend.
    window_s : (float, float), optional
        Turbulence window [s], shaded.

    Returns
    -------
    Figure
    """
    fig, (ax_y, ax_z) = new_figure(2, 1, size=(8.0, 5.5), sharex=True)
    for res, v in zip(results, airspeeds):
        off = res.drogue_offset_m
        ax_y.plot(res.t_s, off[:, 1], lw=0.9, label=f"{v:g} m/s")
        ax_z.plot(res.t_s, off[:, 2], lw=0.9, label=f"{v:g} m/s")
    for ax in (ax_y, ax_z):
        _shade_window(ax, window_s)
        _grid(ax)
        ax.set_xlabel("time t [s]")
    ax_y.set_ylabel("lateral displacement dy [m]")
    ax_z.set_ylabel("vertical displacement dz [m]\n(positive down)")
    ax_y.legend(title="airspeed", fontsize=8, ncol=len(results), loc="upper left")
    return fig
