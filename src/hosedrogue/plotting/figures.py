"""Figures of simulation results. Every function returns a matplotlib Figure (no ``show()``);
axes carry units. Nothing here selects a backend or touches pyplot, so importing the package
leaves a user's interactive backend as it was; ``Figure.savefig`` renders files with Agg. Import cost stays out of the model: matplotlib loads here only.

Figures are built on :func:`new_figure`, which creates figures outside pyplot's global state, so
a long-running process (or a test suite) never accumulates pyplot figures. The functions take
*data* (arrays, result objects, mappings of labelled curves) and do no physics: the reproduction
report (:mod:`hosedrogue.report`) computes the data, writes it to CSV and hands it to these.

Conventions shared by the functions below:

- channels are ``"lateral"`` (u_hor [N] -> P_ny [m], drogue y, right positive) and
  ``"vertical"`` (u_ver [N] -> P_nz [m], drogue z, down positive);
- a *curve mapping* is ``{label: {"lateral": array, "vertical": array}}``; each label becomes
  one line in both channel panels, in the mapping's order;
- ``reference`` arguments (the paper's published models) are drawn dashed.
"""

from __future__ import annotations

from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

import matplotlib.ticker
from matplotlib.figure import Figure

CHANNELS = ("lateral", "vertical")
_CHANNEL_TITLE = {"lateral": "lateral channel (u_hor -> P_ny)", "vertical": "vertical channel (u_ver -> P_nz)"}


def new_figure(nrows: int = 1, ncols: int = 1, size=(7.0, 4.0), **kw):
    """A figure not registered with pyplot's global state (safe in long-running processes).

    Parameters
    ----------
    nrows, ncols : int
        Grid of axes [-].
    size : tuple of float
        Figure width and height [inch].
    **kw
        Passed to :meth:`matplotlib.figure.Figure.subplots` (``sharex``, ...).

    Returns
    -------
    fig : matplotlib.figure.Figure
    axes : matplotlib.axes.Axes or numpy.ndarray of them
    """
    fig = Figure(figsize=size, constrained_layout=True)
    axes = fig.subplots(nrows, ncols, **kw)
    return fig, axes


def save_figure(fig: Figure, path: str | Path, dpi: int = 120) -> Path:
    """Write ``fig`` to ``path`` (its folder is created).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : str or Path
        Image file; the format follows the suffix (``.png``, ``.pdf``, ...).
    dpi : int
        Resolution [dots per inch].

    Returns
    -------
    Path
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    return path


def _grid(ax, **kw):
    ax.grid(True, alpha=0.3, **kw)


def _shade_window(ax, window_s):
    """Grey band over the turbulence window (start, end) [s], if given."""
    if window_s is not None:
        ax.axvspan(window_s[0], window_s[1], color="0.85", alpha=0.5, lw=0, zorder=0)


def plot_displacement(result, labels: Sequence[str] | None = None, others: Sequence = (), title: str = ""):
    """Lateral and vertical drogue displacement from the balance position [m] against time [s].

    Parameters
    ----------
    result : SimulationResult
        The run to draw.
    labels : sequence of str, optional
        Legend labels of ``result`` and then of each of ``others``.
    others : sequence of SimulationResult
        Further results drawn on the same axes (e.g. controller off vs on).
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
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


# --- Sec. 2.3: steady state and turbulence --------------------------------------------------------
def plot_sweep(sweep_result) -> Figure:
    """Paper Fig. 3: drogue drag [N] and balance ratio D = V_D / L_H [-] against airspeed [m/s],
    one curve per altitude.

    Parameters
    ----------
    sweep_result : hosedrogue.analysis.sweep.SweepResult
        Points that did not converge are left out of the curves.
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


# --- Sec. 3.1: linear model and its reduction -----------------------------------------------------
def plot_linear_steps(t_s, y) -> Figure:
    """Paper Fig. 5: unit-step responses of the linearized model, both inputs to both outputs.

    Parameters
    ----------
    t_s : array_like, shape (N,)
        Time [s].
    y : array_like, shape (2, 2, N)
        ``y[i, j]`` is output i (P_ny, P_nz) [m] for a 1 N step in input j (u_hor, u_ver).
    """
    y = np.asarray(y)
    t_s = np.asarray(t_s)
    fig, axes = new_figure(2, 2, size=(9.0, 5.5), sharex=True, sharey=True)
    outs = ("P_ny", "P_nz")
    ins = ("u_hor", "u_ver")
    for i in range(2):
        for j in range(2):
            ax = axes[i, j]
            ax.plot(t_s, y[i, j], lw=1.1, color="C0" if i == j else "C3")
            ax.set_title(f"{ins[j]} -> {outs[i]}", fontsize=10)
            ax.set_xlabel("time t [s]")
            ax.set_ylabel(f"{outs[i]} [m] (1 N step)")
            _grid(ax)
    return fig


def _real_axis_scale(ax, reals) -> str:
    """Linear real axis when every point is within 1 1/s of the imaginary axis, else a
    symmetric-log axis (linear within +/-0.1 1/s) so lightly damped poles and far zeros show on
    one plot. Returns the axis-label suffix."""
    reals = np.asarray(reals, dtype=float)
    left = float(min(reals.min(initial=0.0), -1e-3))
    if left > -1.0:
        ax.set_xlim(1.1 * left, -0.08 * left)
        return ""
    ax.set_xscale("symlog", linthresh=0.1, linscale=1.0)
    ax.set_xlim(2.0 * left, 0.05)
    return " (symlog)"


def plot_pole_zero(pz: Mapping[str, Mapping[str, tuple]], reference: Mapping[str, Mapping[str, tuple]] | None = None) -> Figure:
    """Paper Fig. 6: pole-zero maps per channel, one row per model order.

    Parameters
    ----------
    pz : mapping
        ``{label: {"lateral": (poles, zeros), "vertical": (poles, zeros)}}`` (complex arrays,
        [1/s]); one row per label (e.g. full, 6th order, 2nd order).
    reference : mapping, optional
        Same structure keyed by the same labels (e.g. the paper's Table 2 models); drawn as
        hollow grey markers in the matching row.

    Where a row has points far from the imaginary axis the real axis is symmetric-logarithmic
    (linear within +/-0.1 1/s) so that lightly damped poles and far-away zeros show on one plot.
    """
    labels = list(pz)
    fig, axes = new_figure(len(labels), 2, size=(10.0, 2.8 * len(labels)), squeeze=False)
    for r, label in enumerate(labels):
        for c, ch in enumerate(CHANNELS):
            ax = axes[r, c]
            poles, zeros = (np.asarray(v, dtype=complex) for v in pz[label][ch])
            ax.plot(poles.real, poles.imag, "x", color="C0", ms=6, label="poles (this project)")
            ax.plot(zeros.real, zeros.imag, "o", mfc="none", color="C0", ms=6, label="zeros (this project)")
            reals = [poles.real, zeros.real]
            if reference is not None and label in reference:
                rp, rz = (np.asarray(v, dtype=complex) for v in reference[label][ch])
                ax.plot(rp.real, rp.imag, "x", color="0.45", ms=6, label="poles (paper)")
                ax.plot(rz.real, rz.imag, "s", mfc="none", color="0.45", ms=5, label="zeros (paper)")
                reals += [rp.real, rz.real]
            ax.axvline(0.0, color="k", lw=0.6)
            suffix = _real_axis_scale(ax, np.concatenate(reals))
            ax.set_title(f"{label}: {_CHANNEL_TITLE[ch]}", fontsize=9)
            ax.set_xlabel(f"real part [1/s]{suffix}")
            ax.set_ylabel("imaginary part [rad/s]")
            _grid(ax)
    # legend where both this project's and the paper's markers appear, else in the first row
    legend_row = next((r for r, label in enumerate(labels) if reference and label in reference), 0)
    axes[legend_row, 1].legend(fontsize=7, loc="upper left")
    return fig


def _bode_arrays(response):
    response = np.asarray(response, dtype=complex)
    mag_db = 20.0 * np.log10(np.maximum(np.abs(response), 1e-300))
    phase_deg = np.degrees(np.unwrap(np.angle(response)))
    return mag_db, phase_deg


def plot_bode_compare(omega_rad_s, curves: Mapping[str, Mapping[str, np.ndarray]],
                      reference: Mapping[str, Mapping[str, np.ndarray]] | None = None) -> Figure:
    """Paper Fig. 7: frequency response of the full-order vs reduced models per channel.

    Parameters
    ----------
    omega_rad_s : array_like, shape (N,)
        Angular frequency [rad/s].
    curves : mapping
        ``{label: {"lateral": G(j omega), "vertical": G(j omega)}}``, complex [m/N].
    reference : mapping, optional
        Same structure, drawn dashed (e.g. the paper's Table 2 models).
    """
    w = np.asarray(omega_rad_s, dtype=float)
    fig, axes = new_figure(2, 2, size=(10.0, 6.0), sharex=True)
    styles = [(curves, "-")] + ([(reference, "--")] if reference else [])
    for group, ls in styles:
        for k, (label, resp) in enumerate(group.items()):
            for c, ch in enumerate(CHANNELS):
                mag, ph = _bode_arrays(resp[ch])
                color = f"C{k}" if ls == "-" else f"C{k + 5}"
                axes[0, c].semilogx(w, mag, ls, color=color, lw=1.1, label=label)
                axes[1, c].semilogx(w, ph, ls, color=color, lw=1.1, label=label)
    for c, ch in enumerate(CHANNELS):
        axes[0, c].set_title(_CHANNEL_TITLE[ch], fontsize=10)
        axes[0, c].set_ylabel("magnitude |G| [dB re 1 m/N]")
        axes[1, c].set_ylabel("phase [deg]")
        for r in range(2):
            axes[r, c].set_xlabel("angular frequency omega [rad/s]")
            _grid(axes[r, c], which="both")
    axes[0, 1].legend(fontsize=8)
    return fig


def _channel_rows(t_s, rows, ylabel: str, log_time: bool, reference_rows=None, size=None) -> Figure:
    """Grid of step responses: one row per entry of ``rows``, one column per channel."""
    t = np.asarray(t_s, dtype=float)
    names = list(rows)
    fig, axes = new_figure(len(names), 2, size=size or (10.0, 3.2 * len(names)), squeeze=False)
    mask = t > 0 if log_time else np.ones_like(t, dtype=bool)
    for r, name in enumerate(names):
        groups = [(rows[name], "-")]
        if reference_rows is not None and name in reference_rows:
            groups.append((reference_rows[name], "--"))
        for group, ls in groups:
            for k, (label, resp) in enumerate(group.items()):
                color = f"C{k}" if ls == "-" else f"C{k + 5}"
                for c, ch in enumerate(CHANNELS):
                    y = np.asarray(resp[ch], dtype=float)
                    axes[r, c].plot(t[mask], y[mask], ls, color=color, lw=1.1, label=label)
        for c, ch in enumerate(CHANNELS):
            ax = axes[r, c]
            if log_time:
                ax.set_xscale("log")
            title = f"{name}: {_CHANNEL_TITLE[ch]}" if name else _CHANNEL_TITLE[ch]
            ax.set_title(title, fontsize=9)
            ax.set_xlabel("time t [s]" + (" (log scale)" if log_time else ""))
            ax.set_ylabel(ylabel)
            _grid(ax, which="both")
        axes[r, 1].legend(fontsize=8)
    return fig


def plot_step_compare(t_s, curves: Mapping[str, Mapping[str, np.ndarray]],
                      reference: Mapping[str, Mapping[str, np.ndarray]] | None = None) -> Figure:
    """Paper Fig. 8: open-loop unit-step response [m per 1 N] of full vs reduced models.

    Parameters
    ----------
    t_s : array_like
        Time [s].
    curves : mapping
        ``{label: {"lateral": y, "vertical": y}}``, drogue offset [m] for a 1 N force step.
    reference : mapping, optional
        Same structure, drawn dashed (the paper's Table 2 models).
    """
    return _channel_rows(t_s, {"": curves}, "drogue offset [m] (1 N step)", False,
                         None if reference is None else {"": reference}, size=(10.0, 3.6))


def plot_closed_loop_steps(t_s, rows: Mapping[str, Mapping[str, Mapping[str, np.ndarray]]],
                           log_time: bool = False,
                           reference_rows: Mapping[str, Mapping[str, Mapping[str, np.ndarray]]] | None = None) -> Figure:
    """Paper Figs. 10 and 11: closed-loop unit reference steps, one row per design model.

    Parameters
    ----------
    t_s : array_like
        Time [s] (evenly spaced from 0).
    rows : mapping
        ``{row title: {curve label: {"lateral": y, "vertical": y}}}``, drogue offset [m] for
        a 1 m reference step. Fig. 10: rows = design models, curves = PID and LQR; Fig. 11:
        curves = full, 6th and 2nd order.
    log_time : bool
        Logarithmic time axis (shows a 0.07 s PID rise and a 10 s LQR rise on one plot).
    reference_rows : mapping, optional
        Same structure, drawn dashed.
    """
    return _channel_rows(t_s, rows, "drogue offset [m] (1 m step)", log_time, reference_rows)


# --- Sec. 3.3: controllers on the nonlinear model ------------------------------------------------
def plot_controller_on_off(result_off, results_on: Mapping[str, object], window_s=None) -> Figure:
    """Paper Fig. 12: drogue displacement with the controller off and on, and the y-z trajectory.

    One row per controller. Columns: lateral displacement [m] off vs on; vertical displacement
    [m] off vs on; the controlled displacements alone in millimetres (they are invisible on the
    metre scale); the drogue's y-z trajectory about its balance position [m].

    Parameters
    ----------
    result_off : SimulationResult
        Controller off.
    results_on : mapping
        ``{controller label: SimulationResult}`` with the controller on (same turbulence).
    window_s : (float, float), optional
        Turbulence window [s], shaded.
    """
    names = list(results_on)
    fig, axes = new_figure(len(names), 4, size=(15.0, 3.4 * len(names)), squeeze=False)
    off = result_off.drogue_offset_m
    for r, name in enumerate(names):
        res = results_on[name]
        on = res.drogue_offset_m
        for c, (k, what) in enumerate(((1, "lateral dy"), (2, "vertical dz"))):
            ax = axes[r, c]
            _shade_window(ax, window_s)
            ax.plot(result_off.t_s, off[:, k], lw=0.9, color="C3", label="off")
            ax.plot(res.t_s, on[:, k], lw=1.1, color="C0", label=f"on ({name})")
            ax.set_xlabel("time t [s]")
            ax.set_ylabel(f"{what} [m]")
            ax.set_title(f"{name}: {what.split()[0]} displacement", fontsize=9)
            _grid(ax)
            ax.legend(fontsize=7, loc="upper left")
        ax = axes[r, 2]
        _shade_window(ax, window_s)
        ax.plot(res.t_s, 1000.0 * on[:, 1], lw=1.0, color="C0", label="lateral dy")
        ax.plot(res.t_s, 1000.0 * on[:, 2], lw=1.0, color="C2", label="vertical dz")
        ax.set_xlabel("time t [s]")
        ax.set_ylabel("displacement [mm]")
        ax.set_title(f"{name} on: displacement in millimetres", fontsize=9)
        _grid(ax)
        ax.legend(fontsize=7, loc="upper left")
        ax = axes[r, 3]
        ax.plot(off[:, 1], off[:, 2], lw=0.7, color="C3", label="off")
        ax.plot(on[:, 1], on[:, 2], lw=1.0, color="C0", label=f"on ({name})")
        ax.plot([0.0], [0.0], "k+", ms=10)
        ax.invert_yaxis()
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("lateral dy [m] (right)")
        ax.set_ylabel("vertical dz [m] (down)")
        ax.set_title(f"{name}: y-z trajectory, seen from behind", fontsize=9)
        _grid(ax)
        ax.legend(fontsize=7, loc="upper left")
    return fig


def plot_control_forces(results: Mapping[str, object], window_s=None) -> Figure:
    """Paper Fig. 13: control forces u_hor and u_ver [N] against time [s], one curve per
    controller.

    Parameters
    ----------
    results : mapping
        ``{controller label: SimulationResult}``.
    window_s : (float, float), optional
        Turbulence window [s], shaded.
    """
    fig, (ax_h, ax_v) = new_figure(2, 1, size=(8.0, 5.5), sharex=True)
    for k, (name, res) in enumerate(results.items()):
        ax_h.plot(res.t_s, res.control_n[:, 0], lw=0.9, color=f"C{k}", label=name)
        ax_v.plot(res.t_s, res.control_n[:, 1], lw=0.9, color=f"C{k}", label=name)
    for ax, what in ((ax_h, "lateral force u_hor [N]"), (ax_v, "vertical force u_ver [N]\n(positive down)")):
        _shade_window(ax, window_s)
        ax.set_xlabel("time t [s]")
        ax.set_ylabel(what)
        _grid(ax)
    ax_h.legend(fontsize=8)
    return fig


def plot_hose_3d(joints_list: Sequence[np.ndarray], labels: Sequence[str]) -> Figure:
    """The hose in 3D (S_p: x forward, y right, z down, origin at the tow point).

    Parameters
    ----------
    joints_list : sequence of arrays, each (n+1, 3)
        Joint positions [m] (joint 0 = tow point, joint n = drogue). The first shape is drawn
        black and dashed (the reference, e.g. the balance position).
    labels : sequence of str
        One label per shape.

    The axes are scaled independently (the hose is 15 m long and swings by about 1 m), so the
    lateral and vertical excursions are exaggerated relative to the length. The view is from
    behind and to the left of the hose, above it.
    """
    from matplotlib.ticker import MaxNLocator

    fig, ax = new_figure(1, 1, size=(9.0, 5.5), subplot_kw={"projection": "3d"})
    allj = np.concatenate([np.asarray(j) for j in joints_list])
    for k, (joints, label) in enumerate(zip(joints_list, labels)):
        j = np.asarray(joints)
        style = dict(color="k", ls="--", lw=2.0) if k == 0 else dict(color=f"C{k - 1}", ls="-", lw=1.3)
        ax.plot(j[:, 0], j[:, 1], j[:, 2], marker=".", ms=3, label=label, **style)
        ax.plot([j[-1, 0]], [j[-1, 1]], [j[-1, 2]], "o", ms=7, color=style["color"])
    ax.plot([0.0], [0.0], [0.0], "k^", ms=7, label="tow point")
    ax.set_box_aspect((1.6, 1.0, 0.8))
    ax.set_zlim(allj[:, 2].max() + 0.2, allj[:, 2].min() - 0.2)  # z down: draw down as down
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(5))
    ax.set_xlabel("x forward [m]")
    ax.set_ylabel("y right [m]")
    ax.set_zlabel("z down [m]")
    ax.view_init(elev=20.0, azim=-125.0)
    fig.legend(loc="outside right upper", fontsize=8)
    return fig


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
    step_studies : sequence of hosedrogue.analysis.convergence.StepStudy
        (a) max drogue-position error [m] against the step [s], log-log, with a 4th-order
        guide line.
    link_study : LinkStudy or mapping ``{label: LinkStudy}``
        (b) drogue balance height z [m] and (c) lowest lateral/vertical mode frequency
        [rad/s] against the number of links.
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


# --- animation ------------------------------------------------------------------------------------
def _canvas_pillow_writer():
    """A PillowWriter that grabs the Agg canvas as the caller left it (static background plus
    blitted moving artists) instead of re-rendering the whole figure through ``savefig`` for
    every frame (two full draws per frame, mostly tick-label layout: ~50x slower)."""
    from matplotlib.animation import PillowWriter
    from PIL import Image

    class CanvasPillowWriter(PillowWriter):
        def setup(self, fig, outfile, dpi=None):
            super().setup(fig, outfile, dpi=dpi)
            self.images = []

        def grab_frame(self, **savefig_kwargs):
            canvas = self.fig.canvas
            size = canvas.get_width_height(physical=True)
            im = Image.frombuffer("RGBA", size, bytes(canvas.buffer_rgba()), "raw", "RGBA", 0, 1)
            self.images.append(im.convert("RGB"))

        def finish(self):
            self.images[0].save(self.outfile, save_all=True, append_images=self.images[1:],
                                duration=int(1000 / self.fps), loop=0)

    return CanvasPillowWriter


def animate_hose(result_off, result_on, path: str | Path, fps: int = 10, window_s=None,
                 labels: tuple[str, str] = ("controller off", "controller on"), dpi: int = 72) -> Path:
    """GIF of the hose and drogue in turbulence, controller off and on: side view (x-z) and rear
    view (y-z, looking forward from behind the drogue).

    Parameters
    ----------
    result_off, result_on : SimulationResult
        Two runs of the same turbulence, controller off and on.
    path : str or Path
        Output GIF file.
    fps : int
        Frames per second of both the GIF and the simulated time (one frame per 1/fps s of
        simulated time: the animation runs in real time).
    window_s : (float, float), optional
        Time span to animate [s]; default the whole run.
    labels : (str, str)
        Legend labels of the two runs.
    dpi : int
        Resolution; the default keeps a 20 s animation at 10 fps near 1-2 MB.

    Returns
    -------
    Path
        The written file.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    t = np.asarray(result_off.t_s)
    t0, t1 = (t[0], t[-1]) if window_s is None else window_s
    frame_times = np.arange(t0, t1 + 1e-9, 1.0 / fps)
    idx_off = np.clip(np.searchsorted(t, frame_times), 0, t.size - 1)
    t_on = np.asarray(result_on.t_s)
    idx_on = np.clip(np.searchsorted(t_on, frame_times), 0, t_on.size - 1)
    j_off = np.asarray(result_off.joints_m)
    j_on = np.asarray(result_on.joints_m)
    both = np.concatenate([j_off[idx_off].reshape(-1, 3), j_on[idx_on].reshape(-1, 3)])
    lo, hi = both.min(axis=0), both.max(axis=0)
    pad = 0.08 * np.maximum(hi - lo, 0.5)

    fig, (ax_side, ax_rear) = new_figure(1, 2, size=(9.0, 3.4), gridspec_kw={"width_ratios": [2.2, 1.0]})
    fig.set_dpi(dpi)
    lines = []
    for ax, (a, b) in ((ax_side, (0, 2)), (ax_rear, (1, 2))):
        for key, color, lab in (("off", "C3", labels[0]), ("on", "C0", labels[1])):
            (hose,) = ax.plot([], [], "-", color=color, lw=1.6, label=lab, animated=True)
            (drogue,) = ax.plot([], [], "o", color=color, ms=6, animated=True)
            lines.append((key, hose, drogue, a, b))
        ax.plot([0.0], [0.0], "k^", ms=6)
        ax.set_xlim(lo[a] - pad[a], hi[a] + pad[a])
        ax.set_ylim(hi[b] + pad[b], lo[b] - pad[b])  # z down
        _grid(ax)
    ax_side.set_xlabel("x forward [m]")
    ax_side.set_ylabel("z down [m]")
    ax_side.set_title("side view", fontsize=9)
    ax_rear.set_xlabel("y right [m]")
    ax_rear.set_ylabel("z down [m]")
    ax_rear.set_title("rear view (from behind)", fontsize=9)
    ax_side.legend(fontsize=7, loc="lower left")
    stamp = ax_side.text(0.5, 0.95, "", transform=ax_side.transAxes, ha="center", va="top", fontsize=9,
                         animated=True)

    # Draw (and lay out) the static parts once, then freeze the layout and blit the moving
    # artists onto a copy of that background for every frame.
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    fig.set_layout_engine("none")
    background = canvas.copy_from_bbox(fig.bbox)
    writer = _canvas_pillow_writer()(fps=fps)
    with writer.saving(fig, str(path), dpi=dpi):
        for k, tf in enumerate(frame_times):
            canvas.restore_region(background)
            for key, hose, drogue, a, b in lines:
                j = j_off[idx_off[k]] if key == "off" else j_on[idx_on[k]]
                hose.set_data(j[:, a], j[:, b])
                drogue.set_data([j[-1, a]], [j[-1, b]])
                fig.draw_artist(hose)
                fig.draw_artist(drogue)
            stamp.set_text(f"t = {tf:5.1f} s")
            fig.draw_artist(stamp)
            writer.grab_frame()
    return path


__all__ = [
    "new_figure", "save_figure", "plot_displacement", "plot_sweep", "plot_turbulence_speeds",
    "plot_linear_steps", "plot_pole_zero", "plot_bode_compare", "plot_step_compare",
    "plot_closed_loop_steps", "plot_controller_on_off", "plot_control_forces", "plot_hose_3d",
    "plot_convergence", "animate_hose", "plt",
]
