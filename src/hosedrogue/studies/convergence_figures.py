"""Figure of the convergence study (RK4 step and number of links)."""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

import matplotlib.ticker
from matplotlib.figure import Figure

from ..plotting.base import _grid, new_figure


def _plain_log_ticks(ax, values):
    """Ticks at exactly ``values`` on a log x-axis, written plainly (0.005, 20), no minor labels."""
    from matplotlib.ticker import FixedLocator, NullFormatter, NullLocator

    ax.xaxis.set_major_locator(FixedLocator(values))
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.xaxis.set_minor_formatter(NullFormatter())


def plot_convergence(step_studies: Sequence, link_study) -> Figure:
    """Convergence of the drogue position with the RK4 step and with the link count.

    Parameters
    ----------
    step_studies : sequence of hosedrogue.studies.convergence.StepStudy
        (a) max drogue-position error [m] against the step [s], log-log, with a 4th-order
        guide line.
    link_study : LinkStudy or mapping ``{label: LinkStudy}``
        (b) drogue balance height z [m] and (c) lowest lateral/vertical mode frequency
        [rad/s] against the number of links.

    Returns
    -------
    Figure
    """
    studies = link_study if isinstance(link_study, Mapping) else {"": link_study}
    fig, (ax_s, ax_z, ax_w) = new_figure(1, 3, size=(14.0, 4.2))
    for k, st in enumerate(step_studies):
        h = np.asarray(st.steps_s)
        e = np.asarray(st.max_error_m)
        ax_s.loglog(h, e, "o-", color=f"C{k}", label=st.case)
    if step_studies:
        h_all = np.concatenate([np.asarray(s.steps_s) for s in step_studies])
        e_all = np.concatenate([np.asarray(s.max_error_m) for s in step_studies])
        hh = np.array([h_all.min(), h_all.max()])
        anchor = np.exp(np.mean(np.log(e_all))) * (hh / np.exp(np.mean(np.log(h_all)))) ** 4
        ax_s.loglog(hh, anchor, "k:", lw=1.0, label="slope 4 (RK4)")
        ax_s.axhline(1e-4, color="0.5", ls="--", lw=0.8, label="0.1 mm")
    if step_studies:
        _plain_log_ticks(ax_s, np.unique(np.concatenate([np.asarray(s.steps_s) for s in step_studies])))
    ax_s.set_xlabel("RK4 step h [s]")
    ax_s.set_ylabel("max drogue position error [m]")
    ax_s.set_title("(a) integration step", fontsize=10)
    ax_s.legend(fontsize=7)
    _grid(ax_s, which="both")
    # distinct markers (hollow after the first) so that coinciding studies stay visible
    markers = ("o", "D", "x", "^", "v", "s")
    for k, (label, ls) in enumerate(studies.items()):
        links = np.asarray(ls.links)
        mk = dict(marker=markers[k % len(markers)], mfc=f"C{k}" if k == 0 else "none", ms=7 - k, color=f"C{k}")
        ax_z.semilogx(links, np.asarray(ls.drogue_position_m)[:, 2], "-", label=label or None, **mk)
        ax_w.semilogx(links, ls.lowest_lateral_rad_s, "-", label=f"{label} lateral".strip(), **mk)
        ax_w.semilogx(links, ls.lowest_vertical_rad_s, "--", label=f"{label} vertical".strip(), **mk)
    all_links = np.unique(np.concatenate([np.asarray(ls.links) for ls in studies.values()]))
    for ax in (ax_z, ax_w):
        _plain_log_ticks(ax, all_links)
    ax_z.set_xlabel("number of links n [-]")
    ax_z.set_ylabel("drogue balance height z [m] (down)")
    ax_z.set_title("(b) balance position against link count", fontsize=10)
    ax_w.set_xlabel("number of links n [-]")
    ax_w.set_ylabel("lowest mode frequency [rad/s]")
    ax_w.set_title("(c) pendulum modes against link count", fontsize=10)
    for ax in (ax_z, ax_w):
        _grid(ax, which="both")
    if any(studies):
        ax_z.legend(fontsize=7)
    ax_w.legend(fontsize=7)
    return fig
