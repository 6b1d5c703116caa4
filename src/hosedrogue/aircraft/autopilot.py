"""The receiver's built-in inner loop: a sampled-data LQR on the aircraft's linear model that holds
a reference flight - airspeed, attitude and a point moving at the commanded velocity - through the
throttle and the three surfaces (docs/receiver.md, "The inner loop").

The reference is the trim's Euler-angle state (:data:`hosedrogue.aircraft.linear.STATE_NAMES`)
with its airspeed, heading and pitch moved by the commanded velocity and its position the point
that moves at it; the controls are the trim's less ``K (xe - xe_ref)``, clipped to the model's
limits. ``K`` is the discrete LQR (python-control's ``dlqr``) of the linear model held by a
zero-order hold over the sample time, so the sampled loop is designed as it runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .linear import STATE_NAMES, ReceiverLinearModel, linearize_receiver
from .trim import Trim

#: Bryson's rule: the deviation of each state (13, :data:`STATE_NAMES`) that costs as much as
#: another's: 0.5 m/s of airspeed and 0.3 m of position (a docking approach corrects by
#: decimetres), 2 deg of alpha, beta and pitch (a formation pilot's attitude changes), 5 deg of
#: bank and heading, 10 deg/s of rate, 20 % of power (half the throttle's range of the engine).
STATE_SCALE = np.array([0.5, math.radians(2.0), math.radians(2.0), math.radians(5.0), math.radians(2.0),
                        math.radians(5.0), math.radians(10.0), math.radians(10.0), math.radians(10.0), 0.3, 0.3,
                        0.3, 20.0])
#: Bryson's rule for the inputs: 0.1 of throttle, 5 deg of elevator, 10 deg of aileron and rudder
#: (a quarter to a third of the F-16's ranges: +-25, +-21.5, +-30 deg).
INPUT_SCALE = np.array([0.1, 5.0, 10.0, 10.0])


@dataclass(frozen=True)
class InnerLoop:
    """The receiver's inner loop about ``trim`` (see the module's docstring)."""

    trim: Trim  #: the trim it holds
    linear: ReceiverLinearModel  #: the linear model it is designed on
    sample_time_s: float  #: the zero-order hold's period [s]
    K: np.ndarray  #: (4, 13) gain: controls [throttle, deg, deg, deg] per state deviation
    poles: np.ndarray  #: closed-loop poles of the sampled loop as continuous ones, log(z) / T [1/s]

    def controls(self, xe: np.ndarray, xe_ref: np.ndarray) -> np.ndarray:
        """Throttle and surfaces [-, deg] for the Euler-angle state ``xe`` and reference ``xe_ref``.

        Parameters
        ----------
        xe, xe_ref : numpy.ndarray
            (13,) :data:`STATE_NAMES`.

        Returns
        -------
        numpy.ndarray
            (4,) controls clipped to the model's limits (throttle 0..1).
        """
        e = xe - xe_ref
        e[5] = math.remainder(e[5], 2.0 * math.pi)  # heading
        u = self.trim.controls - self.K @ e
        lim = self.trim.model.limits_deg
        lo = np.array([0.0, lim["elevator"][0], lim["aileron"][0], lim["rudder"][0]])
        hi = np.array([1.0, lim["elevator"][1], lim["aileron"][1], lim["rudder"][1]])
        return np.clip(u, lo, hi)


def design_inner_loop(trim: Trim, sample_time_s: float) -> InnerLoop:
    """The discrete LQR of the receiver's linear model about ``trim`` at ``sample_time_s``.

    Parameters
    ----------
    trim : Trim
        The flight held (:func:`hosedrogue.aircraft.trim`).
    sample_time_s : float
        The loop's sample time [s] (zero-order hold), > 0.

    Returns
    -------
    InnerLoop
        With the closed-loop poles (all with a negative real part: the loop stabilizes the
        statically unstable F-16 at xcg 0.35).
    """
    import control

    lm = linearize_receiver(trim)
    sysd = control.c2d(control.ss(lm.A, lm.B, np.eye(len(STATE_NAMES)), 0.0), sample_time_s, method="zoh")
    Q = np.diag(1.0 / STATE_SCALE ** 2)
    R = np.diag(1.0 / INPUT_SCALE ** 2)
    K, _, z = control.dlqr(sysd.A, sysd.B, Q, R)
    return InnerLoop(trim, lm, float(sample_time_s), np.asarray(K), np.log(np.asarray(z, dtype=complex)) / sample_time_s)
