"""Figures of the accuracy studies (:mod:`hosedrogue.studies.accuracy`): the link-count convergence and a
scenario's RK4 step error."""

from __future__ import annotations

from typing import Sequence

import numpy as np
from matplotlib.figure import Figure

from ..plotting.base import _grid, new_figure


def plot_accuracy(studies: Sequence, tolerances_m=(1e-2, 1e-3)) -> Figure:
    """Drogue-position error against the continuum, lowest-mode frequencies and RMS turbulence
    response against the number of links, one line per mass lumping.

    Parameters
    ----------
    studies : sequence of hosedrogue.studies.accuracy.LumpingStudy
        One per mass lumping (links, position errors [m], frequencies [rad/s], RMS responses [m]).
    tolerances_m : sequence of float
        Error levels drawn as horizontal lines [m].

    Returns
    -------
    matplotlib.figure.Figure
        Three panels; units on every axis.
    """
    fig, axes = new_figure(1, 3, size=(13.0, 4.0))
    ax_err, ax_freq, ax_rms = axes
    for st in studies:
        n = st.links
        line, = ax_err.loglog(n, st.position_error_m * 1e3, "o-", label=f"{st.lumping}")
        if st.frequencies is not None:
            ax_freq.semilogx(n, st.frequencies.lateral_rad_s, "o-", color=line.get_color(),
                             label=f"{st.lumping}, lateral")
            ax_freq.semilogx(n, st.frequencies.vertical_rad_s, "s--", color=line.get_color(),
                             label=f"{st.lumping}, vertical")
        if st.rms_response_m is not None:
            ax_rms.semilogx(n, st.rms_response_m[:, 0] * 1e3, "o-", color=line.get_color(),
                            label=f"{st.lumping}, lateral")
            ax_rms.semilogx(n, st.rms_response_m[:, 1] * 1e3, "s--", color=line.get_color(),
                            label=f"{st.lumping}, vertical")
    if studies:
        n = np.asarray(studies[0].links, float)
        for order, style in ((1, ":"), (2, "-.")):
            ref = studies[0].position_error_m[0] * 1e3 * (n / n[0]) ** (-order)
            ax_err.loglog(n, ref, "k" + style, lw=0.8, label=f"order {order}")
    for tol in tolerances_m:
        ax_err.axhline(tol * 1e3, color="0.6", lw=0.8)
    ax_err.set_xlabel("links [-]")
    ax_err.set_ylabel("steady drogue position error vs continuum [mm]")
    ax_freq.set_xlabel("links [-]")
    ax_freq.set_ylabel("lowest mode frequency [rad/s]")
    ax_rms.set_xlabel("links [-]")
    ax_rms.set_ylabel("RMS drogue offset in turbulence [mm]")
    for ax in axes:
        if studies:  # label the link counts themselves, not powers of ten
            ax.set_xticks([int(k) for k in studies[0].links], [str(int(k)) for k in studies[0].links])
            ax.minorticks_off()
        _grid(ax)
        ax.legend(fontsize=7)
    return fig


def plot_scenario_steps(study) -> Figure:
    """A turbulence scenario's RK4 step error: the largest drogue difference from the reference
    step against the step, with RK4's fourth-order slope through the finest step and the change the
    gust reading makes (the paper's linear, unsmoothed reading against the scenario's) for scale.

    Parameters
    ----------
    study : hosedrogue.studies.accuracy.ScenarioStepStudy
        Steps [s], their largest errors [m], the reference step [s] and the reading change [m].

    Returns
    -------
    matplotlib.figure.Figure
        One panel; units on both axes.
    """
    fig, axes = new_figure(1, 1, size=(6.0, 4.2))
    ax = axes
    h = np.asarray(study.steps_s, float)
    err_mm = np.asarray(study.max_error_m, float) * 1e3
    order = np.argsort(h)
    ax.loglog(h[order], err_mm[order], "o-", label="largest drogue difference from the reference")
    h_ref = h[order][0]
    ax.loglog(h[order], err_mm[order][0] * (h[order] / h_ref) ** 4, "k:", lw=0.8, label="order 4 (RK4)")
    ax.axhline(study.reading_change_m * 1e3, color="0.5", lw=0.8, ls="--",
               label="change of gust reading (paper's against the scenario's)")
    ax.set_xlabel("RK4 step [s]")
    ax.set_ylabel(f"drogue position error vs step {study.reference_step_s:g} s [mm]")
    ax.set_title(f"{study.duration_s:g} s of turbulence", fontsize=9)
    _grid(ax)
    ax.legend(fontsize=7)
    return fig
