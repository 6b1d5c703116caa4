"""Figures of a Monte Carlo campaign: distributions of the per-run statistics over runs.

``table`` is a campaign's runs table (a pandas DataFrame with ``run``, ``controller``,
``completed`` and the statistic columns of :mod:`hosedrogue.results.statistics`; the capture-radius columns
``inside_*`` in the order of the capture radii).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from .base import legend_or_note, new_figure

_LABELS = {
    "peak_radial_m": "peak radial displacement [m]",
    "rms_radial_m": "RMS radial displacement [m]",
    "peak_dy_m": "peak lateral displacement |dy| [m]",
    "peak_dz_m": "peak vertical displacement |dz| [m]",
    "peak_u_n": "peak control force [N]",
}


def _fixed_layout(fig, **margins):
    """Fixed margins [figure fractions] in place of the constrained layout (the figures are made
    with ``new_figure(..., constrained=False)``): a campaign writes three figures, and the layout
    solver was half of their 0.8 s of CPU (measured 2026-12-03), paid for every cell of the
    report's docking grids; their labels and sizes do not vary, so fixed margins show the same."""
    fig.subplots_adjust(**margins)
    return fig


def _completed_values(table, controller: str, column: str) -> np.ndarray:
    sub = table[(table["controller"] == controller) & table["completed"].astype(bool)]
    x = sub[column].to_numpy(dtype=np.float64)
    return x[np.isfinite(x)]


def _capture_columns(table) -> list[str]:
    """The capture-radius columns of the table, in the order of the capture radii."""
    return [c for c in table.columns if c.startswith("inside_")]


def plot_histograms(table, controllers: Sequence[str], capture_radii_m: Sequence[float]):
    """Histograms of the per-run statistics of completed runs, one colour per controller.

    Parameters
    ----------
    table : pandas.DataFrame
        The campaign's runs (module docstring).
    controllers : sequence of str
        Controllers to show, in legend order.
    capture_radii_m : sequence of float
        The campaign's capture radii [m]; the first two get a panel.

    Returns
    -------
    matplotlib.figure.Figure
    """
    panels = ["peak_radial_m", "rms_radial_m", "peak_dy_m", "peak_dz_m"]
    labels = dict(_LABELS)
    for r, column in list(zip(capture_radii_m, _capture_columns(table)))[:2]:
        panels.append(column)
        labels[column] = f"time fraction within {r:g} m [-]"
    if any(c != "none" for c in controllers) or len(panels) < 6:
        panels = panels[:5] + ["peak_u_n"]  # without a controller the force is zero: not worth a panel
    fig, axes = new_figure(2, 3, size=(11.0, 6.0), constrained=False)
    for ax, col in zip(axes.flat, panels):
        data = [_completed_values(table, c, col) for c in controllers]
        allx = np.concatenate(data) if data else np.empty(0)
        bins = np.histogram_bin_edges(allx, bins="auto") if allx.size else 10
        for i, (c, x) in enumerate(zip(controllers, data)):
            if x.size:  # a controller none of whose runs completed draws nothing (its colour kept for the others)
                ax.hist(x, bins=bins, alpha=0.6 if len(controllers) > 1 else 0.9, color=f"C{i}", label=f"controller {c}")
        ax.set_xlabel(labels[col])
        ax.set_ylabel("runs [-]")
    legend_or_note(axes.flat[0], "no completed run", loc="upper right", fontsize="small")
    seeds = table["run"].nunique()
    fig.suptitle(f"Monte Carlo campaign: {seeds} turbulence seeds, controller " + " vs ".join(controllers))
    return _fixed_layout(fig, left=0.06, right=0.985, bottom=0.085, top=0.92, wspace=0.25, hspace=0.3)


def plot_cdf(table, controllers: Sequence[str], capture_radii_m: Sequence[float]):
    """Empirical CDFs of peak and RMS radial displacement of completed runs, capture radii marked.

    Parameters
    ----------
    table : pandas.DataFrame
        The campaign's runs (module docstring).
    controllers : sequence of str
        Controllers to show, in legend order.
    capture_radii_m : sequence of float
        Capture radii [m], drawn as dashed lines.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = new_figure(1, 2, size=(10.0, 4.0), constrained=False, sharey=True)
    for ax, col in zip(axes, ("peak_radial_m", "rms_radial_m")):
        for c in controllers:
            x = np.sort(_completed_values(table, c, col))
            if x.size:
                fraction = np.arange(0, x.size + 1) / x.size
                ax.step(np.r_[x[0], x], fraction, where="post", label=f"controller {c}")
        for r in capture_radii_m:
            ax.axvline(r, color="0.4", linestyle="--", linewidth=0.8)
        ax.set_xlabel(_LABELS[col])
    fig.suptitle("Empirical CDF over runs; dashed: capture radii " + ", ".join(f"{r:g} m" for r in capture_radii_m))
    axes[0].set_ylabel("fraction of runs [-]")
    legend_or_note(axes[0], "no completed run", loc="lower right", fontsize="small")
    return _fixed_layout(fig, left=0.065, right=0.985, bottom=0.125, top=0.9, wspace=0.06)


def draw_miss_cdf(ax, miss_m, label: str = "{n} runs", **kw) -> int:
    """Draw the empirical CDF of the radial miss on ``ax`` (one step line).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    miss_m : array (N,)
        Radial miss distance [m] of each run that reached the coupler plane (non-finite ignored).
    label : str
        Legend text; ``{n}`` becomes the number of finite misses.
    **kw
        Passed to ``Axes.step`` (colour, line style).

    Returns
    -------
    int
        The number of finite misses drawn.
    """
    x = np.sort(np.asarray(miss_m, dtype=np.float64))
    x = x[np.isfinite(x)]
    if x.size:
        ax.step(np.r_[x[0], x], np.arange(0, x.size + 1) / x.size, where="post", label=label.format(n=x.size), **kw)
    return int(x.size)


def plot_miss_cdf(miss_m, capture_radius_m: float, title: str = ""):
    """Empirical CDF of the radial miss at the coupler plane over an engagement campaign's runs.

    Parameters
    ----------
    miss_m : array (N,)
        Radial miss distance [m] of each run that reached the coupler plane (non-finite ignored).
    capture_radius_m : float
        Capture radius [m], drawn as a dashed line.
    title : str
        Figure title (e.g. the capture rate).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = new_figure(1, 1, size=(6.0, 4.0), constrained=False)
    draw_miss_cdf(ax, miss_m)
    ax.axvline(capture_radius_m, color="0.4", linestyle="--", linewidth=0.8,
               label=f"capture radius {capture_radius_m:g} m")
    ax.set_xlabel("radial miss at the coupler plane [m]")
    ax.set_ylabel("fraction of runs [-]")
    ax.legend(loc="lower right", fontsize="small")
    ax.set_title(title or "Empirical CDF of the miss distance")
    return _fixed_layout(fig, left=0.12, right=0.94, bottom=0.125, top=0.92)
