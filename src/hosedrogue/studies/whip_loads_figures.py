"""Figure of the whip-load study (:mod:`hosedrogue.studies.whip_loads`): the whip's loads against
the closure speed, per axial stiffness and reel law."""

from __future__ import annotations

from typing import Sequence

import numpy as np
from matplotlib.figure import Figure

from ..plotting.base import _grid, new_figure

__all__ = ["plot_whip_loads"]

#: Rows of :func:`plot_whip_loads`: (key of a study row's peaks, axis label).
_WHIP_ROWS = (("peak_tension_rise_n", "exit-tension rise [kN]"), ("peak_probe_load_n", "peak probe load [kN]"))


def plot_whip_loads(rows: Sequence[object]) -> Figure:
    """The whip-load study: the rise of the exit tension above the trail tension and the peak
    probe load [kN] against the closure speed [m/s], one line per axial stiffness EA, one column
    per reel law; hollow markers where the run does not call the peak converged.

    Parameters
    ----------
    rows : sequence of hosedrogue.studies.whip_loads.WhipLoadRow
        The study's rows.

    Returns
    -------
    matplotlib.figure.Figure
    """
    laws = list(dict.fromkeys(r.law for r in rows))
    stiffnesses = sorted({r.stiffness_n for r in rows})
    fig, axes = new_figure(len(_WHIP_ROWS), len(laws), size=(3.5 * len(laws) + 0.8, 2.6 * len(_WHIP_ROWS) + 0.4),
                           sharex=True, sharey="row", squeeze=False)
    for j, law in enumerate(laws):
        for i, (key, label) in enumerate(_WHIP_ROWS):
            ax = axes[i, j]
            for c, ea in enumerate(stiffnesses):
                sel = sorted((r for r in rows if r.law == law and r.stiffness_n == ea), key=lambda r: r.closure_speed_m_s)
                v = np.array([r.closure_speed_m_s for r in sel])
                y = np.array([r.peaks[key] for r in sel]) / 1e3
                ok = np.array([r.converged[key] for r in sel], dtype=bool)
                ax.plot(v, y, color=f"C{c}", lw=1.0, label=f"EA {ea:.0e} N")
                ax.plot(v[ok], y[ok], "o", color=f"C{c}", ms=4)
                ax.plot(v[~ok], y[~ok], "o", mfc="none", color=f"C{c}", ms=4)
            _grid(ax)
            if j == 0:
                ax.set_ylabel(label, fontsize=8)
        axes[0, j].set_title(law, fontsize=9)
        axes[-1, j].set_xlabel("closure speed [m/s]")
    axes[0, 0].legend(fontsize=7)
    return fig
