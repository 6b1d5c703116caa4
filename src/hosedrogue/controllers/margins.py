"""Loop analysis of the drogue controller: gain, phase and delay margins and the frequency
response of each channel's loop on the full-order linear model (docs/loop-analysis.md).

Each channel's loop is broken at its force input with the other channel's loop closed (the
loop-at-a-time margins): L_i(s) = -(u_i returned) / (u_i injected), the minus turning the
controller's own sign (:mod:`hosedrogue.controllers.linear`) into the usual negative-feedback
convention, so that the loop is stable when the Nyquist plot of L_i does not encircle -1.

Continuous controller: L(s) = -K(s) G(s) on the full-order linearization. Sampled controller
(sample time T, sensor delay d T), as the simulation runs it: the plant discretized exactly with
a zero-order hold, the controller's zero-order-hold discretization
(:func:`hosedrogue.controllers.discrete.discretize`), the delay z^-d; the loop is then exact at
the sampling instants and its frequency response runs to the Nyquist frequency pi / T.

Margins from the frequency response on a dense grid (:data:`GRID_POINTS` per decade), each
crossing refined by Brent's method:

* gain margin: 1 / |L| where L crosses the negative real axis; the one nearest 1 (in log) is
  reported (python-control's rule), with its frequency;
* phase margin: 180 deg + arg L where |L| = 1; the smallest in magnitude is reported;
* delay margin: the smallest extra delay that brings a gain crossover onto -1, min over the
  crossovers of (phase margin [rad] / crossover frequency), wrapped to [0, 2 pi) [s]. For a
  sampled loop an extra delay that is a whole number of samples is exactly z^-m, so the loop is
  stable with extra delays below the margin and unstable just above (the test simulates both).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..analysis.linearize import LinearModel
from .covariance import delay_samples
from .discrete import discretize
from .linear import LinearController

__all__ = ["CHANNELS", "GRID_POINTS", "LoopMargins", "channel_loop", "loop_margins", "margins"]

#: The channels: name, force input and measured output index.
CHANNELS = ("lateral", "vertical")
#: Frequency grid of the margins' search [points per decade]: consecutive points 0.5 % apart, so a
#: crossing is bracketed unless two lie within 0.5 % of each other.
GRID_POINTS = 500
#: Lowest frequency of the grid [rad/s], far below the hose's lowest mode (~1 rad/s).
W_MIN_RAD_S = 1e-3
#: Highest frequency of a continuous loop's grid [rad/s] (a sampled loop's is its Nyquist frequency).
W_MAX_RAD_S = 1e4


def _delay_line(d: int, T: float):
    """z^-d on two channels, as a discrete state space (None for d = 0)."""
    import control

    if d == 0:
        return None
    n = 2 * d
    A = np.zeros((n, n))
    for i in range(1, d):
        A[2 * i:2 * i + 2, 2 * i - 2:2 * i] = np.eye(2)
    B = np.zeros((n, 2))
    B[:2] = np.eye(2)
    C = np.zeros((2, n))
    C[:, n - 2:] = np.eye(2)
    return control.ss(A, B, C, np.zeros((2, 2)), T)


def channel_loop(lm: LinearModel, controller: LinearController, channel: str, sample_time_s: float = 0.0,
                 delay_s: float = 0.0):
    """The loop L of one channel, broken at its force input with the other channel closed.

    Parameters
    ----------
    lm : LinearModel
        The full-order linear model.
    controller : LinearController
        The design (continuous; discretized here when sampled).
    channel : {"lateral", "vertical"}
        The loop to break.
    sample_time_s : float
        The controller's sample time [s]; 0: continuous.
    delay_s : float
        The sensor's delay [s], a whole multiple of the sample time (sampled only).

    Returns
    -------
    control.StateSpace
        SISO, continuous or discrete (dt = T); force [N] -> force [N], negative-feedback sign.
    """
    import control

    i = CHANNELS.index(channel)
    j = 1 - i
    plant = control.ss(lm.A, lm.B, lm.C, lm.D)
    if sample_time_s > 0.0:
        T = float(sample_time_s)
        plant = control.c2d(plant, T, method="zoh")
        ctrl = control.ss(*discretize(controller, T), T)
        line = _delay_line(delay_samples(delay_s, T), T)
        if line is not None:
            plant = control.series(plant, line)
    else:
        ctrl = controller.as_statespace()
    kp = control.series(plant, ctrl)  # u (2) -> controller's output (2)
    close_j = np.zeros((2, 2))
    close_j[j, j] = 1.0
    kp = control.feedback(kp, control.ss([], [], [], close_j, kp.dt), sign=+1)
    return -kp[i, i]


@dataclass(frozen=True)
class LoopMargins:
    """Margins of one channel's loop."""

    gain_margin: float  #: factor [-] (inf: no phase crossover)
    gain_crossover_phase_rad_s: float  #: frequency where the gain margin is read [rad/s] (NaN: none)
    phase_margin_deg: float  #: [deg] (inf: no gain crossover)
    crossover_rad_s: float  #: gain crossover frequency of the phase margin [rad/s] (NaN: none)
    delay_margin_s: float  #: extra delay that makes the loop unstable [s] (inf: no crossover; 0: unstable already)
    stable: bool  #: the closed loop (both channels) is stable
    sample_time_s: float  #: [s]; 0 continuous
    delay_s: float  #: the sensor's delay already in the loop [s]

    @property
    def gain_margin_db(self) -> float:
        """The gain margin in decibels."""
        return 20.0 * math.log10(self.gain_margin) if self.gain_margin > 0 else -math.inf

    def as_dict(self) -> dict:
        """Plain numbers for JSON (infinities are written as null by :mod:`hosedrogue.jsonio`)."""
        return {"gain_margin": self.gain_margin, "gain_margin_db": self.gain_margin_db,
                "phase_crossover_rad_s": self.gain_crossover_phase_rad_s,
                "phase_margin_deg": self.phase_margin_deg, "gain_crossover_rad_s": self.crossover_rad_s,
                "delay_margin_s": self.delay_margin_s, "stable": self.stable}


def frequency_grid(loop) -> np.ndarray:
    """The margins' frequency grid of a loop [rad/s] (:data:`GRID_POINTS` per decade, up to the
    Nyquist frequency of a sampled loop).

    Parameters
    ----------
    loop : control.StateSpace

    Returns
    -------
    numpy.ndarray
    """
    w_max = math.pi / loop.dt * (1.0 - 1e-9) if loop.isdtime(strict=True) else W_MAX_RAD_S
    decades = math.log10(w_max / W_MIN_RAD_S)
    return np.geomspace(W_MIN_RAD_S, w_max, int(decades * GRID_POINTS) + 1)


def response(loop, w) -> np.ndarray:
    """L at frequencies ``w`` [rad/s] (s = i w, or z = exp(i w T) for a sampled loop), complex.

    Parameters
    ----------
    loop : control.StateSpace
    w : array_like

    Returns
    -------
    numpy.ndarray
    """
    w = np.asarray(w, dtype=float)
    arg = np.exp(1j * w * loop.dt) if loop.isdtime(strict=True) else 1j * w
    return np.asarray(loop(arg), dtype=complex).reshape(w.shape)


def _roots(fun, w, values):
    idx = np.nonzero(np.diff(np.sign(values)) != 0)[0]
    return np.array([brentq(fun, w[k], w[k + 1], xtol=1e-12, rtol=1e-12) for k in idx])


def margins(loop, closed_stable: bool = True, sample_time_s: float = 0.0, delay_s: float = 0.0) -> LoopMargins:
    """Gain, phase and delay margins of a SISO loop from its frequency response.

    Parameters
    ----------
    loop : control.StateSpace
        L, negative-feedback convention.
    closed_stable : bool
        Whether the closed loop is stable (reported with the margins).
    sample_time_s, delay_s : float
        Recorded with the margins [s].

    Returns
    -------
    LoopMargins
    """
    w = frequency_grid(loop)
    L = response(loop, w)

    def mag(x):
        return math.log(abs(response(loop, x))) if np.isscalar(x) else np.log(np.abs(response(loop, x)))

    def imag(x):
        return float(response(loop, x).imag)

    wc = _roots(mag, w, np.log(np.abs(L)))
    w180 = _roots(imag, w, L.imag)
    w180 = w180[response(loop, w180).real < 0.0] if w180.size else w180
    gm, w_gm = math.inf, math.nan
    if w180.size:
        gms = 1.0 / np.abs(response(loop, w180))
        k = int(np.argmin(np.abs(np.log(gms))))
        gm, w_gm = float(gms[k]), float(w180[k])
    pm, w_pm, dm = math.inf, math.nan, math.inf
    if wc.size:
        pms = np.remainder(np.angle(response(loop, wc), deg=True), 360.0) - 180.0
        k = int(np.argmin(np.abs(pms)))
        pm, w_pm = float(pms[k]), float(wc[k])
        dm = float(np.min(np.remainder(np.radians(pms), 2.0 * math.pi) / wc)) if closed_stable else 0.0
    return LoopMargins(gm, w_gm, pm, w_pm, dm, closed_stable, float(sample_time_s), float(delay_s))


def _closed_stable(lm: LinearModel, controller: LinearController, sample_time_s: float, delay_s: float) -> bool:
    loop = channel_loop(lm, controller, "lateral", sample_time_s, delay_s)
    closed = loop.feedback(1.0)
    p = np.linalg.eigvals(closed.A)
    return bool(np.all(np.abs(p) < 1.0)) if sample_time_s > 0.0 else bool(np.all(p.real < 0.0))


def loop_margins(lm: LinearModel, controller: LinearController, sample_time_s: float = 0.0,
                 delay_s: float = 0.0) -> dict[str, LoopMargins]:
    """The margins of both channels' loops.

    Parameters
    ----------
    lm : LinearModel
        The full-order linear model.
    controller : LinearController
        The design.
    sample_time_s : float
        The controller's sample time [s]; 0: continuous.
    delay_s : float
        The sensor's delay [s], a whole multiple of the sample time.

    Returns
    -------
    dict
        ``{"lateral": LoopMargins, "vertical": LoopMargins}``.
    """
    stable = _closed_stable(lm, controller, sample_time_s, delay_s)
    return {ch: margins(channel_loop(lm, controller, ch, sample_time_s, delay_s), stable, sample_time_s, delay_s)
            for ch in CHANNELS}
