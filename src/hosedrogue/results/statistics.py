"""Per-run statistics of the drogue's displacement and the control force: one definition for the
compiled batch (:mod:`hosedrogue.simulation.batch`), the Monte Carlo campaign
(:mod:`hosedrogue.studies.campaign`) and the report.

Window
------
The statistics are taken over the samples at times ``t`` [s] with::

    start_s - WINDOW_EPS_S <= t < end_s - WINDOW_EPS_S

(:func:`in_window`, compiled :func:`in_window_at`). Output times ``t = k h`` carry rounding
errors of order 1e-15 s; the tolerance ``WINDOW_EPS_S`` = 1e-9 s makes a sample at the nominal
start count and a sample at the nominal end not count, whichever way it was rounded. With
turbulence the window is the turbulence window ``[start_s, start_s + duration_s)``
(:func:`turbulence_window`); without it the whole run ``[0, inf)``.

Statistics (columns and units: :data:`STATISTIC_UNITS`, :func:`statistic_units`)
--------------------------------------------------------------------------------
Displacements ``dy`` (lateral, right) and ``dz`` (vertical, down) are of the drogue from its
balance position in S_p [m]; ``dr = hypot(dy, dz)`` is the radial displacement [m].

* ``peak_*``: ``max |x|`` over the window [m or N];
* ``rms_*``: ``sqrt(mean(x^2))`` about the balance position [m];
* ``inside_<r>m_frac``: fraction of the window's samples with ``dr <= r`` [-];
* ``peak_u_y_n``, ``peak_u_z_n``, ``peak_u_n``: ``max |u_y|``, ``max |u_z|`` and
  ``max hypot(u_y, u_z)`` of the force applied to the drogue (lateral y, vertical z) [N].

:func:`window_statistics` evaluates them over a saved time series (numpy); the compiled
accumulator (:func:`accumulate`, :func:`finish`) evaluates the same formulas sample by sample
inside an integration loop, so no time series is stored. The two agree to round-off (the
accumulator sums in time order, numpy's mean sums pairwise: ~1e-16 relative).

The drogue's control surfaces, when it has them, have theirs in :mod:`hosedrogue.results.surfaces`.

This module imports numpy and numba only.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from numba import njit

from ..jit import JIT

#: Capture radii [m]: 0.1 m, the drogue positioning accuracy required in Wu et al. (2018); 0.305 m,
#: the radius of the paper's drogue basket (diameter 0.61 m, Table 1).
DEFAULT_CAPTURE_RADII_M = (0.1, 0.305)

#: Tolerance on the window's edges [s]: output times t = k h carry rounding errors.
WINDOW_EPS_S = 1e-9

#: (column, unit) of the displacement statistics, in column order.
DISPLACEMENT_STATISTICS = (
    ("peak_dy_m", "m"), ("peak_dz_m", "m"), ("peak_radial_m", "m"),
    ("rms_dy_m", "m"), ("rms_dz_m", "m"), ("rms_radial_m", "m"),
)
#: (column, unit) of the control-force statistics, in column order.
FORCE_STATISTICS = (("peak_u_y_n", "N"), ("peak_u_z_n", "N"), ("peak_u_n", "N"))

#: The fixed statistics and their units, in column order (the capture-radius columns follow).
STATISTIC_UNITS = dict(DISPLACEMENT_STATISTICS + FORCE_STATISTICS)

#: Fixed columns of a batch summary: whether the run completed, when it stopped [s], then the
#: statistics; one :func:`capture_column` per capture radius follows.
SUMMARY_COLUMNS = ("completed", "t_end_s", *STATISTIC_UNITS)

# layout of the accumulator array (compiled code indexes it with these constants)
_PEAK_Y, _PEAK_Z, _PEAK_R, _SQ_Y, _SQ_Z, _SQ_R, _PEAK_U0, _PEAK_U1, _PEAK_U, _COUNT = range(10)
#: Length of the accumulator before its capture-radius counters (:func:`new_accumulator`).
ACCUMULATOR_FIXED = 10


def capture_column(radius_m: float) -> str:
    """Column name of the time fraction inside a capture radius.

    Parameters
    ----------
    radius_m : float
        Capture radius [m].

    Returns
    -------
    str
        ``inside_<radius>m_frac`` with the radius to 6 significant digits, e.g. ``inside_0.1m_frac``.
    """
    return f"inside_{float(radius_m):g}m_frac"


def statistic_units(capture_radii_m: Sequence[float]) -> dict[str, str]:
    """The per-run statistics (column names) and their units, in column order.

    Parameters
    ----------
    capture_radii_m : sequence of float
        Capture radii [m], one ``inside_<r>m_frac`` column (unit ``"1"``) each.

    Returns
    -------
    dict
        Column name -> unit.
    """
    units = dict(STATISTIC_UNITS)
    units.update({capture_column(r): "1" for r in capture_radii_m})
    return units


def turbulence_window(turbulence) -> tuple[float, float]:
    """The statistics window [s] of a turbulence specification.

    Parameters
    ----------
    turbulence : object
        Has ``enabled`` (bool), ``start_s`` [s] and ``duration_s`` [s], e.g.
        :class:`hosedrogue.spec.params.Turbulence`.

    Returns
    -------
    (float, float)
        ``(start_s, start_s + duration_s)`` [s] with turbulence, ``(0, inf)`` without.
    """
    if not turbulence.enabled:
        return 0.0, math.inf
    return turbulence.start_s, turbulence.start_s + turbulence.duration_s


def in_window(t_s: np.ndarray, window_s: tuple[float, float]) -> np.ndarray:
    """Which samples lie in the window (the module's rule).

    Parameters
    ----------
    t_s : array
        Sample times [s].
    window_s : (float, float)
        Window ``(start, end)`` [s]; ``end`` may be inf.

    Returns
    -------
    array of bool
        ``start - WINDOW_EPS_S <= t < end - WINDOW_EPS_S``.
    """
    t = np.asarray(t_s)
    return (t >= window_s[0] - WINDOW_EPS_S) & (t < window_s[1] - WINDOW_EPS_S)


@njit(**JIT)
def in_window_at(t, start_s, end_s):
    """Compiled :func:`in_window` for one sample.

    Parameters
    ----------
    t : float
        Sample time [s].
    start_s, end_s : float
        Window start and end [s] (end may be inf).

    Returns
    -------
    bool
    """
    return t >= start_s - WINDOW_EPS_S and t < end_s - WINDOW_EPS_S


def window_statistics(t_s: np.ndarray, offset_m: np.ndarray, control_n: np.ndarray,
                      window_s: tuple[float, float], capture_radii_m: Sequence[float]) -> dict:
    """The per-run statistics of a saved time series inside a window.

    Parameters
    ----------
    t_s : array (N,)
        Sample times [s].
    offset_m : array (N, 3)
        Drogue position relative to its balance position [m] in S_p (columns x, y, z).
    control_n : array (N, 2)
        Force applied to the drogue ``[u_hor, u_ver]`` [N].
    window_s : (float, float)
        Statistics window [s] (:func:`in_window`).
    capture_radii_m : sequence of float
        Capture radii [m].

    Returns
    -------
    dict
        Column (:func:`statistic_units`) -> value; NaN where the window holds no sample (a run
        that stopped before the window).
    """
    inside = in_window(t_s, window_s)
    off = offset_m[inside]
    u = control_n[inside]
    dy, dz = off[:, 1], off[:, 2]
    dr = np.hypot(dy, dz)
    force = np.hypot(u[:, 0], u[:, 1])
    row = {
        "peak_dy_m": _peak(dy), "peak_dz_m": _peak(dz), "peak_radial_m": _peak(dr),
        "rms_dy_m": _rms(dy), "rms_dz_m": _rms(dz), "rms_radial_m": _rms(dr),
        "peak_u_y_n": _peak(u[:, 0]), "peak_u_z_n": _peak(u[:, 1]), "peak_u_n": _peak(force),
    }
    for r in capture_radii_m:
        row[capture_column(r)] = float(np.mean(dr <= r)) if dr.size else math.nan
    return row


def _peak(x: np.ndarray) -> float:
    return float(np.max(np.abs(x))) if x.size else math.nan


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(x * x))) if x.size else math.nan


# --- the compiled accumulator --------------------------------------------------------------------
def new_accumulator(n_radii: int) -> np.ndarray:
    """An empty accumulator for :func:`accumulate` (zeros).

    Parameters
    ----------
    n_radii : int
        Number of capture radii.

    Returns
    -------
    array (10 + n_radii,)
    """
    return np.zeros(ACCUMULATOR_FIXED + n_radii)


@njit(**JIT)
def reset(acc):
    """Empty an accumulator in place (compiled).

    Parameters
    ----------
    acc : array
        Accumulator of :func:`new_accumulator`.
    """
    acc[:] = 0.0


@njit(**JIT)
def accumulate(acc, dy, dz, u_hor, u_ver, radii):
    """Add one window sample to the accumulator ``acc`` (compiled).

    Parameters
    ----------
    acc : array (10 + len(radii),)
        Accumulator (:func:`new_accumulator`), updated in place.
    dy, dz : float
        Lateral and vertical drogue displacement from the balance position [m].
    u_hor, u_ver : float
        Force applied to the drogue [N].
    radii : array
        Capture radii [m].
    """
    dr = math.hypot(dy, dz)
    acc[_PEAK_Y] = max(acc[_PEAK_Y], abs(dy))
    acc[_PEAK_Z] = max(acc[_PEAK_Z], abs(dz))
    acc[_PEAK_R] = max(acc[_PEAK_R], dr)
    acc[_SQ_Y] += dy * dy
    acc[_SQ_Z] += dz * dz
    acc[_SQ_R] += dr * dr
    acc[_PEAK_U0] = max(acc[_PEAK_U0], abs(u_hor))
    acc[_PEAK_U1] = max(acc[_PEAK_U1], abs(u_ver))
    acc[_PEAK_U] = max(acc[_PEAK_U], math.hypot(u_hor, u_ver))
    for j in range(radii.shape[0]):
        if dr <= radii[j]:
            acc[ACCUMULATOR_FIXED + j] += 1.0
    acc[_COUNT] += 1.0


@njit(**JIT)
def finish(acc, out):
    """Write the statistics of the accumulator ``acc`` to ``out`` in column order (compiled).

    Parameters
    ----------
    acc : array (10 + n_radii,)
        Accumulator filled by :func:`accumulate`.
    out : array (9 + n_radii,)
        Receives the :data:`STATISTIC_UNITS` columns then the capture fractions; NaN when no
        sample was added.
    """
    c = acc[_COUNT]
    nr = acc.shape[0] - ACCUMULATOR_FIXED
    if c == 0.0:
        out[:] = math.nan
        return
    out[0] = acc[_PEAK_Y]
    out[1] = acc[_PEAK_Z]
    out[2] = acc[_PEAK_R]
    out[3] = math.sqrt(acc[_SQ_Y] / c)
    out[4] = math.sqrt(acc[_SQ_Z] / c)
    out[5] = math.sqrt(acc[_SQ_R] / c)
    out[6] = acc[_PEAK_U0]
    out[7] = acc[_PEAK_U1]
    out[8] = acc[_PEAK_U]
    for j in range(nr):
        out[9 + j] = acc[ACCUMULATOR_FIXED + j] / c


# --- whole-run figures of the report -------------------------------------------------------------
def peaks(offset_m: np.ndarray) -> tuple[float, float]:
    """Peak lateral and vertical displacement over the whole run.

    Parameters
    ----------
    offset_m : array (N, 3)
        Drogue position relative to its balance position [m].

    Returns
    -------
    (float, float)
        ``max |dy|``, ``max |dz|`` [m].
    """
    return float(np.max(np.abs(offset_m[:, 1]))), float(np.max(np.abs(offset_m[:, 2])))


def rms_in_window(t_s: np.ndarray, offset_m: np.ndarray, window_s: tuple[float, float]) -> tuple[float, float]:
    """RMS lateral and vertical displacement inside a window (the module's rule).

    Parameters
    ----------
    t_s : array (N,)
        Sample times [s].
    offset_m : array (N, 3)
        Drogue position relative to its balance position [m].
    window_s : (float, float)
        Window [s].

    Returns
    -------
    (float, float)
        ``rms dy``, ``rms dz`` [m].
    """
    off = offset_m[in_window(t_s, window_s)]
    return _rms(off[:, 1]), _rms(off[:, 2])


def force_peaks(control_n: np.ndarray) -> tuple[float, float]:
    """Peak horizontal and vertical control force over the whole run.

    Parameters
    ----------
    control_n : array (N, 2)
        Force applied to the drogue ``[u_hor, u_ver]`` [N].

    Returns
    -------
    (float, float)
        ``max |u_hor|``, ``max |u_ver|`` [N].
    """
    return float(np.max(np.abs(control_n[:, 0]))), float(np.max(np.abs(control_n[:, 1])))
