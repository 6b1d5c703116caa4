"""Figures of the loop analysis and of the drogue's spectra: each channel's Bode and Nyquist plots
with its margins (:mod:`hosedrogue.controllers.margins`), and the PSD of a run's drogue offset
beside the covariance analysis's prediction (:mod:`hosedrogue.controllers.covariance`)."""

from __future__ import annotations

from typing import Mapping

import numpy as np
from matplotlib.figure import Figure

from .base import _grid, new_figure

#: The Nyquist plot shows L where |L| is below this [-]: the view is the region about -1.
NYQUIST_CLIP = 10.0


def plot_loops(w_rad_s: Mapping[str, np.ndarray], response: Mapping[str, np.ndarray],
               margins: Mapping[str, Mapping], title: str = "") -> Figure:
    """Bode magnitude, Bode phase and Nyquist plot of each channel's loop L.

    Parameters
    ----------
    w_rad_s : mapping
        Channel -> frequencies [rad/s].
    response : mapping
        Channel -> L(i w) (complex, force [N] to force [N]).
    margins : mapping
        Channel -> ``gain_margin_db`` [dB], ``phase_margin_deg`` [deg], ``gain_crossover_rad_s``
        [rad/s], ``delay_margin_s`` [s] (:meth:`hosedrogue.controllers.margins.LoopMargins.as_dict`).
    title : str
        Figure title.

    Returns
    -------
    Figure
    """
    channels = list(response)
    fig, axes = new_figure(3, len(channels), size=(5.0 * len(channels), 10.0), squeeze=False)
    for c, ch in enumerate(channels):
        w, L, m = np.asarray(w_rad_s[ch]), np.asarray(response[ch]), margins[ch]
        ax_m, ax_p, ax_n = axes[0, c], axes[1, c], axes[2, c]
        ax_m.semilogx(w, 20.0 * np.log10(np.abs(L)), lw=1.1)
        ax_m.axhline(0.0, color="0.5", lw=0.8)
        ax_m.set_ylabel("|L| [dB]")
        ax_m.set_title(f"{ch}: GM {m['gain_margin_db']:.3g} dB, PM {m['phase_margin_deg']:.3g} deg, "
                       f"DM {1e3 * m['delay_margin_s']:.3g} ms", fontsize=9)
        ax_p.semilogx(w, np.degrees(np.unwrap(np.angle(L))), lw=1.1)
        ax_p.set_ylabel("arg L [deg]")
        ax_p.set_xlabel("angular frequency [rad/s]")
        for ax in (ax_m, ax_p):
            if np.isfinite(m["gain_crossover_rad_s"]):
                ax.axvline(m["gain_crossover_rad_s"], color="C3", lw=0.8, ls="--")
            _grid(ax)
        near = np.where(np.abs(L) < NYQUIST_CLIP, L, np.nan)  # the part near -1, no chords to far points
        ax_n.plot(near.real, near.imag, lw=1.1, label="w > 0")
        ax_n.plot(near.real, -near.imag, lw=0.8, ls=":", color="C0", label="w < 0")
        ax_n.legend(fontsize=7, loc="upper right")
        ax_n.plot([-1.0], [0.0], "r+", ms=10)
        circle = np.exp(1j * np.linspace(0.0, 2.0 * np.pi, 200))
        ax_n.plot(circle.real, circle.imag, color="0.6", lw=0.6)
        ax_n.set_xlim(-3.0, 2.0)
        ax_n.set_ylim(-2.5, 2.5)
        ax_n.set_aspect("equal")
        ax_n.set_xlabel("Re L [-]")
        ax_n.set_ylabel("Im L [-]")
        _grid(ax_n)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


def plot_psd(frequency_hz: np.ndarray, psd_m2_hz: np.ndarray, predicted: Mapping | None = None,
             resolution_hz: float | None = None, title: str = "") -> Figure:
    """One-sided PSD of the drogue's lateral and vertical offset, with the linear prediction.

    Parameters
    ----------
    frequency_hz : array_like (F,)
        Frequencies of the run's estimate [Hz].
    psd_m2_hz : array_like (2, F)
        Lateral, vertical PSD [m^2/Hz].
    predicted : mapping, optional
        ``frequency_hz`` (G,) [Hz] and ``psd_m2_hz`` (2, G) [m^2/Hz] of the prediction.
    resolution_hz : float, optional
        The estimate's frequency resolution [Hz], shown in the legend.
    title : str
        Figure title.

    Returns
    -------
    Figure
    """
    f = np.asarray(frequency_hz)
    psd = np.asarray(psd_m2_hz)
    fig, axes = new_figure(1, 2, size=(10.0, 4.0), squeeze=False)
    label = "run (Welch" + (f", resolution {resolution_hz:.3g} Hz)" if resolution_hz else ")")
    for i, name in enumerate(("lateral", "vertical")):
        ax = axes[0, i]
        keep = f > 0.0
        ax.loglog(f[keep], psd[i, keep], lw=1.0, label=label)
        if predicted is not None:
            ax.loglog(predicted["frequency_hz"], np.asarray(predicted["psd_m2_hz"])[i], lw=1.2, ls="--",
                      color="C3", label="linear prediction")
        ax.set_title(f"{name} offset", fontsize=10)
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel("PSD [m^2/Hz]")
        ax.legend(fontsize=8)
        _grid(ax)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig
