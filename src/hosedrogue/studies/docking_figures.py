"""Figures of the report's "Docking" section: capture rate against turbulence intensity, the
miss-distance CDFs per intensity, one approach seen from behind and the capture rate against the
closure speed and against the actuator's force limit (the bow-wave figure is
:func:`hosedrogue.studies.bow_wave_figures.plot_bow_wave`).

``table`` is the section's capture table (a pandas DataFrame, one row per campaign) with the
columns ``level``, ``sigma_m_s``, ``controller``, ``bow_wave`` (bool), ``rate``, ``ci95_low`` and
``ci95_high``, and optionally ``pilot`` (bool: the pilot model flew the probe).
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from ..plotting.base import new_figure
from ..plotting.campaign import draw_miss_cdf

#: Line style per bow-wave setting.
_BOW_STYLE = {True: "-", False: "--"}


def plot_capture_rates(table, controllers: Sequence[str], levels: Sequence[str]):
    """Capture rate against the turbulence intensity, one colour per controller, solid with the
    bow wave and dashed without it, Wilson 95 % intervals as error bars; the pilot's rows (column
    ``pilot`` true), if any, in a colour of their own.

    Parameters
    ----------
    table : pandas.DataFrame
        One row per campaign (module docstring); rates and interval bounds [-].
    controllers : sequence of str
        Controllers, in legend order.
    levels : sequence of str
        Turbulence levels in the order of the x axis (their ``sigma_m_s`` [m/s] is the position).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = new_figure(1, 1, size=(9.0, 4.5))
    colours = {c: f"C{i}" for i, c in enumerate(controllers)}
    sigmas = [float(table.loc[table["level"] == lev, "sigma_m_s"].iloc[0]) for lev in levels]
    spread = 0.015 * (max(sigmas) - min(sigmas) or 1.0)  # side by side, so the bars do not overlap
    pilot = table["pilot"].to_numpy(bool) if "pilot" in table else np.zeros(len(table), bool)
    lines = [(c, bow, False) for bow in (True, False) for c in controllers]
    if pilot.any():
        lines.insert(len(controllers), ("none", True, True))
        colours["pilot"] = f"C{len(controllers)}"
    for k, (c, bow, piloted) in enumerate(lines):
        sub = table[(table["controller"] == c) & (table["bow_wave"] == bow) & (pilot == piloted)]
        sub = sub.set_index("level").reindex([lev for lev in levels if lev in set(sub["level"])])
        if sub.empty:
            continue
        x = sub["sigma_m_s"].to_numpy(dtype=float) + (k - (len(lines) - 1) / 2) * spread
        y = sub["rate"].to_numpy(dtype=float)
        err = np.vstack([y - sub["ci95_low"].to_numpy(dtype=float), sub["ci95_high"].to_numpy(dtype=float) - y])
        ax.errorbar(x, y, yerr=err, color=colours["pilot" if piloted else c], ls=_BOW_STYLE[bow],
                    marker="s" if piloted else "o", ms=4, capsize=3,
                    label=("pilot flies the probe, no controller" if piloted else c)
                    + f", bow wave {'on' if bow else 'off'}")
    ax.set_xticks(sigmas, [f"{s:.2f}\n{lev}" for s, lev in zip(sigmas, levels)])
    ax.set_xlabel("turbulence intensity σ_w at 8000 m [m/s]")
    ax.set_ylabel("capture rate [-]")
    ax.set_ylim(-0.02, 1.05)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small", loc="center left", bbox_to_anchor=(1.02, 0.5))
    ax.set_title("capture rate (Wilson 95 % intervals)")
    return fig


def plot_miss_cdfs(miss_m: Mapping[str, Mapping[str, np.ndarray]], capture_radius_m: float):
    """Empirical CDFs of the radial miss, one panel per turbulence level, one line per controller.

    Parameters
    ----------
    miss_m : mapping
        ``level -> controller -> array`` of the radial miss [m] at the coupler plane of each run
        (non-finite values, runs without contact, ignored).
    capture_radius_m : float
        Capture radius [m], drawn as a dashed line.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = new_figure(1, len(miss_m), size=(4.2 * len(miss_m), 3.8), sharey=True, squeeze=False)
    for ax, (level, by_controller) in zip(axes[0], miss_m.items()):
        for i, (c, miss) in enumerate(by_controller.items()):
            draw_miss_cdf(ax, miss, label=f"{c} ({{n}} runs)", color=f"C{i}", ls=("-", "--", ":")[i % 3])
        ax.axvline(capture_radius_m, color="0.4", linestyle="--", linewidth=0.8,
                   label=f"capture radius {capture_radius_m:g} m")
        ax.set_xlabel("radial miss at the coupler plane [m]")
        ax.set_title(f"{level} turbulence, bow wave on")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="lower right", fontsize="small")
    axes[0][0].set_ylabel("fraction of runs [-]")
    return fig


def plot_approach_from_behind(paths: Mapping[str, Mapping[str, np.ndarray]], capture_radius_m: float):
    """Probe-tip and drogue paths in the y-z plane up to contact, seen from behind (y right, z
    down), the capture circle around the drogue at contact and the contact point.

    Parameters
    ----------
    paths : mapping
        ``label -> {"probe_yz_m": (N, 2), "drogue_yz_m": (N, 2), "contact_probe_yz_m": (2,),
        "contact_drogue_yz_m": (2,)}``: positions [m] in S_p (y right, z down) from the start to
        contact; the contact entries may be absent (no contact).
    capture_radius_m : float
        Capture radius [m], drawn around the drogue at contact.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = new_figure(1, len(paths), size=(4.6 * len(paths), 4.6), squeeze=False)
    phi = np.linspace(0.0, 2.0 * np.pi, 181)
    for ax, (label, p) in zip(axes[0], paths.items()):
        d, pr = np.asarray(p["drogue_yz_m"]), np.asarray(p["probe_yz_m"])
        ax.plot(d[:, 0], d[:, 1], "C0-", lw=1.2, label="drogue")
        ax.plot(d[0, 0], d[0, 1], "C0s", ms=5, label="drogue at start")
        ax.plot(pr[:, 0], pr[:, 1], "C3-", lw=1.2, marker="^", markevery=[0], label="probe tip")
        if "contact_drogue_yz_m" in p:
            cd, cp = np.asarray(p["contact_drogue_yz_m"]), np.asarray(p["contact_probe_yz_m"])
            ax.plot(cd[0] + capture_radius_m * np.cos(phi), cd[1] + capture_radius_m * np.sin(phi), "0.3", ls="--",
                    lw=0.9, label=f"capture radius {capture_radius_m:g} m at contact")
            ax.plot(*cd, "C0o", ms=6, label="drogue at contact")
            ax.plot(*cp, "kx", ms=9, mew=2, label="contact point (probe tip)")
        ax.set_xlabel("right y [m]")
        ax.set_ylabel("down z [m]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.invert_yaxis()
        ax.grid(True, alpha=0.3)
        ax.set_title("pilot flies the probe, no controller" if label == "pilot" else f"controller {label}")
        ax.legend(fontsize="x-small", loc="upper right")
    return fig


def plot_closure_speed(table, controllers: Sequence[str], min_closure_speed_m_s: float):
    """Capture rate and failed-latch fraction against the probe's closure speed (left), and the
    closure speed at the coupler against the probe's (right), one colour per controller.

    Parameters
    ----------
    table : pandas.DataFrame
        One row per (controller, speed): ``controller``, ``probe_speed_m_s`` [m/s], ``rate``,
        ``ci95_low``, ``ci95_high``, ``failed_latch_fraction`` [-] and
        ``coupler_speed_p05_m_s``, ``coupler_speed_median_m_s``, ``coupler_speed_p95_m_s`` [m/s].
    controllers : sequence of str
        Controllers, in legend order.
    min_closure_speed_m_s : float
        The latch window's minimum closure speed at the coupler [m/s], drawn as a line.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax, bx) = new_figure(1, 2, size=(11.0, 4.3))
    speeds = np.array(sorted(set(table["probe_speed_m_s"])), dtype=float)
    spread = 0.012 * (speeds.max() - speeds.min() or 1.0)  # side by side, so the bars do not overlap
    for k, c in enumerate(controllers):
        sub = table[table["controller"] == c].sort_values("probe_speed_m_s")
        if sub.empty:
            continue
        v = sub["probe_speed_m_s"].to_numpy(dtype=float)
        x = v + (k - (len(controllers) - 1) / 2) * spread
        y = sub["rate"].to_numpy(dtype=float)
        err = np.vstack([y - sub["ci95_low"].to_numpy(dtype=float), sub["ci95_high"].to_numpy(dtype=float) - y])
        ax.errorbar(x, y, yerr=err, color=f"C{k}", marker="o", ms=4, capsize=3, label=f"{c}: capture rate")
        ax.plot(x, sub["failed_latch_fraction"].to_numpy(dtype=float), color=f"C{k}", ls=":", marker="x",
                label=f"{c}: failed latches")
        med = sub["coupler_speed_median_m_s"].to_numpy(dtype=float)
        cerr = np.vstack([med - sub["coupler_speed_p05_m_s"].to_numpy(dtype=float),
                          sub["coupler_speed_p95_m_s"].to_numpy(dtype=float) - med])
        bx.errorbar(x, med, yerr=cerr, color=f"C{k}", marker="o", ms=4, capsize=3, ls="none",
                    label=f"{c} (median, 5th-95th percentile)")
    bx.plot(speeds, speeds, color="0.6", lw=0.8, label="equal to the probe's")
    bx.axhline(min_closure_speed_m_s, color="C3", ls="--", lw=0.9, label=f"latch minimum {min_closure_speed_m_s:g} m/s")
    ax.set_ylim(-0.02, 1.05)
    ax.set_ylabel("fraction of runs [-]")
    ax.set_title("capture rate (Wilson 95 %) and failed latches")
    bx.set_ylabel("closure speed at the coupler [m/s]")
    bx.set_title("closure speed at contact")
    for a in (ax, bx):
        a.set_xticks(speeds)
        a.set_xlabel("probe closure speed [m/s]")
        a.grid(True, alpha=0.3)
        a.legend(fontsize="x-small", loc="best")
    return fig


def plot_force_limit(table):
    """Capture rate against the actuator's force limit per axis (left, log x, the unlimited point at
    the right edge) with each level's no-controller interval as a band, and the fraction of runs
    whose force saturated (right); one colour per turbulence level, one line style per controller.

    Parameters
    ----------
    table : pandas.DataFrame
        One row per cell: ``level``, ``controller`` ("none" for the band), ``max_force_n`` [N]
        (inf: unlimited), ``rate``, ``ci95_low``, ``ci95_high`` and ``saturated_fraction`` [-].

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax, bx) = new_figure(1, 2, size=(11.5, 4.5))
    finite = np.isfinite(table["max_force_n"].to_numpy(dtype=float))
    limits = np.array(sorted(set(table.loc[finite, "max_force_n"])), dtype=float)
    x_free = limits.max() * (limits.max() / limits.min()) ** (1.0 / max(len(limits) - 1, 1)) * 1.4  # right edge
    levels = list(dict.fromkeys(table["level"]))
    controllers = [c for c in dict.fromkeys(table["controller"]) if c != "none"]
    styles = ("-", "--", ":", "-.")
    n_lines = len(levels) * len(controllers)
    for i, level in enumerate(levels):
        colour = f"C{i}"
        none = table[(table["level"] == level) & (table["controller"] == "none")]
        if len(none):
            r = none.iloc[0]
            ax.axhspan(r["ci95_low"], r["ci95_high"], color=colour, alpha=0.12, lw=0)
            ax.axhline(r["rate"], color=colour, lw=0.8, ls=":", label=f"{level}, no controller (band: 95 %)")
        for j, c in enumerate(controllers):
            sub = table[(table["level"] == level) & (table["controller"] == c)].sort_values("max_force_n")
            shift = 1.04 ** (i * len(controllers) + j - (n_lines - 1) / 2)  # side by side in log x
            lim = sub[np.isfinite(sub["max_force_n"])]
            x = np.append(lim["max_force_n"].to_numpy(dtype=float), [x_free] * (len(sub) - len(lim))) * shift
            y = sub["rate"].to_numpy(dtype=float)
            err = np.vstack([y - sub["ci95_low"].to_numpy(dtype=float), sub["ci95_high"].to_numpy(dtype=float) - y])
            k, ls, mk = len(lim), styles[j % len(styles)], "os^v"[j % 4]
            ax.errorbar(x[:k], y[:k], yerr=err[:, :k], color=colour, ls=ls, marker=mk, ms=4, capsize=3,
                        label=f"{level}, {c}")
            if len(sub) > k:  # the unlimited point, joined by a thin dotted line (no limits between)
                ax.errorbar(x[k:], y[k:], yerr=err[:, k:], color=colour, ls="none", marker=mk, ms=4, capsize=3)
                ax.plot(x[k - 1:k + 1], y[k - 1:k + 1], color=colour, ls=":", lw=0.8)
            bx.plot(x[:k], lim["saturated_fraction"].to_numpy(dtype=float), color=colour, ls=ls, marker=mk, ms=4,
                    label=f"{level}, {c}")
    ax.set_ylim(-0.02, 1.05)
    ax.set_ylabel("capture rate [-]")
    ax.set_title("capture rate (Wilson 95 %)")
    bx.set_ylim(-0.02, 1.05)
    bx.set_ylabel("fraction of runs saturated [-]")
    bx.set_title("runs whose per-axis force reached the limit")
    for a, ticks in ((ax, np.append(limits, x_free)), (bx, limits)):
        a.set_xscale("log")
        a.set_xticks(ticks, [f"{v:g}" for v in limits] + (["unlimited"] if len(ticks) > len(limits) else []))
        a.minorticks_off()
        a.set_xlabel("actuator force limit per axis [N]")
        a.grid(True, alpha=0.3)
        a.legend(fontsize="x-small", loc="best")
    bx.set_xlim(ax.get_xlim())  # the same limits at the same places in both panels
    return fig
