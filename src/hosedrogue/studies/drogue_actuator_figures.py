"""Figures of the actuated drogue (the report's "Actuated drogue" section): the paper's turbulence
case with the ideal force and the surfaces, the peaks of the claims cases against the paper's 1 cm,
and the capture rate against the surfaces' deflection limit and servo bandwidth."""

from __future__ import annotations

import numpy as np

from ..plotting.base import _grid, _shade_window, new_figure

__all__ = ["plot_actuated_run", "plot_claims", "plot_capture_vs_surfaces"]


def plot_actuated_run(ideal, actuated, window_s=None, max_deflection_deg: float | None = None):
    """The same turbulence with the ideal force and with the drogue's surfaces: lateral and
    vertical drogue offset [mm], the control force [N], each surface's deflection [deg] and the
    dynamic pressure at the drogue [Pa].

    Parameters
    ----------
    ideal, actuated : hosedrogue.results.run.RunResult
        The two runs (the second with its ``surfaces``).
    window_s : (float, float), optional
        Turbulence window [s], shaded.
    max_deflection_deg : float, optional
        The deflection limit [deg], drawn as dashed lines.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = new_figure(3, 2, size=(11.5, 8.5))
    # the ideal force wide and light under the surfaces' thin dark line: both visible where they agree
    styles = {"ideal force": (ideal, dict(lw=2.6, color="0.65")), "surfaces": (actuated, dict(lw=0.8, color="C0"))}
    for j, (axis, name) in enumerate(((1, "lateral dy"), (2, "vertical dz"))):
        for label, (r, kw) in styles.items():
            axes[0, j].plot(r.t_s, 1000 * r.drogue_offset_m[:, axis], label=label, **kw)
            axes[1, j].plot(r.t_s, r.control_force_n[:, axis - 1], label=label, **kw)
        axes[0, j].set_ylabel(f"{name} [mm]")
        axes[1, j].set_ylabel(f"{('u_hor', 'u_ver')[j]} [N]")
    d = np.degrees(actuated.surfaces.deflection_rad)
    cx = axes[2, 0]
    for k in range(d.shape[1]):
        cx.plot(actuated.t_s, d[:, k], lw=0.8, label=f"surface {k + 1}")
    if max_deflection_deg is not None:
        for s in (-1, 1):
            cx.axhline(s * max_deflection_deg, color="k", ls="--", lw=0.8)
    cx.set_ylabel("deflection [deg]")
    qx = axes[2, 1]
    qx.plot(actuated.t_s, actuated.surfaces.q_pa, color="C2", lw=0.9)
    qx.set_ylabel("dynamic pressure at the drogue [Pa]")
    for ax in axes.ravel():
        _shade_window(ax, window_s)
        _grid(ax)
        ax.set_xlabel("t [s]")
    axes[0, 0].legend(fontsize="small")
    cx.legend(fontsize="x-small", ncol=2)
    return fig


def plot_claims(table, one_cm_m: float = 0.01):
    """The largest lateral or vertical peak offset over the seeds [m] per turbulence case, one
    panel per controller, one marker per drogue (ideal force and the surfaces' variants), against
    the paper's "within 1 cm" line; a case whose runs diverged is drawn at the top edge.

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`hosedrogue.studies.drogue_actuator.claims_table`.
    one_cm_m : float
        The claim's bound [m].

    Returns
    -------
    matplotlib.figure.Figure
    """
    controllers = list(dict.fromkeys(table["controller"]))
    levels = list(dict.fromkeys(table["level"]))
    forces = list(dict.fromkeys(table["force"]))
    fig, axes = new_figure(1, len(controllers), size=(5.5 * len(controllers), 4.2), squeeze=False)
    top = 10.0
    for ax, c in zip(axes[0], controllers):
        for k, f in enumerate(forces):
            sub = table[(table["controller"] == c) & (table["force"] == f)].set_index("level").reindex(levels)
            worst = np.maximum(sub["peak_dy_m_max"], sub["peak_dz_m_max"]).to_numpy(dtype=float)
            diverged = sub["completed_fraction"].to_numpy(dtype=float) < 1.0
            worst = np.where(diverged | ~np.isfinite(worst), top, worst)
            x = np.arange(len(levels)) + (k - (len(forces) - 1) / 2) * 0.12
            ax.plot(x, worst, "os^vD"[k % 5], color=f"C{k}", ls="none", label=f)
            if diverged.any():
                ax.plot(x[diverged], worst[diverged], "x", color="k", ms=9)
        ax.axhline(one_cm_m, color="k", ls="--", lw=1.0, label="paper: within 1 cm")
        ax.set_yscale("log")
        ax.set_ylim(1e-3, top * 1.5)
        ax.set_xticks(np.arange(len(levels)), levels)
        ax.set_xlabel("turbulence case [-]")
        ax.set_ylabel("largest peak |dy|, |dz| over the seeds [m]")
        ax.set_title(f"{c.upper()} (x: a run diverged, drawn at {top:g} m)")
        _grid(ax)
        ax.legend(fontsize="x-small", loc="upper left")
    return fig


def plot_capture_vs_surfaces(table, newtons_per_deg: float | None = None):
    """Capture rate (Wilson 95 % intervals) against the surfaces' deflection limit (left, at the
    default bandwidth) and servo bandwidth (right, at the default limit), one colour per
    turbulence level; each level's ideal-force rate as a band.

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`hosedrogue.studies.docking_statistics.actuator_table` (``max_deflection_deg`` and
        ``bandwidth_hz`` inf for the ideal force).
    newtons_per_deg : float, optional
        Force per axis per degree of the deflection limit [N/deg] (the top axis of the left panel).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..spec.sections import DrogueActuator

    default = DrogueActuator()
    fig, axes = new_figure(1, 2, size=(11.5, 4.5))
    sweeps = (("max_deflection_deg", "bandwidth_hz", default.bandwidth_hz, "deflection limit [deg]"),
              ("bandwidth_hz", "max_deflection_deg", default.max_deflection_deg, "servo bandwidth [Hz]"))
    for ax, (x_col, fixed_col, fixed, label) in zip(axes, sweeps):
        for i, level in enumerate(dict.fromkeys(table["level"])):
            colour = f"C{i}"
            lev = table[table["level"] == level]
            free = lev[~np.isfinite(lev["max_deflection_deg"].to_numpy(dtype=float))]
            if len(free):
                r = free.iloc[0]
                ax.axhspan(r["ci95_low"], r["ci95_high"], color=colour, alpha=0.12, lw=0)
                ax.axhline(r["rate"], color=colour, lw=0.8, ls=":", label=f"{level}, ideal force (band: 95 %)")
            sub = lev[(lev[fixed_col] == fixed) & np.isfinite(lev[x_col].to_numpy(dtype=float))].sort_values(x_col)
            if sub.empty:
                continue
            x = sub[x_col].to_numpy(dtype=float)
            y = sub["rate"].to_numpy(dtype=float)
            err = np.vstack([y - sub["ci95_low"].to_numpy(dtype=float), sub["ci95_high"].to_numpy(dtype=float) - y])
            ax.errorbar(x * 1.03 ** (i - 0.5), y, yerr=err, color=colour, marker="o", ms=4, capsize=3,
                        label=f"{level}, surfaces")
        ax.set_xscale("log")
        ticks = sorted(set(table.loc[np.isfinite(table[x_col].to_numpy(dtype=float)), x_col]))
        force = newtons_per_deg and x_col == "max_deflection_deg"  # the authority under each limit
        ax.set_xticks(ticks, [f"{v:g}\n{v * newtons_per_deg:.0f} N" if force else f"{v:g}" for v in ticks])
        ax.minorticks_off()
        ax.set_xlabel(label + (" (below: per-axis authority at the nominal q [N])" if force else ""))
        ax.set_ylim(-0.02, 1.05)
        ax.set_ylabel("capture rate [-]")
        _grid(ax)
        ax.legend(fontsize="x-small", loc="best")
    axes[0].set_title(f"authority (servo {default.bandwidth_hz:g} Hz)")
    axes[1].set_title(f"bandwidth (limit {default.max_deflection_deg:g} deg)")
    return fig
