"""The spectrum of a run's drogue displacement: Welch's estimate of the one-sided power spectral
density of the lateral and vertical offset from the balance position over the run's statistics
window (``scipy.signal.welch``), for ``run.json`` and its figure, beside the covariance analysis's
prediction where the run has one (docs/loop-analysis.md, "Spectra of runs").

Welch's method here: Hann window, segments of :data:`SEGMENT_S` (or half the window when it is
shorter than two of them), 50 % overlap, each segment's mean removed; the frequency resolution is
1 / segment length [Hz] (stated in the document). The PSD is per hertz and one-sided: its integral
over frequency is the offset's variance about the segments' means.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["F_MAX_HZ", "MIN_SAMPLES", "PREDICTION_KEY", "SEGMENT_S", "displacement_spectrum", "spectrum_figure"]

#: The key of a run's ``meta`` that holds the covariance analysis's prediction
#: (:func:`hosedrogue.scenarios.spectrum.spectrum_prediction`); run.json puts it in ``"spectrum"``.
PREDICTION_KEY = "spectrum_prediction"
#: Segment length of Welch's estimate [s]: resolution 0.025 Hz, finer than the half-power bandwidth
#: of the hose's least damped modes (0.03 Hz for the paper's lateral mode, 0.245 Hz, damping 0.07).
SEGMENT_S = 40.0
#: Fewest samples in the statistics window for a spectrum [-] (below it, none: too short to tell).
MIN_SAMPLES = 256
#: Highest frequency written to run.json [Hz]: the drogue's displacement spectrum is 1e-6 of its
#: peak and below there in every shipped scenario.
F_MAX_HZ = 10.0


def displacement_spectrum(result, prediction: dict | None = None) -> dict | None:
    """Welch's PSD of the drogue's lateral and vertical offset over the statistics window.

    Parameters
    ----------
    result : RunResult
        The run (its ``t_s``, ``drogue_offset_m`` and ``statistics_window_s``).
    prediction : dict, optional
        The covariance analysis's ``frequency_hz`` [Hz], ``lateral_m2_hz`` and ``vertical_m2_hz``
        [m^2/Hz] and ``rms_m`` [m], put beside the estimate as ``"predicted"``; or a ``"note"``
        saying why there is none.

    Returns
    -------
    dict or None
        ``method``, ``segment_s`` [s], ``resolution_hz`` [Hz], ``window_s`` [s], ``frequency_hz``
        [Hz], ``lateral_m2_hz``, ``vertical_m2_hz`` [m^2/Hz] (up to :data:`F_MAX_HZ`), ``predicted``
        (or ``predicted_note``); None when the window holds fewer than :data:`MIN_SAMPLES` samples
        or the output times are not evenly spaced.
    """
    t = np.asarray(result.t_s, dtype=float)
    start, end = result.statistics_window_s
    keep = (t >= start) & (t < end)
    if keep.sum() < MIN_SAMPLES:
        return None
    tw = t[keep]
    dt = np.diff(tw)
    if not np.allclose(dt, dt[0], rtol=1e-6, atol=0.0):
        return None
    # imported here, after the checks: scipy.signal takes 0.3-0.7 s of CPU to import, which a run
    # too short for a spectrum (a first engagement run) need not pay
    from scipy.signal import welch

    h = float(dt[0])
    span = tw[-1] - tw[0] + h
    segment = min(SEGMENT_S, span / 2.0)
    nper = int(round(segment / h))
    off = result.drogue_offset_m[keep]
    f, pyy = welch(off[:, 1], fs=1.0 / h, window="hann", nperseg=nper, noverlap=nper // 2, detrend="constant")
    _, pzz = welch(off[:, 2], fs=1.0 / h, window="hann", nperseg=nper, noverlap=nper // 2, detrend="constant")
    band = f <= F_MAX_HZ
    out = {"method": "Welch (scipy.signal.welch): Hann window, 50 % overlap, segment means removed; one-sided, "
                     "per hertz",
           "segment_s": round(nper * h, 9), "resolution_hz": round(1.0 / (nper * h), 9),
           "window_s": [float(tw[0]), float(tw[-1] + h)],
           "frequency_hz": f[band].tolist(), "lateral_m2_hz": pyy[band].tolist(), "vertical_m2_hz": pzz[band].tolist()}
    if prediction is not None and "note" in prediction:
        out["predicted_note"] = prediction["note"]
    elif prediction is not None:
        out["predicted"] = prediction
    return out


def spectrum_figure(result, title: str = ""):
    """The figure of :func:`displacement_spectrum` with the run's prediction (meta
    ``"spectrum_prediction"``), or None without a spectrum.

    Parameters
    ----------
    result : RunResult
        The run.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure or None
    """
    from ..plotting.loop import plot_psd

    spec = displacement_spectrum(result, result.meta.get(PREDICTION_KEY))
    if spec is None:
        return None
    pred = spec.get("predicted")
    predicted = None if pred is None else {"frequency_hz": pred["frequency_hz"],
                                           "psd_m2_hz": [pred["lateral_m2_hz"], pred["vertical_m2_hz"]]}
    return plot_psd(np.array(spec["frequency_hz"]), np.array([spec["lateral_m2_hz"], spec["vertical_m2_hz"]]),
                    predicted, spec["resolution_hz"], title or str(result.meta.get("scenario", "")))


def rms_from_spectrum(spec: dict) -> tuple[float, float]:
    """The RMS [m] the spectrum holds (lateral, vertical): the square root of its integral.

    Parameters
    ----------
    spec : dict
        :func:`displacement_spectrum`'s document.

    Returns
    -------
    tuple of float
    """
    f = np.asarray(spec["frequency_hz"])
    return tuple(math.sqrt(float(np.trapezoid(np.asarray(spec[k]), f))) for k in ("lateral_m2_hz", "vertical_m2_hz"))
