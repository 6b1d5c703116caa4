"""Figures of simulation results. Every function returns a matplotlib Figure (Agg backend, no
``show()``); axes carry units. Import cost stays out of the model: matplotlib loads here only.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402


def new_figure(nrows: int = 1, ncols: int = 1, size=(7.0, 4.0), **kw):
    """A figure not registered with pyplot's global state (safe in long-running processes)."""
    fig = Figure(figsize=size, constrained_layout=True)
    axes = fig.subplots(nrows, ncols, **kw)
    return fig, axes


def save_figure(fig: Figure, path: str | Path, dpi: int = 120) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    return path


def plot_displacement(result, labels: Sequence[str] | None = None, others: Sequence = (), title: str = ""):
    """Lateral and vertical drogue displacement from the balance position [m] against time [s].

    ``others`` are further results drawn on the same axes (e.g. controller off vs on).
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
    ax_z.set_xlabel("time t [s]")
    for ax in (ax_y, ax_z):
        ax.grid(True, alpha=0.3)
    if any(labels):
        ax_y.legend(loc="upper right")
    if title:
        fig.suptitle(title)
    return fig


__all__ = ["new_figure", "save_figure", "plot_displacement", "plt"]
