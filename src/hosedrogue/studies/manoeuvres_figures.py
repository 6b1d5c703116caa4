"""Figures of the tanker's manoeuvres (:mod:`hosedrogue.studies.manoeuvres`)."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure


def plot_steady_flight(bank, flight_path) -> Figure:
    """Drogue position (from its level-flight position, the sweep's angle nearest 0) and exit tension
    in steady turns (against the bank angle) and steady climbs and descents (against the
    flight-path angle), in the tanker's body axes.

    Parameters
    ----------
    bank, flight_path : hosedrogue.analysis.steady_flight.SteadySweep
        The two sweeps: angles [deg], drogue positions [m], exit tensions [N].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(8.0, 6.0), constrained_layout=True)
    axes = fig.subplots(2, 2)
    for col, (sw, label) in enumerate(((bank, "bank angle [deg] (> 0 turning right)"),
                                       (flight_path, "flight-path angle [deg] (> 0 climbing)"))):
        ax, ax_t = axes[0, col], axes[1, col]
        a = sw.angles_deg
        level = sw.drogue_position_m[int(np.argmin(np.abs(a)))]
        d = sw.drogue_position_m - level
        for i, (marker, name) in enumerate((("^", "x (forward)"), ("s", "y (right)"), ("o", "z (down)"))):
            ax.plot(a, d[:, i], marker + "-", color=f"C{i}", label=name)
        ax.set_ylabel("drogue position from\nits level-flight one [m]")
        ax.legend(fontsize=8)
        ax_t.plot(a, sw.exit_tension_n, "o-", color="C3")
        ax_t.set_ylabel("exit tension [N]")
        for a_ in (ax, ax_t):
            a_.set_xlabel(label)
            a_.grid(True, alpha=0.3)
    axes[0, 0].set_title("steady coordinated level turn")
    axes[0, 1].set_title("steady climb or descent, wings level")
    return fig


def plot_turn_entry(entry) -> Figure:
    """The turn entry: the bank angle, the drogue's lateral and vertical position open loop and
    with the paper's PID, and the PID's force.

    Parameters
    ----------
    entry : hosedrogue.studies.manoeuvres.TurnEntry
        Times [s], bank [deg], drogue positions [m], balance positions [m], force [N].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(8.0, 9.0), constrained_layout=True)
    ax_b, ax_y, ax_z, ax_u = fig.subplots(4, 1, sharex=True)
    t = entry.t_s
    ax_b.plot(t, entry.bank_deg, color="k")
    ax_b.set_ylabel("bank angle [deg]")
    for ax, i, name in ((ax_y, 1, "lateral y (right)"), (ax_z, 2, "vertical z (down)")):
        ax.plot(t, entry.open_loop_m[:, i] - entry.level_m[i], color="C0", lw=1.0, label="open loop")
        ax.plot(t, entry.pid_m[:, i] - entry.level_m[i], color="C1", lw=1.0, label="paper's PID")
        ax.axhline(entry.turn_m[i] - entry.level_m[i], color="C0", ls="--", lw=0.8, label="turn's balance position")
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_ylabel(f"drogue {name}\nfrom level balance [m]")
        ax.legend(fontsize=8, loc="lower right")
    ax_u.plot(t, entry.pid_force_n[:, 0], color="C1", ls="-", label="u_y")
    ax_u.plot(t, entry.pid_force_n[:, 1], color="C3", ls="-", label="u_z")
    ax_u.set_ylabel("PID force [N]")
    ax_u.legend(fontsize=8)
    for ax in (ax_b, ax_y, ax_z, ax_u):
        ax.set_xlabel("time t [s]")
        ax.axvspan(entry.roll_start_s, entry.roll_end_s, color="0.9", zorder=0)
        ax.grid(True, alpha=0.3)
    return fig


def plot_turn_capture(capture) -> Figure:
    """Capture rate of the approach in level flight and in the turn, with 95 % Wilson intervals.

    Parameters
    ----------
    capture : hosedrogue.studies.manoeuvres.TurnCapture
        Labels and capture blocks (rate [-], ci95 [-], runs).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(5.0, 3.2), constrained_layout=True)
    ax = fig.subplots()
    x = np.arange(len(capture.labels))
    rate = np.array([c["rate"] for c in capture.capture])
    lo = np.array([c["ci95"][0] for c in capture.capture])
    hi = np.array([c["ci95"][1] for c in capture.capture])
    ax.bar(x, rate, color=["C0", "C1"][: len(x)], width=0.5)
    ax.errorbar(x, rate, yerr=[rate - lo, hi - rate], fmt="none", ecolor="k", capsize=6)
    ax.set_xticks(x, [f"{lbl}\n({c['runs']} runs)" for lbl, c in zip(capture.labels, capture.capture)])
    ax.set_ylim(0.0, 1.05)
    ax.set_xlabel("the tanker's flight [-]")
    ax.set_ylabel("capture rate [-]")
    ax.set_title("approach in moderate turbulence (95 % Wilson intervals)", fontsize=9)
    ax.grid(True, axis="y", alpha=0.3)
    return fig
