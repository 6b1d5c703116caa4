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

The drogue's control surfaces, when it has them, are a run's :class:`SurfaceSeries`: their columns
and their statistics (:func:`surface_statistics`) join the run's through :class:`WithSurfaces`.

This module imports numpy and numba only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numba import njit

from .jit import JIT

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

#: (column, unit) of a drogue actuator's statistics (:func:`surface_statistics`), in column order.
SURFACE_STATISTICS = (("peak_deflection_deg", "deg"), ("peak_deflection_rate_deg_s", "deg/s"),
                      ("deflection_saturated_frac", "1"), ("rate_saturated_frac", "1"))
#: A surface counts as at its limit within this fraction of it [-] (the second-order servo's soft
#: stop approaches the deflection limit exponentially, so "at the limit" needs a margin).
SATURATION_MARGIN = 0.01

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


def surface_statistics(t_s: np.ndarray, deflection_rad: np.ndarray, rate_rad_s: np.ndarray,
                       window_s: tuple[float, float], max_deflection_rad: float, max_rate_rad_s: float) -> dict:
    """A drogue actuator's statistics inside a window (:data:`SURFACE_STATISTICS`): the largest
    deflection [deg] and deflection rate [deg/s] of any surface, and the fractions of the window's
    samples in which some surface is within :data:`SATURATION_MARGIN` of its deflection limit
    (saturated in authority) or of its rate limit (saturated in rate) [-].

    Parameters
    ----------
    t_s : array (N,)
        Sample times [s].
    deflection_rad, rate_rad_s : array (N, n_s)
        Each surface's deflection [rad] and deflection rate [rad/s].
    window_s : (float, float)
        Statistics window [s] (:func:`in_window`).
    max_deflection_rad, max_rate_rad_s : float
        The deflection [rad] and rate [rad/s] limits.

    Returns
    -------
    dict
        Column -> value; NaN where the window holds no sample.
    """
    inside = in_window(t_s, window_s)
    d = np.abs(np.asarray(deflection_rad)[inside])
    r = np.abs(np.asarray(rate_rad_s)[inside])
    keep = 1.0 - SATURATION_MARGIN
    if not d.size:
        return {name: math.nan for name, _ in SURFACE_STATISTICS}
    return {"peak_deflection_deg": math.degrees(float(d.max())),
            "peak_deflection_rate_deg_s": math.degrees(float(r.max())),
            "deflection_saturated_frac": float(np.mean(np.any(d >= keep * max_deflection_rad, axis=1))),
            "rate_saturated_frac": float(np.mean(np.any(r >= keep * max_rate_rad_s, axis=1)))}


@dataclass(frozen=True)
class SurfaceSeries:
    """The drogue's control surfaces over a run (docs/model.md, "Actuated drogue")."""

    deflection_rad: np.ndarray  #: (N, n_s) each surface's deflection [rad]
    rate_rad_s: np.ndarray  #: (N, n_s) each surface's deflection rate [rad/s]
    q_pa: np.ndarray  #: (N,) dynamic pressure of the air at the drogue [Pa]
    max_deflection_rad: float  #: the deflection limit [rad]
    max_rate_rad_s: float  #: the rate limit [rad/s]

    def columns(self) -> dict[str, np.ndarray]:
        """``deflection_k_deg`` and ``deflection_rate_k_deg_s`` of each surface k = 1..n_s, then
        ``drogue_q_pa``."""
        d, r = np.degrees(self.deflection_rad), np.degrees(self.rate_rad_s)
        cols = {f"deflection_{k + 1}_deg": d[:, k] for k in range(d.shape[1])}
        cols.update({f"deflection_rate_{k + 1}_deg_s": r[:, k] for k in range(r.shape[1])})
        cols["drogue_q_pa"] = self.q_pa
        return cols


@dataclass(frozen=True, kw_only=True)
class WithSurfaces:
    """A run's result whose drogue may steer itself with control surfaces (``surfaces``): their
    columns after the run's, their statistics with the run's, a line in the headline. Mixed into
    :class:`hosedrogue.results.SimulationResult` and :class:`~hosedrogue.results.EngagementResult`."""

    surfaces: SurfaceSeries | None = None  #: the control surfaces' series (None: the ideal force)

    def columns(self) -> dict[str, np.ndarray]:
        """The run's columns, then the surfaces' (:meth:`SurfaceSeries.columns`)."""
        cols = super().columns()
        if self.surfaces is not None:
            cols.update(self.surfaces.columns())
        return cols

    def statistics(self, capture_radii_m=None) -> dict[str, float]:
        """The run's window statistics and the surfaces' (:meth:`surface_statistics`)."""
        return {**super().statistics(capture_radii_m), **self.surface_statistics()}

    def surface_statistics(self, window_s: tuple | None = None) -> dict[str, float]:
        """The surfaces' statistics (:func:`surface_statistics`; empty with the ideal force) over
        ``window_s`` [s] (default the run's statistics window), ended at contact in an engagement
        (after it the controller is off and the surfaces only return to neutral).

        Parameters
        ----------
        window_s : (float, float), optional
            Window [start, end) [s].

        Returns
        -------
        dict
        """
        if self.surfaces is None:
            return {}
        start, end = self.statistics_window_s if window_s is None else window_s
        contact = (getattr(self, "outcome", None) or {}).get("contact_time_s")
        end = end if contact is None else min(end, float(contact))
        s = self.surfaces
        return surface_statistics(self.t_s, s.deflection_rad, s.rate_rad_s, (start, end), s.max_deflection_rad,
                                  s.max_rate_rad_s)

    def headline(self) -> str:
        """The run's headline, then the surfaces' largest deflection [deg] and rate [deg/s] and the
        time at their limits [%]."""
        text = super().headline()
        if self.surfaces is not None:
            st = self.surface_statistics()
            text += (f"\ncontrol surfaces: largest deflection {st['peak_deflection_deg']:.3g} deg, rate "
                     f"{st['peak_deflection_rate_deg_s']:.3g} deg/s; at the deflection limit "
                     f"{100 * st['deflection_saturated_frac']:.3g} % and at the rate limit "
                     f"{100 * st['rate_saturated_frac']:.3g} % of the window")
        return text


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
