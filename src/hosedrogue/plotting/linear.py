"""Figures of the linear model, its reductions and the closed-loop steps (paper Sec. 3.1-3.2:
Figs. 5-8, 10 and 11)."""

from __future__ import annotations

from typing import Mapping

import numpy as np

from matplotlib.figure import Figure

from .base import CHANNELS, _CHANNEL_TITLE, _grid, new_figure


def plot_linear_steps(t_s, y) -> Figure:
    """Paper Fig. 5: unit-step responses of the linearized model, both inputs to both outputs.

    Parameters
    ----------
    t_s : array_like, shape (N,)
        Time [s].
    y : array_like, shape (2, 2, N)
        ``y[i, j]`` is output i (P_ny, P_nz) [m] for a 1 N step in input j (u_hor, u_ver).

    Returns
    -------
    Figure
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

    Returns
    -------
    Figure
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

    Returns
    -------
    Figure
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

    Returns
    -------
    Figure
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

    Returns
    -------
    Figure
    """
    return _channel_rows(t_s, rows, "drogue offset [m] (1 m step)", log_time, reference_rows)
