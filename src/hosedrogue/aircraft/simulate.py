"""Time simulation of the receiver aircraft alone: classical fourth-order Runge-Kutta, fixed step.

The quaternion is scaled back to unit norm after each step (its drift is of the step's
truncation order; the scaling changes no rotation). A run whose state stops being finite ends
there, marked incomplete with the time and the reason, and keeps what it computed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..constants import G0
from ..errors import ParameterError
from .dynamics import derivative
from .model_file import AircraftModel
from .rigid_body import normalized


def rk4_step(f: Callable[[np.ndarray], np.ndarray], x: np.ndarray, dt: float) -> np.ndarray:
    """One classical Runge-Kutta step of x' = f(x).

    Parameters
    ----------
    f : callable
        The derivative, ``f(x) -> dx``.
    x : numpy.ndarray
        State now.
    dt : float
        Step [s].

    Returns
    -------
    numpy.ndarray
        State after ``dt``.
    """
    k1 = f(x)
    k2 = f(x + 0.5 * dt * k1)
    k3 = f(x + 0.5 * dt * k2)
    k4 = f(x + dt * k3)
    return x + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


@dataclass(frozen=True)
class Flight:
    """A simulated flight: times [s], states (n, 14), controls (n, 4), and whether it finished."""

    t: np.ndarray  #: (n,) times [s]
    x: np.ndarray  #: (n, 14) states
    u: np.ndarray  #: (n, 4) controls held over each step
    completed: bool  #: False when the run stopped early
    message: str  #: why it stopped early ("" when completed)


def fly(model: AircraftModel, x0: np.ndarray, controls, duration_s: float, dt_s: float = 0.01,
        gravity: float = G0) -> Flight:
    """Fly ``model`` from ``x0`` for ``duration_s`` with ``controls`` held over each step.

    Parameters
    ----------
    model : AircraftModel
        The aircraft.
    x0 : numpy.ndarray
        (14,) initial state (e.g. ``Trim.state``).
    controls : array_like or callable
        (4,) controls, or ``controls(t, x) -> (4,)`` evaluated at the start of each step.
    duration_s : float
        Duration [s], > 0.
    dt_s : float
        Step [s], > 0.
    gravity : float
        [m/s^2].

    Returns
    -------
    Flight
    """
    if not (math.isfinite(duration_s) and duration_s > 0 and math.isfinite(dt_s) and 0 < dt_s <= duration_s):
        raise ParameterError(f"duration_s = {duration_s!r}, dt_s = {dt_s!r}: need 0 < dt_s <= duration_s")
    n = int(round(duration_s / dt_s))
    t = np.arange(n + 1) * dt_s
    xs = np.empty((n + 1, x0.size))
    us = np.empty((n + 1, 4))
    xs[0] = x0
    law = controls if callable(controls) else (lambda _t, _x, c=np.asarray(controls, float): c)
    for k in range(n):
        u = np.asarray(law(t[k], xs[k]), dtype=float)
        us[k] = u
        try:
            nxt = normalized(rk4_step(lambda x: derivative(model, x, u, gravity), xs[k], dt_s))
        except (ValueError, ZeroDivisionError, ParameterError) as exc:
            nxt, reason = None, str(exc)
        if nxt is None or not np.all(np.isfinite(nxt)):
            why = reason if nxt is None else "the state is no longer finite"
            return Flight(t[:k + 1], xs[:k + 1], us[:k + 1], False, f"stopped at t = {t[k]:.3f} s: {why}")
        xs[k + 1] = nxt
    us[n] = us[n - 1]
    return Flight(t, xs, us, True, "")
