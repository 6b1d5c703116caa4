"""Dryden spectra, forming filters and their exact discretization (the gust record drawn from
them is :mod:`hosedrogue.environment.turbulence`).

Spectra
-------
For an aircraft flying at true airspeed V through a frozen turbulence field, the temporal
frequency is ``omega = V Omega`` [rad/s]. With ``x = L omega / V`` the one-sided power spectral
densities, normalised so that ``integral_0^inf Phi(omega) d omega = sigma^2``, are

* MIL-F-8785C (default):
  ``Phi_u = sigma^2 (2 L / (pi V)) / (1 + x^2)``,
  ``Phi_v = Phi_w = sigma^2 (L / (pi V)) (1 + 3 x^2) / (1 + x^2)^2``;
* MIL-HDBK-1797 (option): ``Phi_u`` as above and
  ``Phi_v = Phi_w = sigma^2 (2 L / (pi V)) (1 + 12 x^2) / (1 + 4 x^2)^2``
  (the handbook's form with the lateral/vertical scale length written as 2L).

Forming filters
---------------
Each axis is the output of a linear filter ``dx = A x dt + B dW``, ``g = C x`` driven by
unit-intensity white noise (``E[dW dW] = dt``). Its two-sided output spectrum is ``|H(i omega)|^2``
with ``H(s) = C (sI - A)^-1 B``, so the one-sided spectrum in the convention above is
``|H(i omega)|^2 / pi``. The transfer functions are therefore sqrt(pi) times the usual
"spectral square roots"::

    u (both):        H(s) = sigma sqrt(2 T)      / (1 + T s),                     T = L / V
    v, w (8785C):    H(s) = sigma sqrt(T)   (1 + sqrt(3) T s)   / (1 + T s)^2
    v, w (1797):     H(s) = sigma sqrt(2 T) (1 + 2 sqrt(3) T s) / (1 + 2 T s)^2

The realizations are scaled so that the stationary state covariance is the identity matrix (checked
by a Lyapunov solve in the tests); the stationary output variance is then ``C C^T = sigma^2``
exactly, and a stationary initial state is a vector of standard normal numbers.

Exact discretization
--------------------
At a sample interval dt the state obeys ``x[k+1] = Phi x[k] + w[k]`` with ``Phi = expm(A dt)`` and
``w[k] ~ N(0, Qd)``, ``Qd = integral_0^dt expm(A s) B B^T expm(A^T s) ds`` (Van Loan's method).
Started from the stationary distribution, the sampled record has exactly the autocovariance of the
continuous process at the sample times, for any dt: the gust statistics do not depend on the
sample interval or on the integration step.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg

from ..spec.params import ParameterError

__all__ = ["AXES", "MODELS", "discretize_filter", "dryden_psd", "forming_filter"]

#: Filter families, as accepted by ``Turbulence.model``.
MODELS = ("mil-f-8785c", "mil-hdbk-1797")
#: Gust axes along S_p x, y, z.
AXES = ("u", "v", "w")

_SQRT3 = math.sqrt(3.0)


def _check_model(model: str) -> None:
    if model not in MODELS:
        allowed = ", ".join(repr(m) for m in MODELS)
        raise ParameterError(f"turbulence.model = {model!r}: must be one of {allowed}")


def _check_axis(axis: str) -> None:
    if axis not in AXES:
        raise ValueError(f"axis = {axis!r}: must be one of 'u', 'v', 'w'")


def _check_filter_args(sigma: float, L: float, V: float) -> None:
    if not (math.isfinite(sigma) and sigma >= 0.0):
        raise ValueError(f"sigma = {sigma!r}: must be a finite number >= 0 [m/s]")
    if not (math.isfinite(L) and L > 0.0):
        raise ValueError(f"L = {L!r}: the scale length must be a finite number > 0 [m]")
    if not (math.isfinite(V) and V > 0.0):
        raise ValueError(f"V = {V!r}: the airspeed must be a finite number > 0 [m/s]")


def dryden_psd(model: str, axis: str, omega, sigma: float, L: float, V: float) -> np.ndarray:
    """One-sided Dryden power spectral density in temporal frequency.

    Parameters
    ----------
    model : {"mil-f-8785c", "mil-hdbk-1797"}
        Spectrum family (see the module docstring).
    axis : {"u", "v", "w"}
        Gust component along S_p x, y or z.
    omega : array_like
        Temporal circular frequency [rad/s], >= 0.
    sigma : float
        Rms intensity of the component [m/s].
    L : float
        Scale length of the component [m].
    V : float
        True airspeed [m/s].

    Returns
    -------
    numpy.ndarray
        ``Phi(omega)`` [(m/s)^2 / (rad/s)], normalised so that its integral over
        ``omega in [0, inf)`` equals ``sigma^2``.
    """
    _check_model(model)
    _check_axis(axis)
    _check_filter_args(sigma, L, V)
    x2 = (L * np.asarray(omega, dtype=np.float64) / V) ** 2
    if axis == "u":
        return sigma**2 * (2.0 * L / (math.pi * V)) / (1.0 + x2)
    if model == "mil-f-8785c":
        return sigma**2 * (L / (math.pi * V)) * (1.0 + 3.0 * x2) / (1.0 + x2) ** 2
    return sigma**2 * (2.0 * L / (math.pi * V)) * (1.0 + 12.0 * x2) / (1.0 + 4.0 * x2) ** 2


def forming_filter(model: str, axis: str, sigma: float, L: float, V: float):
    """Continuous forming filter of one gust component, driven by unit-intensity white noise.

    Parameters
    ----------
    model : {"mil-f-8785c", "mil-hdbk-1797"}
        Spectrum family.
    axis : {"u", "v", "w"}
        Gust component along S_p x, y or z.
    sigma : float
        Rms intensity [m/s].
    L : float
        Scale length [m].
    V : float
        True airspeed [m/s].

    Returns
    -------
    A : numpy.ndarray
        State matrix [1/s], (n, n) with n = 1 (u) or 2 (v, w).
    B : numpy.ndarray
        Noise input matrix [1/sqrt(s)], (n, 1).
    C : numpy.ndarray
        Output matrix [m/s], (1, n).

    Notes
    -----
    ``dx = A x dt + B dW``, gust ``= C x``, with W a standard Wiener process. The state is scaled so
    that its stationary covariance is the identity, hence the stationary output variance is
    ``C C^T = sigma^2`` and ``|C (i omega I - A)^-1 B|^2 / pi = dryden_psd(...)``.
    """
    _check_model(model)
    _check_axis(axis)
    _check_filter_args(sigma, L, V)
    T = L / V
    if axis == "u":
        # H = sigma sqrt(2T) / (1 + T s); state variance B^2 T / 2 = 1
        A = np.array([[-1.0 / T]])
        B = np.array([[math.sqrt(2.0 / T)]])
        C = np.array([[sigma]])
        return A, B, C
    if model == "mil-f-8785c":
        gain, lead, tau = sigma * math.sqrt(T), _SQRT3 * T, T
    else:
        gain, lead, tau = sigma * math.sqrt(2.0 * T), 2.0 * _SQRT3 * T, 2.0 * T
    # H = gain (1 + lead s) / (1 + tau s)^2, realized as a critically damped oscillator whose
    # position and velocity are scaled to unit stationary variance (they are uncorrelated).
    A = np.array([[0.0, 1.0], [-1.0, -2.0]]) / tau
    B = np.array([[0.0], [2.0 / math.sqrt(tau)]])
    C = gain / (2.0 * math.sqrt(tau)) * np.array([[1.0, lead / tau]])
    return A, B, C


def discretize_filter(A: np.ndarray, B: np.ndarray, dt: float):
    """Exact discretization of the linear SDE ``dx = A x dt + B dW`` (Van Loan, 1978).

    Parameters
    ----------
    A : numpy.ndarray
        State matrix [1/s], (n, n).
    B : numpy.ndarray
        Noise input matrix [1/sqrt(s)], (n, m), unit-intensity white noise.
    dt : float
        Sample interval [s], > 0.

    Returns
    -------
    Phi : numpy.ndarray
        Transition matrix ``expm(A dt)``, (n, n).
    Qd : numpy.ndarray
        Covariance of the state increment over one interval,
        ``integral_0^dt expm(A s) B B^T expm(A^T s) ds``, (n, n), symmetric.

    Notes
    -----
    Van Loan's block matrix contains ``-A``, whose exponential grows like ``exp(|A| dt)``; when
    ``|A| dt`` is large (a sample interval of many filter time constants) its round-off would
    swamp ``Qd``. So the block exponential is taken over ``h = dt / 2^s`` with ``|A| h <= 1/2``,
    and ``Qd`` is doubled ``s`` times by ``Qd(2h) = Phi(h) Qd(h) Phi(h)^T + Qd(h)`` (a sum of
    positive semi-definite terms: no cancellation). ``Phi`` is ``expm(A dt)`` directly.
    """
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt = {dt!r}: the sample interval must be a finite number > 0 [s]")
    A = np.asarray(A, dtype=np.float64)
    B = np.asarray(B, dtype=np.float64)
    n = A.shape[0]
    a_dt = np.linalg.norm(A, 1) * dt
    halvings = max(0, math.ceil(math.log2(a_dt / 0.5))) if a_dt > 0.5 else 0
    h = dt / 2.0**halvings
    M = np.zeros((2 * n, 2 * n))
    M[:n, :n] = -A
    M[:n, n:] = B @ B.T
    M[n:, n:] = A.T
    E = scipy.linalg.expm(M * h)
    Phi_h = E[n:, n:].T
    Qd = Phi_h @ E[:n, n:]
    for _ in range(halvings):
        Qd = Phi_h @ Qd @ Phi_h.T + Qd
        Phi_h = Phi_h @ Phi_h
    Phi = scipy.linalg.expm(A * dt)
    return Phi, 0.5 * (Qd + Qd.T)
