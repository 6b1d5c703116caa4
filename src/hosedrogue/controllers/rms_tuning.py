"""A PID tuned to a predicted RMS offset in turbulence: the least gain crossover that meets it
(docs/loop-analysis.md, "Tuning to an RMS target").

The family: per channel, the loop-shaping PID of :func:`hosedrogue.controllers.pid.tune_pid` on
the channel's 2nd-order design model (balanced truncation, as the paper designs), with a fixed
phase margin at a gain crossover w_c. Raising w_c lowers the drogue's RMS offset and raises the
force, the noise the loop passes and its sensitivity to delay (its delay margin falls as 1 / w_c).
So among the designs that meet the target the one of least w_c is taken: the stated cost is the
crossover frequency. The RMS of each design is the covariance analysis's
(:func:`hosedrogue.controllers.covariance.predict`) on the full-order model with both channels
closed, sampled and delayed as asked. Each channel is searched on a logarithmic grid of w_c, the
first grid point that meets the target (with a stable loop) refined by Brent's method on
log(RMS / target); the channels are searched one after the other, twice, since a channel's RMS
depends (weakly, through the coupling of a turn) on the other's gains.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..analysis.linearize import linearize
from ..errors import ParameterError
from .covariance import disturbance_model, predict
from .design import reduced_channels
from .pid import PAPER_PID, PIDGains, pid_controller, tune_pid

__all__ = ["RmsDesign", "tune_pid_to_rms", "meets", "MET_RTOL"]

#: Crossover frequencies searched [rad/s]: from below the hose's lowest mode to well above the
#: paper's PID (40-60 rad/s), 60 points (12 % apart).
CROSSOVER_GRID_RAD_S = np.geomspace(0.3, 300.0, 60)
#: Phase margin of every design of the family [deg].
PHASE_MARGIN_DEG = 60.0


@dataclass(frozen=True)
class RmsDesign:
    """A PID per channel tuned to an RMS target."""

    gains: dict  #: channel -> PIDGains
    crossover_rad_s: dict  #: channel -> w_c of the design [rad/s]
    rms_m: dict  #: channel -> predicted RMS offset [m] with both loops closed
    targets_m: dict  #: channel -> the target [m]
    met: bool  #: every channel meets its target (else the closest design, marked)


def _rms(params, dm, gains, sample_time_s, delay_s) -> np.ndarray:
    try:
        pr = predict(params, pid_controller(gains["lateral"], gains["vertical"]), sample_time_s, delay_s, dm=dm,
                     frequency_hz=np.empty(0))
    except ParameterError:  # an unstable loop
        return np.full(2, math.inf)
    return pr.rms_m


def _design(plant, w: float):
    try:
        return tune_pid(plant, float(w), PHASE_MARGIN_DEG)
    except ValueError:  # this shape cannot give the phase at w
        return None


def _search_channel(k, ch, plant, gains, target, evaluate):
    """The least crossover on the grid (then refined) meeting ``target``; else the best one."""
    best = (math.inf, None, None)
    prev = None
    for w in CROSSOVER_GRID_RAD_S:
        g = _design(plant, w)
        if g is None:
            continue
        r = evaluate({**gains, ch: g})[k]
        if r < best[0]:
            best = (r, w, g)
        if r <= target:
            if prev is not None and math.isfinite(prev[1]):
                def f(x):
                    gx = _design(plant, x)
                    return math.log(evaluate({**gains, ch: gx})[k] / target) if gx is not None else math.inf
                try:
                    w = brentq(f, prev[0], w, xtol=1e-6, rtol=MET_RTOL)
                    g = _design(plant, w)
                    r = evaluate({**gains, ch: g})[k]
                except ValueError:  # no sign change (a design missing inside): keep the grid point
                    pass
            return r, w, g
        prev = (w, r)
    return best


def tune_pid_to_rms(params, targets_m, sample_time_s: float = 0.0, delay_s: float = 0.0) -> RmsDesign:
    """PID gains of least crossover whose predicted RMS offset meets ``targets_m``.

    Parameters
    ----------
    params : Params
        Model, flight condition and turbulence (enabled with its intensities, e.g.
        :func:`hosedrogue.controllers.covariance.with_standard_turbulence`).
    targets_m : sequence of float
        RMS targets [m], lateral and vertical, each > 0.
    sample_time_s : float
        The controller's sample time [s] (0: continuous).
    delay_s : float
        The sensor's delay [s], a whole multiple of the sample time.

    Returns
    -------
    RmsDesign
        ``met`` False when some target cannot be met on the family: the closest design found.
    """
    targets = [float(t) for t in targets_m]
    if len(targets) != 2 or not all(math.isfinite(t) and t > 0 for t in targets):
        raise ParameterError(f"rms targets = {list(targets_m)!r}: give two RMS offsets [m] > 0, lateral and vertical")
    lm = linearize(params)
    dm = disturbance_model(params, lm=lm)
    ch2 = reduced_channels(lm, 2)
    plants = {"lateral": ch2.lateral, "vertical": ch2.vertical}
    gains: dict[str, PIDGains] = dict(PAPER_PID)
    found = {}

    def evaluate(g):
        return _rms(params, dm, g, sample_time_s, delay_s)

    for _ in range(2):
        for k, ch in enumerate(("lateral", "vertical")):
            r, w, g = _search_channel(k, ch, plants[ch], gains, targets[k], evaluate)
            if g is None:
                raise ParameterError(f"rms targets = {targets!r}: no PID of the family keeps the {ch} loop stable")
            gains[ch] = g
            found[ch] = w
    rms = evaluate(gains)
    return RmsDesign(gains, found, {"lateral": float(rms[0]), "vertical": float(rms[1])},
                     {"lateral": targets[0], "vertical": targets[1]},
                     bool(meets(rms[0], targets[0]) and meets(rms[1], targets[1])))


#: Relative tolerance [-] within which a predicted RMS meets its target: Brent's method refines the
#: crossover to the target to this relative accuracy.
MET_RTOL = 1e-6


def meets(rms_m: float, target_m: float) -> bool:
    """Whether a predicted RMS offset [m] meets its target [m] (within :data:`MET_RTOL`).

    Parameters
    ----------
    rms_m, target_m : float
        The predicted RMS and the target [m].

    Returns
    -------
    bool
    """
    return bool(rms_m <= target_m * (1.0 + MET_RTOL))
