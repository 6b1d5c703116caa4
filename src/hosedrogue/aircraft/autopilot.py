"""The receiver's built-in inner loop: a sampled-data LQR on the aircraft's linear model that holds
a reference flight - airspeed, attitude and a point moving at the commanded velocity - through the
throttle and the three surfaces (docs/receiver.md, "The inner loop").

The reference is the trim's Euler-angle state (:data:`hosedrogue.aircraft.linear.STATE_NAMES`)
with its airspeed, heading and pitch moved by the commanded velocity and its position the point
that moves at it. The position held is a point on the airframe (``lever_m`` from the centre of
gravity, body axes: the probe tip), so the loop moves the tip by turning the airframe about the
centre of gravity as well as by moving it: the linear model's north, east and altitude become the
point's (a change of coordinates of the state, x' = T x, exact to first order about the trim); the controls are the trim's less ``K (xe - xe_ref)``, clipped to the model's
limits. ``K`` is the discrete LQR (python-control's ``dlqr``) of the linear model held by a
zero-order hold over the sample time, so the sampled loop is designed as it runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .linear import STATE_NAMES, ReceiverLinearModel, linearize_receiver
from .rigid_body import dcm_body_from_ned, euler_from_quaternion, quaternion_from_euler
from .trim import Trim

#: Bryson's rule: the deviation of each state (13, :data:`STATE_NAMES`) that costs as much as
#: another's: 0.5 m/s of airspeed and 0.1 m of the held point's position (a docking approach
#: corrects by decimetres within a capture radius of 0.3 m), 5 deg of alpha, beta and pitch and
#: 10 deg of bank and heading (the attitude is free to move the probe), 10 deg/s of rate, 20 % of
#: power (half the throttle's range of the engine). With 0.3 m of position and 2 and 5 deg of
#: attitude the F-16 missed 3 of 6 approaches in moderate turbulence (seeds 2018, 1-5).
STATE_SCALE = np.array([0.5, math.radians(5.0), math.radians(5.0), math.radians(10.0), math.radians(5.0),
                        math.radians(10.0), math.radians(10.0), math.radians(10.0), math.radians(10.0), 0.1, 0.1,
                        0.1, 20.0])
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
            (13,) :data:`STATE_NAMES`, north, east and altitude the held point's (see the module's docstring).

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


def point_transform(trim: Trim, lever_m) -> np.ndarray:
    """T (13, 13): the linear model's state with north, east and altitude those of the point
    ``lever_m`` (body axes from the centre of gravity [m]) instead of the centre of gravity's; the
    attitude's effect by central differences of the point's offset C_NB(phi, theta, psi) lever.

    Parameters
    ----------
    trim : Trim
        The flight linearized about.
    lever_m : array_like
        (3,) [m].

    Returns
    -------
    numpy.ndarray
    """
    lever = np.asarray(lever_m, dtype=np.float64)
    T = np.eye(len(STATE_NAMES))
    angles = np.array(euler_from_quaternion(trim.state[6:10]))
    step = 1e-6  # rad: central differences of a trigonometric function, error ~1e-12 of the lever

    def offset(a):
        d = dcm_body_from_ned(quaternion_from_euler(*a)).T @ lever
        return np.array([d[0], d[1], -d[2]])  # north, east, up

    for i in range(3):
        da = np.zeros(3)
        da[i] = step
        T[9:12, 3 + i] = (offset(angles + da) - offset(angles - da)) / (2.0 * step)
    return T


def design_inner_loop(trim: Trim, sample_time_s: float, lever_m=(0.0, 0.0, 0.0)) -> InnerLoop:
    """The discrete LQR of the receiver's linear model about ``trim`` at ``sample_time_s``.

    Parameters
    ----------
    trim : Trim
        The flight held (:func:`hosedrogue.aircraft.trim`).
    sample_time_s : float
        The loop's sample time [s] (zero-order hold), > 0.
    lever_m : array_like
        (3,) the point whose position is held, body axes from the centre of gravity [m] (the
        probe tip; zeros: the centre of gravity).

    Returns
    -------
    InnerLoop
        With the closed-loop poles (all with a negative real part: the loop stabilizes the
        statically unstable F-16 at xcg 0.35).
    """
    import control

    lm = linearize_receiver(trim)
    T = point_transform(trim, lever_m)
    sysd = control.c2d(control.ss(T @ lm.A @ np.linalg.inv(T), T @ lm.B, np.eye(len(STATE_NAMES)), 0.0),
                       sample_time_s, method="zoh")
    Q = np.diag(1.0 / STATE_SCALE ** 2)
    R = np.diag(1.0 / INPUT_SCALE ** 2)
    K, _, z = control.dlqr(sysd.A, sysd.B, Q, R)
    return InnerLoop(trim, lm, float(sample_time_s), np.asarray(K), np.log(np.asarray(z, dtype=complex)) / sample_time_s)
