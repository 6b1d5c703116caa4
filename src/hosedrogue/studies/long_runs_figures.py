"""Figure of the long-runs study (:mod:`hosedrogue.studies.long_runs`)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure


def plot_long_runs(study) -> Figure:
    """Three panels: time to blow-up of the paper's model against turbulence intensity, the least
    damped mode's damping ratio per model option, and the converged model's hour-long run.

    Parameters
    ----------
    study : hosedrogue.studies.long_runs.LongRunStudy
        Blow-up table (intensity, sigma [m/s], stop time [s]), mode table (damping ratio [-],
        natural frequency [rad/s]) and the stable run (drogue offsets [m] against time [s]).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(7.0, 8.5), constrained_layout=True)
    ax_b, ax_m, ax_h = fig.subplots(3, 1)

    b = study.blowup
    for level, grp in b.groupby("intensity", sort=False):
        done = grp["completed"].to_numpy(bool)
        sigma = grp["sigma_m_s"].to_numpy(float)
        t_end = grp["t_end_s"].to_numpy(float)
        ax_b.plot(sigma[~done], t_end[~done], "o", color="C3")
        ax_b.plot(sigma[done], t_end[done], "^", color="C2")
        ax_b.annotate(str(level), (sigma[0], float(np.max(t_end))), textcoords="offset points",
                      xytext=(4, 4), fontsize=8)
    ax_b.axhline(study.cap_s, color="0.5", lw=0.8, ls="--")
    ax_b.plot([], [], "o", color="C3", label="stopped at the yaw limit")
    ax_b.plot([], [], "^", color="C2", label=f"completed {study.cap_s:g} s")
    ax_b.set_xlabel("turbulence intensity sigma [m/s]")
    ax_b.set_ylabel("time to blow-up [s]")
    ax_b.set_title("paper's model, open loop, turbulence from 10 s to the end")
    ax_b.legend(fontsize=8)
    ax_b.grid(True, alpha=0.3)

    m = study.modes
    x = np.arange(len(m))
    ax_m.bar(x, m["damping_ratio"], color="C0")
    ax_m.set_yscale("log")
    ax_m.set_xticks(x, [f"{o}\n{w:.1f} rad/s" for o, w in zip(m["option"], m["natural_frequency_rad_s"])],
                    fontsize=8)
    ax_m.set_xlabel("model option, least damped mode's natural frequency [rad/s]")
    ax_m.set_ylabel("damping ratio [-]")
    ax_m.set_title("least damped mode of the linearization about the balance position")
    ax_m.grid(True, axis="y", alpha=0.3)

    h = study.hour
    off = h.drogue_offset_m
    ax_h.plot(h.t_s, off[:, 1], lw=0.5, label="lateral")
    ax_h.plot(h.t_s, off[:, 2], lw=0.5, label="vertical")
    ax_h.set_xlabel("time [s]")
    ax_h.set_ylabel("drogue displacement [m]")
    state = "completed" if h.completed else h.message
    ax_h.set_title(f"converged model, severe turbulence: {state}")
    ax_h.legend(fontsize=8)
    ax_h.grid(True, alpha=0.3)
    return fig
