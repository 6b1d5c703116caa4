"""The unity-feedback PID loop around a SISO channel model, as polynomials: exact unit-step responses
in modal form, for one design and for a population of designs at once (the tuner's evaluations,
:mod:`.pid_tuning`).

Loop: ``C(s) = K_P + K_I/s + K_D N s/(s + N)`` on the error r - y, plant ``G(s) = num_G / den_G``
(strictly proper, force [N] -> offset [m]). Its reference-to-output transfer function is
``T = num_G c(s) / (s (s + N) den_G + num_G c(s))`` with ``c(s) = (K_P + K_D N) s^2 + (K_P N + K_I) s
+ K_I N``; T is strictly proper and T(0) = 1 (integral action), so the unit step is

    y(t) = 1 + sum_i r_i exp(p_i t),    r_i = num_T(p_i) / (p_i den_T'(p_i)),

over the closed-loop poles p_i (simple poles; a repeated pole is non-generic and only perturbs
the residues' rounding). The figures of merit are Table 3's (:mod:`.stepinfo`): 10-90 % rise time
and 2 % settling time (from the step instant) and overshoot [% of the step].
"""

from __future__ import annotations

import math

import numpy as np
import control
from scipy.optimize import brentq

from ..analysis.reduction import require_siso
from .stepinfo import StepMetrics

__all__ = ["plant_polynomials", "loop_polynomials", "population_step_figures", "ModalStep", "SETTLING_BAND"]

#: Half-width of the settling band as a fraction of the step [-] (Table 3's 2 %).
SETTLING_BAND = 0.02


def plant_polynomials(plant_siso) -> tuple[np.ndarray, np.ndarray]:
    """Numerator and monic denominator of a strictly proper SISO plant (descending powers of s).

    Parameters
    ----------
    plant_siso : control.TransferFunction or control.StateSpace
        G(s), force [N] -> offset [m].

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        ``num_G`` [m/N s^k] and ``den_G`` (leading coefficient 1).

    Raises
    ------
    ValueError
        If the plant is not SISO, not finite, not strictly proper, or has a zero at s = 0
        (integral action could not give a unit final value).
    """
    require_siso("plant_siso", plant_siso)
    tf = control.tf(plant_siso)
    num = np.trim_zeros(np.atleast_1d(np.squeeze(np.asarray(tf.num[0][0], dtype=float))), "f")
    den = np.atleast_1d(np.squeeze(np.asarray(tf.den[0][0], dtype=float)))
    if num.size == 0 or not np.all(np.isfinite(num)) or not np.all(np.isfinite(den)):
        raise ValueError("plant_siso must have a finite, nonzero transfer function")
    if num.size >= den.size:
        raise ValueError(f"plant_siso must be strictly proper, got numerator degree {num.size - 1} "
                         f"and denominator degree {den.size - 1}")
    if num[-1] == 0.0:
        raise ValueError("plant_siso has a zero at s = 0: integral action cannot give a unit final value")
    return num / den[0], den / den[0]


def loop_polynomials(num_g, den_g, gains) -> tuple[np.ndarray, np.ndarray]:
    """Closed-loop numerator and denominator of T(s) for one or many PIDs.

    Parameters
    ----------
    num_g, den_g : numpy.ndarray
        The plant's polynomials (:func:`plant_polynomials`).
    gains : array_like, shape (4,) or (4, S)
        K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s] (columns: designs).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        Coefficients, shape (n + 3,) or (S, n + 3), descending powers, n = the plant's order; the
        numerator's leading entries are 0 (T is strictly proper).
    """
    kp, ki, kd, n = np.asarray(gains, dtype=float)
    cn = np.stack([kp + kd * n, kp * n + ki, ki * n], axis=-1)
    cd = np.stack([np.ones_like(n), n, np.zeros_like(n)], axis=-1)
    size = den_g.size + 2
    num = np.zeros(cn.shape[:-1] + (size,))
    den = np.zeros(cn.shape[:-1] + (size,))
    g_num = np.concatenate([np.zeros(den_g.size - num_g.size), num_g])
    for i in range(3):
        for j in range(den_g.size):
            num[..., i + j] += cn[..., i] * g_num[j]
            den[..., i + j] += cd[..., i] * den_g[j]
    return num, den + num


def _roots(den: np.ndarray) -> np.ndarray:
    """Roots of each row of ``den`` (leading coefficient nonzero): the companion matrices' eigenvalues."""
    k = den.shape[-1] - 1
    comp = np.zeros(den.shape[:-1] + (k, k))
    comp[..., 0, :] = -den[..., 1:] / den[..., :1]
    comp[..., np.arange(1, k), np.arange(k - 1)] = 1.0
    return np.linalg.eigvals(comp)


def _residues(num: np.ndarray, den: np.ndarray, poles: np.ndarray) -> np.ndarray:
    """Residues of num / (s den) at the simple poles ``poles`` (the modal weights of the step)."""
    dden = den[..., :-1] * np.arange(den.shape[-1] - 1, 0, -1)

    def horner(c, x):
        out = np.zeros_like(x)
        for i in range(c.shape[-1]):
            out = out * x + c[..., i : i + 1]
        return out

    return horner(num.astype(complex), poles) / (poles * horner(dden.astype(complex), poles))


def population_step_figures(num_g, den_g, gains, t) -> dict[str, np.ndarray]:
    """Step figures of S designs on one shared time grid, crossings interpolated linearly.

    Parameters
    ----------
    num_g, den_g : numpy.ndarray
        The plant's polynomials (:func:`plant_polynomials`).
    gains : array_like, shape (4, S)
        One design per column: K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s].
    t : numpy.ndarray
        Common sample times [s] from 0, increasing; its step limits the figures' accuracy.

    Returns
    -------
    dict
        ``rise_time_s``, ``settling_time_s`` (NaN where the step does not rise or does not settle
        within ``t``), ``overshoot_pct`` [%], ``min_damping`` (smallest damping ratio of the
        closed-loop poles [-]) and ``stable`` (bool), each of shape (S,).
    """
    num, den = loop_polynomials(num_g, den_g, gains)
    p = _roots(den)
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        r = _residues(num, den, p)
        y = 1.0 + np.real(np.einsum("si,sit->st", r, np.exp(p[..., None] * t)))
        rise = _first_crossing(t, y, 0.9) - _first_crossing(t, y, 0.1)
        settle = _settling(t, y)
        over = 100.0 * np.maximum(0.0, y.max(axis=1) - 1.0)
    return {"rise_time_s": rise, "settling_time_s": settle, "overshoot_pct": over,
            "min_damping": np.min(-p.real / np.abs(p), axis=1), "stable": np.all(p.real < 0.0, axis=1)}


def _first_crossing(t, y, level):
    above = y >= level
    i = np.argmax(above, axis=1)
    rows = np.arange(y.shape[0])
    hit = above[rows, i] & (i > 0)
    i = np.maximum(i, 1)
    y0, y1 = y[rows, i - 1], y[rows, i]
    tc = t[i - 1] + (level - y0) / (y1 - y0) * (t[i] - t[i - 1])
    return np.where(hit, tc, np.nan)


def _settling(t, y):
    out = np.abs(y - 1.0) > SETTLING_BAND
    last = y.shape[1] - 1 - np.argmax(out[:, ::-1], axis=1)
    rows = np.arange(y.shape[0])
    j = np.minimum(last, y.shape[1] - 2)
    y0, y1 = y[rows, j], y[rows, j + 1]
    edge = 1.0 + SETTLING_BAND * np.sign(y0 - 1.0)
    ts = t[j] + (edge - y0) / (y1 - y0) * (t[j + 1] - t[j])
    ts = np.where(last == y.shape[1] - 1, np.nan, ts)
    return np.where(out.any(axis=1), ts, 0.0)


class ModalStep:
    """The exact unit-step response of one PID loop, y(t) = 1 + sum_i r_i exp(p_i t).

    Parameters
    ----------
    num_g, den_g : numpy.ndarray
        The plant's polynomials (:func:`plant_polynomials`).
    gains : array_like, shape (4,)
        K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s].

    Attributes
    ----------
    poles : numpy.ndarray
        Closed-loop poles [rad/s].
    stable : bool
        All poles in the open left half plane (the other attributes and methods need it).
    """

    def __init__(self, num_g, den_g, gains):
        num, den = loop_polynomials(num_g, den_g, np.asarray(gains, dtype=float)[:, None])
        self.poles = np.roots(den[0])
        self.stable = bool(np.all(self.poles.real < 0.0))
        if self.stable:
            self._res = _residues(num[0], den[0], self.poles)
            self._final = num[0, -1] / den[0, -1]

    def y(self, t):
        """Offset [m] per metre of reference step at times ``t`` [s]."""
        return self._final + self._modal_sum(t, self._res)

    def dy(self, t):
        """Its rate [1/s] at times ``t`` [s]."""
        return self._modal_sum(t, self._res * self.poles)

    def _modal_sum(self, t, weights):
        """sum_i Re(w_i exp(p_i t)), summed in the poles' order by numpy's own loop: not by a BLAS
        product, whose kernels and threads could order the additions otherwise in another process."""
        return np.sum(np.real(np.exp(np.multiply.outer(t, self.poles)) * weights), axis=-1)

    def grid(self) -> np.ndarray:
        """Times [s] following every mode over 12 of its time constants (exp(-12) = 6e-6 of its
        amplitude left) with a step of 0.2 / |p| (31 samples a period): fine enough to bracket
        every crossing and extremum, which :meth:`metrics` then locates by root finding."""
        pieces = []
        for p in self.poles:
            span = 12.0 / abs(p.real)
            pieces.append(np.linspace(0.0, span, int(min(20_000, math.ceil(span * abs(p) / 0.2))) + 1))
        return np.unique(np.concatenate(pieces))

    def min_damping(self) -> float:
        """Smallest damping ratio -Re p / |p| of the closed-loop poles [-] (1 for real poles,
        negative for an unstable loop)."""
        return float(np.min(-self.poles.real / np.abs(self.poles)))

    def extrema(self, t) -> np.ndarray:
        """Instants [s] of every extremum of the response inside ``t``: each sign change of the
        rate between two samples, located by root finding (a pair of extrema closer than one step
        of :meth:`grid` would be missed; the grid follows every mode at 31 samples a period)."""
        d = self.dy(t)
        k = np.nonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0.0)[0]
        return np.array([brentq(lambda tt: float(self.dy(tt)), t[i], t[i + 1], xtol=1e-15, rtol=1e-14) for i in k])

    def metrics(self) -> StepMetrics:
        """Table 3's figures, each instant (crossings, band entry, peak) found by root finding.

        The samples of :meth:`grid` and every extremum between them (:meth:`extrema`) are the
        points read: between two of them the response is monotone, so the last one outside the
        2 % band is the last excursion (an extremum that pokes out of the band between two samples
        counts), and each crossing lies between two neighbours.

        Returns
        -------
        StepMetrics
            Rise and settling time [s] (NaN if not reached within :meth:`grid`), overshoot [%],
            final value 1; all NaN for an unstable loop.
        """
        if not self.stable:
            nan = float("nan")
            return StepMetrics(rise_time_s=nan, settling_time_s=nan, overshoot_pct=nan, final_value=nan)
        t = self.grid()
        t = np.unique(np.concatenate([t, self.extrema(t)]))
        s = self.y(t) / self._final

        def level(value):
            return lambda tt: float(self.y(tt)) / self._final - value

        def cross(value):
            i = int(np.argmax(s >= value))
            if s[i] < value:
                return float("nan")
            return float(t[0]) if i == 0 else brentq(level(value), t[i - 1], t[i], xtol=1e-15, rtol=1e-14)

        rise = cross(0.9) - cross(0.1)
        outside = np.nonzero(np.abs(s - 1.0) > SETTLING_BAND)[0]
        if outside.size == 0:
            settle = 0.0
        elif outside[-1] == s.size - 1:
            settle = float("nan")
        else:
            j = outside[-1]
            edge = 1.0 + SETTLING_BAND * np.sign(s[j] - 1.0)
            settle = brentq(level(edge), t[j], t[j + 1], xtol=1e-15, rtol=1e-14)
        return StepMetrics(rise_time_s=float(rise), settling_time_s=float(settle),
                           overshoot_pct=100.0 * max(0.0, float(np.max(s)) - 1.0), final_value=float(self._final))
