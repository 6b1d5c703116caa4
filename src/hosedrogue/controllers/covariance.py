"""Disturbance rejection by covariance analysis: the drogue's RMS displacement and its spectrum in
Dryden turbulence, predicted from the linear model without simulating (docs/loop-analysis.md).

The model
---------
* The hose: the linearization about the balance position (:func:`hosedrogue.analysis.linearize.
  linearize`), ``x' = A x + B u + B_g g``, ``y = C x`` with the drogue's offset y = [P_ny, P_nz] [m].
  ``B_g`` (4n x 3) is the Jacobian of the same compiled right-hand side with respect to a gust
  g = [u, v, w] [m/s] that every point of the hose and the drogue sees at once: the simulation's
  ``turbulence.distribution = "uniform"`` (the default), where the whole hose reads the tow point's
  gust (:func:`hosedrogue.model.chain_loads.fill_env`). The ``"frozen"`` field (each point the gust
  of -x/V later) is refused: its per-point delays are not in this model.
* The gusts: the Dryden forming filters of :mod:`hosedrogue.environment.dryden` (the very
  matrices the simulation's gust record is drawn through), driven by unit-intensity white noise,
  one filter per axis with the configured model, intensities and scale lengths.
* The controller (optional): a :class:`~hosedrogue.controllers.linear.LinearController`,
  continuous, or sampled as the simulation runs it: its zero-order-hold discretization
  (:func:`hosedrogue.controllers.discrete.discretize`) called every T, reading the offset of
  ``delay_s`` = d T before, its command held over the interval. The plant and the gust filters
  are then discretized exactly at T (the state transition, the held input's integral, and the
  noise's covariance by Van Loan's method, :func:`hosedrogue.environment.dryden.discretize_filter`).

The covariance
--------------
Continuous: the stationary state covariance P solves ``A P + P A^T + B_n B_n^T = 0``; sampled:
``P = F P F^T + Q_d`` (scipy.linalg's Lyapunov solvers). The output variance is ``C P C^T``; the
sampled loop's is the variance at the sampling instants (between them the held force changes the
hose's state by ``O((omega T)^2)`` relative at the loop's frequencies omega: 1e-3 at 3 rad/s and
T = 0.01 s).

The spectrum is one-sided, per hertz (``scipy.signal.welch``'s convention: its integral over
[0, f_max] is the variance): ``2 sum_j |H_j(i 2 pi f)|^2`` continuous, ``2 T H G Q_d G^H H^T``
with ``G = (exp(i 2 pi f T) I - F)^-1`` sampled (up to the Nyquist frequency 1/(2T)).

What is left out: the actuator's limits and lag (a linear loop), sensor noise, the smoothing of
the gust record (``turbulence.smoothing_s``: a low-pass at about 1/width, far above the hose's
modes for the widths the scenarios use) and its interpolation between samples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ..analysis.linearize import LinearModel, linearize
from ..environment.dryden import AXES, discretize_filter, forming_filter
from ..errors import ParameterError
from ..model import chain_dynamics as CD
from ..model import layout as LY
from ..model.system import HoseModel
from ..spec.params import Params
from ..spec.standards import standard_intensity
from .discrete import discretize
from .linear import LinearController

__all__ = ["GUST_FD_STEP_M_S", "DisturbanceModel", "Prediction", "disturbance_model", "gust_input_matrix",
           "predict", "with_standard_turbulence"]

#: Central-difference step of the gust Jacobian [m/s]: the drag is smooth in the gust (a quadratic
#: of the relative velocity over V ~ 1e2 m/s), so the truncation error is ~(1e-4 / 1e2)^2 relative
#: and the round-off ~1e-16 / 1e-4 = 1e-12 relative of the derivative.
GUST_FD_STEP_M_S = 1e-4

#: Number of points of the predicted spectrum's frequency grid [-] (logarithmic).
PSD_POINTS = 400
#: Lowest frequency of the predicted spectrum [Hz]: below the Dryden corner V / (2 pi L) of any
#: shipped case (0.045 Hz at 150 m/s and 530 m).
PSD_F_MIN_HZ = 1e-3
#: Highest frequency of the continuous prediction's spectrum [Hz] (the sampled one stops at its
#: Nyquist frequency): above it the drogue's displacement spectrum is below 1e-9 of its peak.
PSD_F_MAX_HZ = 20.0


def with_standard_turbulence(params: Params, level: str) -> Params:
    """``params`` with the standard isotropic intensity of ``level`` at its altitude switched on
    (MIL-F-8785C Fig. 7, :func:`hosedrogue.spec.standards.standard_intensity`).

    Parameters
    ----------
    params : Params
        The model and flight condition.
    level : {"light", "moderate", "severe"}
        The intensity's probability of exceedance 1e-2, 1e-3 or 1e-5.

    Returns
    -------
    Params
    """
    sigma = standard_intensity(level, params.flight.altitude_m)
    return params.replace(turbulence={"enabled": True, "sigma_m_s": sigma})


def gust_input_matrix(model: HoseModel, lm: LinearModel) -> np.ndarray:
    """``B_g`` (4n, 3): the derivative of the state's rate with respect to a uniform gust [u, v, w]
    [m/s] at the balance position (central differences of the compiled right-hand side, step
    :data:`GUST_FD_STEP_M_S`).

    Parameters
    ----------
    model : HoseModel
        The model ``lm`` was linearized from.
    lm : LinearModel
        The linearization (its balance position).

    Returns
    -------
    numpy.ndarray
        Columns per gust axis along S_p x, y, z [1/(m s) and 1/(m s^2) per m/s].
    """
    env = model.steady_env.copy()
    # a gust record that holds the same gust at every time: the window open at all times
    env[LY.ENV_FROZEN] = 0.0
    env[LY.ENV_T_ON] = -1e300
    env[LY.ENV_T_OFF] = 1e300
    env[LY.ENV_G_T0] = 0.0
    env[LY.ENV_G_DT] = 1.0
    env[LY.ENV_G_CUBIC] = 0.0
    l, M, S, J, ps, _, _ = model.kernel_args(steady=True)
    x0 = lm.equilibrium.state
    u0 = np.zeros(2)
    Bg = np.empty((x0.size, 3))
    for j in range(3):
        rates = []
        for sign in (1.0, -1.0):
            gust = np.zeros((2, 3))
            gust[:, j] = sign * GUST_FD_STEP_M_S
            dx = np.empty_like(x0)
            CD.rhs(0.0, x0, u0, l, M, S, J, ps, env, gust, dx)
            rates.append(dx)
        Bg[:, j] = (rates[0] - rates[1]) / (2.0 * GUST_FD_STEP_M_S)
    return Bg


@dataclass(frozen=True)
class DisturbanceModel:
    """The hose driven by the gust filters: ``s' = A s + B u + B_n w``, ``y = C s``, with the state
    s = [hose state (4n), gust filter states (5)], u = [u_hor, u_ver] [N], w three independent
    unit-intensity white noises and y = [P_ny, P_nz] [m]."""

    A: np.ndarray  #: (ns, ns) [1/s]
    B: np.ndarray  #: (ns, 2) force input
    Bn: np.ndarray  #: (ns, 3) noise input [1/sqrt(s)]
    C: np.ndarray  #: (2, ns) [m per state unit]
    params: Params  #: the model, flight condition and turbulence

    @property
    def gust_states(self) -> int:
        """Number of the gust filters' states (5: u 1, v 2, w 2)."""
        return self.A.shape[0] - self.params.hose.links * 4


def disturbance_model(params: Params, lm: LinearModel | None = None, model: HoseModel | None = None) -> DisturbanceModel:
    """The linear hose driven by the Dryden forming filters of ``params.turbulence``.

    Parameters
    ----------
    params : Params
        Model, flight condition and turbulence (its model, intensities and scale lengths; the
        gusts are used whether or not ``turbulence.enabled``).
    lm : LinearModel, optional
        The linearization of ``params`` (computed if missing).
    model : HoseModel, optional
        The model of ``params`` (built if missing).

    Returns
    -------
    DisturbanceModel
    """
    turb = params.turbulence
    if turb.distribution != "uniform":
        raise ParameterError(f"turbulence.distribution = {turb.distribution!r}: the covariance analysis models the "
                             "gust every point of the hose sees at once ('uniform'); simulate a 'frozen' field")
    model = model if model is not None else HoseModel(params)
    lm = lm if lm is not None else linearize(params, model=model)
    V = params.flight.airspeed_m_s
    filters = [forming_filter(turb.model, axis, float(turb.sigma_m_s[j]), float(turb.scale_length_m[j]), V)
               for j, axis in enumerate(AXES)]
    Af = scipy.linalg.block_diag(*(f[0] for f in filters))
    Bf = scipy.linalg.block_diag(*(f[1] for f in filters))
    Cf = scipy.linalg.block_diag(*(f[2] for f in filters))
    nx, nf = lm.A.shape[0], Af.shape[0]
    A = np.zeros((nx + nf, nx + nf))
    A[:nx, :nx] = lm.A
    A[:nx, nx:] = gust_input_matrix(model, lm) @ Cf
    A[nx:, nx:] = Af
    B = np.vstack([lm.B, np.zeros((nf, 2))])
    Bn = np.vstack([np.zeros((nx, 3)), Bf])
    C = np.hstack([lm.C, np.zeros((2, nf))])
    return DisturbanceModel(A, B, Bn, C, params)


@dataclass(frozen=True)
class Prediction:
    """The predicted stationary response of the drogue in turbulence."""

    rms_m: np.ndarray  #: (2,) RMS lateral, vertical offset [m]
    frequency_hz: np.ndarray  #: (F,) frequencies of the spectrum [Hz]
    psd_m2_hz: np.ndarray  #: (2, F) one-sided PSD of the lateral, vertical offset [m^2/Hz]
    closed_loop: bool  #: a controller was in the loop
    sample_time_s: float  #: the controller's sample time [s] (0: continuous)
    delay_s: float  #: the sensor's delay [s]
    poles: np.ndarray  #: the loop's poles (continuous [rad/s]) or eigenvalues (sampled [-])
    #: (2,) integral over all lags of the squared autocovariance of each offset [m^4 s]
    autocovariance_square_integral: np.ndarray

    def as_dict(self) -> dict:
        """``{"lateral": m, "vertical": m}`` of the RMS [m]."""
        return {"lateral": float(self.rms_m[0]), "vertical": float(self.rms_m[1])}

    def rms_standard_error(self, duration_s: float, runs: int = 1) -> np.ndarray:
        """Standard deviation [m] of the mean over ``runs`` independent runs of the RMS offset
        measured over ``duration_s`` each (lateral, vertical): for a stationary Gaussian offset of
        autocovariance R, the mean square over a window of length T_w has variance
        ``(2 / T_w) integral R(tau)^2 d tau`` (for T_w much longer than the correlation time), and
        the RMS's deviation is the mean square's over ``2 RMS``.

        Parameters
        ----------
        duration_s : float
            Length of each run's statistics window [s], > 0.
        runs : int
            Number of independent runs averaged [-], >= 1.

        Returns
        -------
        numpy.ndarray (2,)
        """
        var_ms = 2.0 * self.autocovariance_square_integral / float(duration_s)
        return np.sqrt(var_ms) / (2.0 * self.rms_m) / math.sqrt(runs)


def _continuous_loop(dm: DisturbanceModel, ctrl: LinearController | None):
    """(A, B_n, C) of the continuous closed loop [s, xc] (u = Cc xc + Dc y; xc' = Ac xc + Bc y)."""
    if ctrl is None:
        return dm.A, dm.Bn, dm.C
    ns, nc = dm.A.shape[0], ctrl.n_states
    A = np.zeros((ns + nc, ns + nc))
    A[:ns, :ns] = dm.A + dm.B @ ctrl.D @ dm.C
    A[:ns, ns:] = dm.B @ ctrl.C
    A[ns:, :ns] = ctrl.B @ dm.C
    A[ns:, ns:] = ctrl.A
    return A, np.vstack([dm.Bn, np.zeros((nc, 3))]), np.hstack([dm.C, np.zeros((2, nc))])


def delay_samples(delay_s: float, sample_time_s: float) -> int:
    """The sensor delay as a whole number of samples (the simulation's rule: a whole multiple).

    Parameters
    ----------
    delay_s : float
        Sensor delay [s], >= 0.
    sample_time_s : float
        Controller sample time [s], > 0.

    Returns
    -------
    int
    """
    d = delay_s / sample_time_s
    if not (math.isfinite(d) and d >= 0.0 and abs(d - round(d)) <= 1e-9 * max(1.0, d)):
        raise ParameterError(f"sensor.delay_s = {delay_s!r}: must be a whole multiple >= 0 of the controller's "
                             f"sample time {sample_time_s!r} s")
    return int(round(d))


def sampled_loop(dm: DisturbanceModel, ctrl: LinearController | None, sample_time_s: float, delay_s: float = 0.0):
    """(F, Q_d, H) of the sampled loop: ``z[k+1] = F z[k] + w[k]``, ``cov(w) = Q_d``, ``y[k] = H z[k]``,
    with z = [s (plant and gust filters), xd (controller), y[k-1] .. y[k-d] (the delay line)].

    Parameters
    ----------
    dm : DisturbanceModel
        The hose and the gust filters.
    ctrl : LinearController or None
        The continuous design (None: open loop).
    sample_time_s : float
        T [s], > 0.
    delay_s : float
        Sensor delay [s], a whole multiple of T.

    Returns
    -------
    F, Qd, H : numpy.ndarray
    """
    import control

    T = float(sample_time_s)
    ctrl = ctrl if ctrl is not None else LinearController.static_zero()
    d = delay_samples(delay_s, T)
    Fs, Qs = discretize_filter(dm.A, dm.Bn, T)
    Gs = control.c2d(control.ss(dm.A, dm.B, dm.C, np.zeros((2, 2))), T, method="zoh").B
    Ad, Bd, Cd, Dd = discretize(ctrl, T)
    ns, nc = dm.A.shape[0], ctrl.n_states
    nz = ns + nc + 2 * d
    Hs = np.zeros((2, nz))
    Hs[:, :ns] = dm.C
    # the measurement the controller reads: y[k] itself, or the delay line's last entry
    Sel = Hs.copy() if d == 0 else np.zeros((2, nz))
    if d:
        Sel[:, nz - 2:] = np.eye(2)
    F = np.zeros((nz, nz))
    F[:ns, :ns] = Fs
    F[:ns, ns:ns + nc] = Gs @ Cd
    F[:ns] += Gs @ Dd @ Sel
    F[ns:ns + nc, ns:ns + nc] = Ad
    F[ns:ns + nc] += Bd @ Sel
    if d:
        F[ns + nc:ns + nc + 2, :ns] = dm.C
        for i in range(1, d):
            r = ns + nc + 2 * i
            F[r:r + 2, r - 2:r] = np.eye(2)
    Qd = np.zeros((nz, nz))
    Qd[:ns, :ns] = Qs
    return F, Qd, Hs


def _stable(poles: np.ndarray, sampled: bool) -> bool:
    return bool(np.all(np.abs(poles) < 1.0)) if sampled else bool(np.all(poles.real < 0.0))


def _psd_continuous(A, Bn, C, f):
    out = np.empty((2, f.size))
    eye = np.eye(A.shape[0])
    for i, fk in enumerate(f):
        H = C @ np.linalg.solve(2j * math.pi * fk * eye - A, Bn)
        out[:, i] = 2.0 * np.sum(np.abs(H) ** 2, axis=1)
    return out


def _psd_sampled(F, Qd, H, T, f):
    w, U = np.linalg.eigh(Qd)
    Lq = U[:, w > 0.0] * np.sqrt(w[w > 0.0])  # Qd = Lq Lq^T
    out = np.empty((2, f.size))
    eye = np.eye(F.shape[0])
    for i, fk in enumerate(f):
        G = H @ np.linalg.solve(np.exp(2j * math.pi * fk * T) * eye - F, Lq)
        out[:, i] = 2.0 * T * np.sum(np.abs(G) ** 2, axis=1)
    return out


def predict(params: Params, controller: LinearController | None = None, sample_time_s: float = 0.0,
            delay_s: float = 0.0, dm: DisturbanceModel | None = None, frequency_hz=None) -> Prediction:
    """The drogue's stationary RMS offset and its spectrum in the turbulence of ``params``.

    Parameters
    ----------
    params : Params
        Model, flight condition and turbulence (:func:`with_standard_turbulence` sets a standard
        intensity).
    controller : LinearController, optional
        The drogue controller (None: open loop).
    sample_time_s : float
        The controller's sample time [s]; 0: continuous.
    delay_s : float
        The sensor's delay [s] (sampled controllers only, as in the simulation), a whole multiple
        of the sample time.
    dm : DisturbanceModel, optional
        :func:`disturbance_model` of ``params`` (built if missing).
    frequency_hz : array_like, optional
        Frequencies of the spectrum [Hz] (default a logarithmic grid of :data:`PSD_POINTS` from
        :data:`PSD_F_MIN_HZ` to :data:`PSD_F_MAX_HZ` or the Nyquist frequency).

    Returns
    -------
    Prediction

    Raises
    ------
    ParameterError
        When the loop is unstable (no stationary response), or a delay without a sampled controller.
    """
    dm = dm if dm is not None else disturbance_model(params)
    sampled = sample_time_s > 0.0
    if delay_s and not sampled:
        raise ParameterError(f"sensor.delay_s = {delay_s!r}: the delay acts on sampled controllers only; give the "
                             "controller's sample time")
    if sampled:
        F, Qd, H = sampled_loop(dm, controller, sample_time_s, delay_s)
        poles = np.linalg.eigvals(F)
    else:
        A, Bn, H = _continuous_loop(dm, controller)
        poles = np.linalg.eigvals(A)
    if not _stable(poles, sampled):
        worst = poles[np.argmax(np.abs(poles) if sampled else poles.real)]
        raise ParameterError(f"controller: the {'sampled ' if sampled else ''}closed loop is unstable (pole "
                             f"{worst:.4g}); no stationary response to predict")
    if sampled:
        P = scipy.linalg.solve_discrete_lyapunov(F, Qd)
    else:
        P = scipy.linalg.solve_continuous_lyapunov(A, -Bn @ Bn.T)
    var = np.diag(H @ P @ H.T)
    r2 = _autocovariance_square_integral(F if sampled else A, P, H, sample_time_s if sampled else 0.0)
    f_max = 0.5 / sample_time_s if sampled else PSD_F_MAX_HZ
    f = (np.geomspace(PSD_F_MIN_HZ, f_max, PSD_POINTS) if frequency_hz is None
         else np.asarray(frequency_hz, dtype=float))
    psd = _psd_sampled(F, Qd, H, sample_time_s, f) if sampled else _psd_continuous(A, Bn, H, f)
    return Prediction(np.sqrt(var), f, psd, controller is not None, float(sample_time_s), float(delay_s), poles, r2)


def _autocovariance_square_integral(A, P, H, sample_time_s):
    """``integral R(tau)^2 d tau`` over all lags of each output (2,): continuous, R(tau) = h e^{A tau} p
    with p = P h^T, so ``integral_0^inf R^2 = h X h^T`` where ``A X + X A^T + p p^T = 0``; sampled,
    ``R_k = h F^k p`` and ``T (2 sum_{k>=0} R_k^2 - R_0^2)`` with ``X = F X F^T + p p^T``."""
    out = np.empty(H.shape[0])
    for i, h in enumerate(H):
        p = (P @ h)[:, None]
        if sample_time_s > 0.0:
            X = scipy.linalg.solve_discrete_lyapunov(A, p @ p.T)
            out[i] = sample_time_s * (2.0 * h @ X @ h - float(h @ p[:, 0]) ** 2)
        else:
            X = scipy.linalg.solve_continuous_lyapunov(A, -p @ p.T)
            out[i] = 2.0 * h @ X @ h
    return out
