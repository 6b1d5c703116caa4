"""Trim of a receiver model: steady flight at an airspeed, altitude, climb angle and bank angle.

Steady flight here is a steady coordinated turn about the vertical (a straight climb or level
flight when the bank is zero): the body's velocity and angular velocity are constant in body
axes, the flight path climbs at the given angle, and the ball is centred (no lateral specific
force). Unknowns (8): angle of attack, sideslip, pitch angle, turn rate, throttle, elevator,
aileron, rudder. Equations (8): the three body accelerations and the three angular accelerations
are zero, the climb rate is V sin(climb), the lateral specific force is zero. The body rates of
the turn are psi_dot (-sin theta, sin phi cos theta, cos phi cos theta); the engine runs at the
power its throttle commands.

The solution is :func:`scipy.optimize.least_squares` (trust-region reflective, the controls held
within their limits and the throttle to 0..1) from a starting point found on a grid of angle of
attack and elevator (lift and pitching moment balanced), then from other angles of attack if that
one does not converge. A trim is accepted when every residual is below :data:`RESIDUAL_TOL`; if
none is, :class:`~hosedrogue.errors.EquilibriumError` says what was left.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from ..constants import G0
from ..errors import EquilibriumError, ParameterError
from .dynamics import N_STATE, POWER, derivative_and_force
from .engine import commanded_power
from .model_file import AircraftModel
from .rigid_body import dcm_body_from_ned, quaternion_from_euler

#: Largest residual a trim may leave: 1e-9 m/s^2 (and rad/s^2, m/s), far below what any sensor or
#: controller resolves; the solver reaches about 1e-12 where a trim exists.
RESIDUAL_TOL = 1e-9

#: Names of the residuals, in the order of :attr:`Trim.residuals`.
RESIDUAL_NAMES = ("u_dot_m_s2", "v_dot_m_s2", "w_dot_m_s2", "p_dot_rad_s2", "q_dot_rad_s2", "r_dot_rad_s2",
                  "climb_rate_error_m_s", "lateral_specific_force_m_s2")

_DEG = math.pi / 180.0


@dataclass(frozen=True)
class Trim:
    """A trimmed steady flight of a receiver model (SI; angles in radians unless named _deg)."""

    model: AircraftModel  #: the aircraft (with its centre of gravity)
    airspeed_m_s: float  #: true airspeed [m/s]
    altitude_m: float  #: altitude [m]
    climb_rad: float  #: flight-path climb angle [rad]
    bank_rad: float  #: bank angle [rad]
    alpha_rad: float  #: angle of attack [rad]
    beta_rad: float  #: sideslip [rad]
    theta_rad: float  #: pitch angle [rad]
    turn_rate_rad_s: float  #: heading rate [rad/s]
    controls: np.ndarray  #: (4,) throttle [-], elevator, aileron, rudder [deg]
    state: np.ndarray  #: (14,) the aircraft's state (north = east = 0, heading 0)
    residuals: np.ndarray  #: (8,) :data:`RESIDUAL_NAMES` at the trim
    gravity_m_s2: float  #: the gravity trimmed under [m/s^2]

    def as_dict(self) -> dict:
        """The trim's numbers by name (degrees for angles), for JSON and tables."""
        th, el, ail, rud = self.controls
        return {"airspeed_m_s": self.airspeed_m_s, "altitude_m": self.altitude_m,
                "climb_deg": self.climb_rad / _DEG, "bank_deg": self.bank_rad / _DEG, "xcg": self.model.xcg,
                "alpha_deg": self.alpha_rad / _DEG, "beta_deg": self.beta_rad / _DEG,
                "theta_deg": self.theta_rad / _DEG, "turn_rate_deg_s": self.turn_rate_rad_s / _DEG,
                "throttle": float(th), "elevator_deg": float(el), "aileron_deg": float(ail),
                "rudder_deg": float(rud), "power_pct": float(self.state[POWER]),
                "residuals": dict(zip(RESIDUAL_NAMES, map(float, self.residuals)))}


def trim_state(model: AircraftModel, airspeed: float, altitude: float, bank: float, z: np.ndarray) -> np.ndarray:
    """The 14-state of a steady turn from the trim unknowns ``z`` (alpha, beta, theta, turn rate,
    throttle, ...), heading 0 at the origin.

    Parameters
    ----------
    model : AircraftModel
        The aircraft.
    airspeed, altitude, bank : float
        [m/s], [m], [rad].
    z : numpy.ndarray
        (8,) unknowns: alpha, beta, theta [rad], turn rate [rad/s], throttle, elevator, aileron, rudder.

    Returns
    -------
    numpy.ndarray
        (14,) state.
    """
    alpha, beta, theta, psi_dot = z[:4]
    x = np.zeros(N_STATE)
    x[2] = -altitude
    x[3:6] = airspeed * np.array([math.cos(alpha) * math.cos(beta), math.sin(beta), math.sin(alpha) * math.cos(beta)])
    x[6:10] = quaternion_from_euler(bank, theta, 0.0)
    x[10:13] = psi_dot * np.array([-math.sin(theta), math.sin(bank) * math.cos(theta),
                                   math.cos(bank) * math.cos(theta)])
    x[POWER] = commanded_power(model.engine, z[4])
    return x


def _residuals(z, model, airspeed, altitude, climb, bank, gravity):
    x = trim_state(model, airspeed, altitude, bank, z)
    u = z[4:]
    dx, force = derivative_and_force(model, x, u, gravity)
    lateral = force[1] / model.mass_kg - gravity * dcm_body_from_ned(x[6:10])[1, 2]
    return np.concatenate([dx[3:6], dx[10:13], [-dx[2] - airspeed * math.sin(climb), lateral]])


def _start(model, airspeed, altitude, climb, bank, gravity) -> np.ndarray:
    """A starting point: angle of attack and elevator balancing lift and pitching moment on a grid,
    then the throttle balancing drag."""
    lo, hi = model.limits_deg["elevator"]
    best = (math.inf, None)
    for alpha in np.arange(-10.0, 50.5, 1.0) * _DEG:
        for el in np.linspace(lo, hi, 26):
            z = np.array([alpha, 0.0, alpha + climb, 0.0, 0.5, el, 0.0, 0.0])
            r = _residuals(z, model, airspeed, altitude, climb, 0.0, gravity)
            cost = r[2] ** 2 + (10.0 * r[4]) ** 2
            if cost < best[0]:
                best = (cost, z)
    z = best[1]
    costs = []
    for th in np.linspace(0.0, 1.0, 41):
        z[4] = th
        costs.append(abs(_residuals(z, model, airspeed, altitude, climb, 0.0, gravity)[0]))
    z[4] = np.linspace(0.0, 1.0, 41)[int(np.argmin(costs))]
    z[3] = gravity * math.tan(bank) / airspeed
    return z


def trim(model: AircraftModel, airspeed_m_s: float, altitude_m: float, climb_deg: float = 0.0,
         bank_deg: float = 0.0, gravity: float = G0) -> Trim:
    """Trim ``model`` in steady flight (see the module's docstring).

    Parameters
    ----------
    model : AircraftModel
        The aircraft (its centre of gravity is ``model.xcg``).
    airspeed_m_s : float
        True airspeed [m/s], > 0.
    altitude_m : float
        Altitude [m].
    climb_deg : float
        Flight-path climb angle [deg], in (-90, 90).
    bank_deg : float
        Bank angle of the coordinated turn [deg], in (-90, 90); 0 for straight flight.
    gravity : float
        Acceleration of gravity [m/s^2].

    Returns
    -------
    Trim

    Raises
    ------
    ParameterError
        For an airspeed, climb or bank out of range.
    EquilibriumError
        When no trim is found (e.g. too slow for the tables, or more thrust than the engine has).
    """
    for name, value, ok in (("airspeed_m_s", airspeed_m_s, airspeed_m_s > 0),
                            ("climb_deg", climb_deg, abs(climb_deg) < 90), ("bank_deg", bank_deg, abs(bank_deg) < 90)):
        if not (math.isfinite(value) and ok):
            raise ParameterError(f"{name} = {value!r}: must be " + ("> 0" if name == "airspeed_m_s" else "in (-90, 90) deg"))
    climb, bank = climb_deg * _DEG, bank_deg * _DEG
    lim = model.limits_deg
    lower = [-30 * _DEG, -30 * _DEG, -89 * _DEG, -np.inf, 0.0, lim["elevator"][0], lim["aileron"][0], lim["rudder"][0]]
    upper = [90 * _DEG, 30 * _DEG, 89 * _DEG, np.inf, 1.0, lim["elevator"][1], lim["aileron"][1], lim["rudder"][1]]
    args = (model, airspeed_m_s, altitude_m, climb, bank, gravity)
    z0 = _start(*args)
    best = None
    for alpha0 in (None, 2.0, 10.0, 25.0, 40.0):
        if alpha0 is not None:
            z0 = z0.copy()
            z0[0], z0[2] = alpha0 * _DEG, alpha0 * _DEG + climb
        sol = least_squares(_residuals, np.clip(z0, lower, upper), bounds=(lower, upper), args=args,
                            x_scale=[0.1, 0.1, 0.1, 0.1, 0.1, 1.0, 1.0, 1.0], xtol=1e-15, ftol=1e-15, gtol=1e-15,
                            max_nfev=2000)
        if best is None or sol.cost < best.cost:
            best = sol
        if np.max(np.abs(sol.fun)) < RESIDUAL_TOL:
            break
    worst = int(np.argmax(np.abs(best.fun)))
    if abs(best.fun[worst]) >= RESIDUAL_TOL:
        th, el = best.x[4], best.x[5]
        raise EquilibriumError(
            f"no trim of {model.name} at {airspeed_m_s:g} m/s, {altitude_m:g} m, climb {climb_deg:g} deg, bank "
            f"{bank_deg:g} deg: the best point found leaves {RESIDUAL_NAMES[worst]} = {best.fun[worst]:.3g} "
            f"(throttle {th:.3f}, elevator {el:.2f} deg, alpha {best.x[0] / _DEG:.2f} deg)", best)
    z = best.x
    return Trim(model, float(airspeed_m_s), float(altitude_m), climb, bank, float(z[0]), float(z[1]), float(z[2]),
                float(z[3]), z[4:].copy(), trim_state(model, airspeed_m_s, altitude_m, bank, z), best.fun.copy(),
                float(gravity))
