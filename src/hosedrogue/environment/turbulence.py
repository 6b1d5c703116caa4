"""Dryden turbulence: the gust record drawn through the forming filters.

The spectra, the forming filters and their exact discretization are in
:mod:`hosedrogue.environment.dryden`, whose public names are re-exported here
(``MODELS``, ``AXES``, ``dryden_psd``, ``forming_filter``, ``discretize_filter``). This module draws a
stationary record from them (:func:`generate_gusts`), reads it in the inner loop
(:func:`gust_at`, compiled) and smooths its window's edges (:func:`smoothed_record`).

Standard intensities
--------------------
:func:`standard_intensity` (defined in :mod:`hosedrogue.spec.standards`, re-exported here) gives the
MIL-F-8785C Fig. 7 high-altitude rms intensity for light, moderate and severe turbulence.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
from numba import njit

from ..jit import JIT, JIT_INLINE, JIT_NO_ALLOC

from ..spec.params import ParameterError, Turbulence
from ..spec.standards import (  # noqa: F401 - part of this module's public interface
    INTENSITY_ALTITUDE_FT,
    INTENSITY_FT_S,
    PROBABILITY_OF_EXCEEDANCE,
    standard_intensity,
)
from .dryden import AXES, MODELS, discretize_filter, dryden_psd, forming_filter  # noqa: F401 - re-exported


def _noise_factor(Qd: np.ndarray) -> np.ndarray:
    """Lower factor L with L L^T = Qd (Cholesky; eigen-decomposition if round-off spoils it)."""
    try:
        return scipy.linalg.cholesky(Qd, lower=True)
    except np.linalg.LinAlgError:
        # Only for extreme dt / (L/V): Qd is positive definite in exact arithmetic, but its
        # smallest eigenvalue can drown in round-off; clip it at zero.
        w, U = np.linalg.eigh(Qd)
        return U * np.sqrt(np.clip(w, 0.0, None))


@njit(**JIT)
def _run_filter(phi, lq, c, x0, noise, out):
    """Fill ``out[k] = c . x[k]`` with ``x[k+1] = phi x[k] + lq noise[k]``, ``x[0] = x0``."""
    n = x0.shape[0]
    x = x0.copy()
    xn = np.empty(n)
    nsamp = out.shape[0]
    for k in range(nsamp):
        y = 0.0
        for i in range(n):
            y += c[i] * x[i]
        out[k] = y
        if k == nsamp - 1:
            break
        for i in range(n):
            s = 0.0
            for j in range(n):
                s += phi[i, j] * x[j] + lq[i, j] * noise[k, j]
            xn[i] = s
        for i in range(n):
            x[i] = xn[i]


# ----------------------------------------------------------------------------------------------
# the gust record
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class GustRecord:
    """Sampled gust velocities and the window in which they act.

    Attributes
    ----------
    t0_s : float
        Time of the first sample [s].
    dt_s : float
        Sample interval [s].
    values : numpy.ndarray
        float64, C-contiguous, shape (N, 3), N >= 2: gust velocity ``[u, v, w]`` [m/s] along
        S_p x, y, z at times ``t0_s + k dt_s``. Treat as read-only.
    t_on_s, t_off_s : float
        The gusts act for ``t_on_s <= t < t_off_s`` [s] and are zero outside.
    interpolation : {"linear", "cubic"}
        How :func:`gust_at` reads between samples (``Turbulence.interpolation``).
    """

    t0_s: float
    dt_s: float
    values: np.ndarray
    t_on_s: float
    t_off_s: float
    interpolation: str = "linear"

    def __post_init__(self) -> None:
        values = np.ascontiguousarray(self.values, dtype=np.float64)
        if values.ndim != 2 or values.shape[1] != 3 or values.shape[0] < 2:
            raise ValueError(f"values: shape {values.shape} must be (N, 3) with N >= 2")
        if not (math.isfinite(self.dt_s) and self.dt_s > 0.0):
            raise ValueError(f"dt_s = {self.dt_s!r}: must be a finite number > 0 [s]")
        if self.interpolation not in ("linear", "cubic"):
            raise ValueError(f"interpolation = {self.interpolation!r}: must be 'linear' or 'cubic'")
        object.__setattr__(self, "values", values)

    @property
    def time_s(self) -> np.ndarray:
        """Sample times [s], shape (N,)."""
        return self.t0_s + self.dt_s * np.arange(self.values.shape[0])

    def at(self, t):
        """Gust velocity at time(s) ``t``, computed by :func:`gust_at` itself (same arithmetic).

        Parameters
        ----------
        t : float or array_like
            Time [s].

        Returns
        -------
        numpy.ndarray
            Shape ``np.shape(t) + (3,)``: ``[u, v, w]`` [m/s] along S_p x, y, z; interpolated
            between samples (``interpolation``), clamped at the ends of the record, zero outside
            ``[t_on_s, t_off_s)``.
        """
        t = np.asarray(t, dtype=np.float64)
        flat = np.ascontiguousarray(t.reshape(-1))
        out = np.empty((flat.size, 3))
        _gust_series(flat, float(self.t0_s), float(self.dt_s), self.values, float(self.t_on_s),
                     float(self.t_off_s), self.interpolation == "cubic", out)
        return out.reshape(t.shape + (3,))


@njit(**JIT_INLINE)
def _segment(v, i, n, j, f, cubic):
    """Value of column j on the segment [i, i+1] at fraction f: linear, or the Catmull-Rom cubic
    through samples i-1 .. i+2 (end samples repeated at the ends of the record)."""
    p1 = v[i, j]
    p2 = v[i + 1, j]
    if not cubic:
        return p1 + f * (p2 - p1)
    p0 = v[i - 1, j] if i > 0 else p1
    p3 = v[i + 2, j] if i + 2 < n else p2
    return p1 + 0.5 * f * ((p2 - p0) + f * ((2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3)
                                            + f * (3.0 * (p1 - p2) + p3 - p0)))


@njit(**JIT_NO_ALLOC)
def gust_at(t, t0, dt, values, t_on, t_off, cubic=False):
    """Gust velocity at time t from a sampled record (numba; the inner-loop lookup).

    Parameters
    ----------
    t : float
        Time [s].
    t0, dt : float
        Time of the first sample and sample interval of the record [s].
    values : numpy.ndarray
        (N, 3) gust velocities [m/s] along S_p x, y, z (``GustRecord.values``).
    t_on, t_off : float
        Window [s]: zero unless ``t_on <= t < t_off``.
    cubic : bool
        False: linear interpolation between samples (continuous, with a kink at every sample);
        True: Catmull-Rom cubic (continuous slope: lets RK4 keep its order on steps longer than
        the sample interval). Both pass through every sample.

    Returns
    -------
    gu, gv, gw : float
        Gust velocity [m/s], interpolated between samples, clamped at the ends.
    """
    n = values.shape[0]
    if not (t >= t_on and t < t_off) or n == 0:
        return 0.0, 0.0, 0.0
    s = (t - t0) / dt
    if s <= 0.0:
        return values[0, 0], values[0, 1], values[0, 2]
    if s >= n - 1:
        return values[n - 1, 0], values[n - 1, 1], values[n - 1, 2]
    i = int(s)
    f = s - i
    return (
        _segment(values, i, n, 0, f, cubic),
        _segment(values, i, n, 1, f, cubic),
        _segment(values, i, n, 2, f, cubic),
    )


@njit(**JIT)
def _gust_series(ts, t0, dt, values, t_on, t_off, cubic, out):
    for k in range(ts.shape[0]):
        out[k, 0], out[k, 1], out[k, 2] = gust_at(ts[k], t0, dt, values, t_on, t_off, cubic)


def generate_gusts(
    turbulence: Turbulence,
    airspeed_m_s: float,
    duration_s: float | None = None,
    seed: int | None = None,
    run_duration_s: float | None = None,
) -> GustRecord:
    """Draw a stationary Dryden gust record by exact discretization of the forming filters.

    Parameters
    ----------
    turbulence : Turbulence
        Model, intensities ``sigma_m_s`` [m/s] and scale lengths ``scale_length_m`` [m] per axis
        [u, v, w], sample interval ``sample_time_s`` [s], window start ``start_s`` [s], seed.
    airspeed_m_s : float
        True airspeed V [m/s] that converts the frozen spatial field to time.
    duration_s : float, optional
        Length of the gust window [s]; default ``turbulence.duration_s``. The window is
        ``[start_s, start_s + duration_s)``.
    seed : int, optional
        Seed of the ``numpy.random.PCG64`` generator; default ``turbulence.seed``.
    run_duration_s : float, optional
        Length of the run [s]: an infinite window (the default ``turbulence.duration_s``: gusts
        for the whole run) is drawn to the run's end, plus a margin of twice the smoothing width
        and two samples, so that neither the smoothing nor the interpolation touches the run.

    Returns
    -------
    GustRecord
        Samples at ``start_s + k dt`` covering the window plus at least one sample past its end.
        The record is stationary from its first sample. The same seed gives bit-identical values.
        With ``turbulence.enabled`` false, a two-sample record of zeros (same window).

    Notes
    -----
    Random numbers are drawn in this fixed order: for u, then v, then w, first the stationary
    initial state (1 or 2 standard normals), then the (N - 1, n) noise array of that axis.
    """
    V = float(airspeed_m_s)
    if not (math.isfinite(V) and V > 0.0):
        raise ParameterError(f"airspeed_m_s = {airspeed_m_s!r}: must be a finite number > 0 m/s")
    duration = turbulence.duration_s if duration_s is None else float(duration_s)
    dt = turbulence.sample_time_s
    if not turbulence.enabled:
        return GustRecord(turbulence.start_s, dt, np.zeros((2, 3)), turbulence.start_s,
                          turbulence.start_s + duration, turbulence.interpolation)
    if math.isinf(duration) and run_duration_s is not None:
        margin = 2.0 * turbulence.smoothing_s + 2.0 * dt
        duration = max(float(run_duration_s) - turbulence.start_s, 0.0) + margin
    if not (math.isfinite(duration) and duration >= 0.0):
        raise ParameterError(f"turbulence.duration_s = {duration!r}: a gust window to the end of the run needs "
                             "the run's length (run_duration_s), else a finite number >= 0 s")
    if duration / dt > Turbulence.MAX_SAMPLES:
        raise ParameterError(f"turbulence.duration_s = {duration!r}: with sample_time_s = {dt!r} the gust record "
                             f"would exceed {Turbulence.MAX_SAMPLES:.0e} samples; shorten it or sample coarser")
    t_on = turbulence.start_s
    t_off = t_on + duration

    nsamp = int(math.ceil(duration / dt)) + 2
    rng = np.random.Generator(np.random.PCG64(turbulence.seed if seed is None else seed))
    values = np.empty((nsamp, 3))
    column = np.empty(nsamp)
    for j, axis in enumerate(AXES):
        Phi, lq, c0 = _discrete_axis(turbulence.model, axis, float(turbulence.sigma_m_s[j]),
                                     float(turbulence.scale_length_m[j]), V, float(dt))
        n = Phi.shape[0]
        x0 = rng.standard_normal(n)  # stationary covariance of this realization is I
        noise = rng.standard_normal((nsamp - 1, n))
        _run_filter(Phi, lq, c0, x0, noise, column)
        values[:, j] = column
    if turbulence.smoothing_s > 0.0:
        return smoothed_record(GustRecord(t_on, dt, values, t_on, t_off, turbulence.interpolation),
                               turbulence.smoothing_s)
    return GustRecord(t_on, dt, values, t_on, t_off, turbulence.interpolation)


@functools.lru_cache(maxsize=64)
def _discrete_axis(model: str, axis: str, sigma: float, scale: float, V: float, dt: float):
    """One axis's discretized forming filter (Phi, noise factor, output row; C-contiguous, not to
    be modified), kept per process: it does not depend on the seed, so a run of another seed (a
    campaign, a stepper's reset) draws its gusts without taking the matrix exponentials again."""
    A, B, C = forming_filter(model, axis, sigma, scale, V)
    Phi, Qd = discretize_filter(A, B, dt)
    return tuple(np.ascontiguousarray(x, dtype=np.float64) for x in (Phi, _noise_factor(Qd), C[0]))


def smoothed_record(record: GustRecord, width_s: float) -> GustRecord:
    """The windowed gust ``g(t) 1[t_on <= t < t_off]`` averaged by a symmetric triangular kernel
    (a box of ``width_s`` applied twice), as a record that is zero at both of its ends.

    The window's edges become ramps centred on ``t_on`` and ``t_off`` (the edge samples are
    halved, so the linear reading of the windowed samples already ramps symmetrically about each
    edge): a symmetric average keeps the forcing's impulse about every instant, so the response
    changes only at second order in ``width_s`` (docs/convergence.md gives the numbers). The
    returned record's window is its whole support.

    Parameters
    ----------
    record : GustRecord
        The sampled gusts and their window.
    width_s : float
        Width of the box applied twice [s] (rounded to whole samples, at least one).

    Returns
    -------
    GustRecord
    """
    dt = record.dt_s
    m = max(1, int(round(width_s / dt)))
    box = np.full(m, 1.0 / m)
    kernel = np.convolve(box, box)  # symmetric, sums to 1, length 2m - 1
    half = kernel.size // 2
    v = record.values.copy()
    k_on = int(round((record.t_on_s - record.t0_s) / dt))
    k_off = int(round((record.t_off_s - record.t0_s) / dt))
    v[:max(k_on, 0)] = 0.0
    if 0 <= k_on < v.shape[0]:
        v[k_on] *= 0.5
    if 0 <= k_off < v.shape[0]:
        v[k_off] *= 0.5
    v[k_off + 1:] = 0.0
    pad = half + 2
    padded = np.zeros((v.shape[0] + 2 * pad, 3))
    padded[pad:pad + v.shape[0]] = v
    out = np.empty_like(padded)
    for j in range(3):
        out[:, j] = np.convolve(padded[:, j], kernel, mode="same")
    t0 = record.t0_s - pad * dt
    t_end = t0 + (out.shape[0] - 1) * dt
    return GustRecord(t0, dt, out, t0, t_end, record.interpolation)

