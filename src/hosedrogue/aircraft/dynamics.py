"""The receiver aircraft's equations of motion: the rigid body with its aerodynamics and engine.

State (14): the rigid body's 13 (:data:`hosedrogue.aircraft.rigid_body.STATE_NAMES`, SI, quaternion
attitude) and the engine's power level [%]. Controls (4, :data:`CONTROL_NAMES`): throttle 0..1 and
elevator, aileron and rudder [deg], signed as the model's tables define them (the F-16's:
positive elevator pitches the nose down, positive aileron rolls left, positive rudder yaws left). Air-relative velocity is the body velocity less the wind (NED, m/s),
zero unless given: the engagement will give the turbulence at the aircraft there.

Forces and moments follow the F16 subroutine of Stevens, Lewis & Johnson (2015, Section 3.5):
dimensionless body-axis coefficients from the model's tables (:mod:`.model_file`) with the rates
made dimensionless by b/(2V) and c/(2V), moments moved from the tables' reference to the centre of
gravity, thrust along body x, the engine's angular momentum in the moment equation.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import G0
from .air import air_data
from .engine import commanded_power, power_rate, thrust_n
from .model_file import AircraftModel
from .rigid_body import N_BODY, QUAT, RATE, VEL, dcm_body_from_ned, rigid_body_derivative

#: Names of the aircraft's 14 states: the rigid body's and the engine's power level.
STATE_NAMES = ("north_m", "east_m", "down_m", "u_m_s", "v_m_s", "w_m_s", "q0", "q1", "q2", "q3",
               "p_rad_s", "q_rad_s", "r_rad_s", "power_pct")
POWER = 13
N_STATE = 14

#: Names of the four controls.
CONTROL_NAMES = ("throttle", "elevator_deg", "aileron_deg", "rudder_deg")

_RAD2DEG = 180.0 / math.pi


def wind_angles(v_air_b: np.ndarray) -> tuple[float, float, float]:
    """Airspeed [m/s], angle of attack and sideslip [rad] of the air-relative body velocity.

    Parameters
    ----------
    v_air_b : numpy.ndarray
        (3,) velocity relative to the air, body axes [m/s].

    Returns
    -------
    airspeed, alpha, beta : float
    """
    u, v, w = v_air_b
    vt = math.sqrt(u * u + v * v + w * w)
    return vt, math.atan2(w, u), math.asin(max(-1.0, min(1.0, v / vt)))


def coefficients(model: AircraftModel, variables: dict[str, float]) -> np.ndarray:
    """Body-axis coefficients (CX, CY, CZ, Cl, Cm, Cn) about the model's centre of gravity.

    Parameters
    ----------
    model : AircraftModel
        The aircraft.
    variables : dict
        alpha, beta, elevator, aileron, rudder [deg], p_hat, q_hat, r_hat [-].

    Returns
    -------
    numpy.ndarray
        (6,) coefficients [-].
    """
    cells = {}  # the tables' cells at these variables, each found once (tables.Table)
    c = np.array([sum(term(variables, cells) for term in model.coefficients[name])
                  for name in ("CX", "CY", "CZ", "Cl", "Cm", "Cn")])
    shift = model.xcg_ref - model.xcg
    c[4] += c[2] * shift
    c[5] -= c[1] * shift * model.chord_m / model.span_m
    return c


def forces_moments(model: AircraftModel, x: np.ndarray, u: np.ndarray, gravity: float = G0,
                   wind_ned: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, dict]:
    """Total force [N] and moment [N m] on the aircraft in body axes, and the air data used.

    Parameters
    ----------
    model : AircraftModel
        The aircraft.
    x : numpy.ndarray
        (14,) state, :data:`STATE_NAMES`.
    u : numpy.ndarray
        (4,) controls, :data:`CONTROL_NAMES`.
    gravity : float
        Acceleration of gravity [m/s^2] (default the standard one).
    wind_ned : numpy.ndarray, optional
        (3,) wind velocity in NED [m/s].

    Returns
    -------
    force_b, moment_b : numpy.ndarray
        (3,) each.
    air : dict
        airspeed_m_s, alpha_rad, beta_rad, mach, dynamic_pressure_pa, thrust_n.
    """
    c_bn = dcm_body_from_ned(x[QUAT])
    v_air = x[VEL] - (c_bn @ wind_ned if wind_ned is not None else 0.0)
    vt, alpha, beta = wind_angles(v_air)
    altitude = -x[2]
    rho, sound = air_data(model.atmosphere, altitude)
    qbar = 0.5 * rho * vt * vt
    p, q, r = x[RATE]
    b2v, c2v = model.span_m / (2.0 * vt), model.chord_m / (2.0 * vt)
    variables = {"alpha": alpha * _RAD2DEG, "beta": beta * _RAD2DEG, "elevator": u[1], "aileron": u[2],
                 "rudder": u[3], "p_hat": p * b2v, "q_hat": q * c2v, "r_hat": r * b2v}
    cx, cy, cz, cl, cm, cn = coefficients(model, variables)
    qs = qbar * model.wing_area_m2
    thrust = thrust_n(model.engine, x[POWER], altitude, vt / sound)
    force = np.array([qs * cx + thrust, qs * cy, qs * cz]) + model.mass_kg * gravity * c_bn[:, 2]
    moment = qs * np.array([model.span_m * cl, model.chord_m * cm, model.span_m * cn])
    air = {"airspeed_m_s": vt, "alpha_rad": alpha, "beta_rad": beta, "mach": vt / sound,
           "dynamic_pressure_pa": qbar, "thrust_n": thrust}
    return force, moment, air


def derivative(model: AircraftModel, x: np.ndarray, u: np.ndarray, gravity: float = G0,
               wind_ned: np.ndarray | None = None) -> np.ndarray:
    """dx/dt of the aircraft's 14 states.

    Parameters
    ----------
    model : AircraftModel
        The aircraft.
    x : numpy.ndarray
        (14,) state, :data:`STATE_NAMES`.
    u : numpy.ndarray
        (4,) controls, :data:`CONTROL_NAMES`.
    gravity : float
        Acceleration of gravity [m/s^2].
    wind_ned : numpy.ndarray, optional
        (3,) wind velocity in NED [m/s] (steady air if not given).

    Returns
    -------
    numpy.ndarray
        (14,) derivative.
    """
    return derivative_and_force(model, x, u, gravity, wind_ned)[0]


def derivative_and_force(model: AircraftModel, x: np.ndarray, u: np.ndarray, gravity: float = G0,
                         wind_ned: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`derivative` and the total body force it was computed from, from one evaluation of the
    tables (the trim's residuals take both: :mod:`.trim`).

    Parameters
    ----------
    model, x, u, gravity, wind_ned
        As :func:`derivative`'s.

    Returns
    -------
    dx : numpy.ndarray
        (14,) derivative.
    force_b : numpy.ndarray
        (3,) total force in body axes [N] (:func:`forces_moments`).
    """
    force, moment, _ = forces_moments(model, x, u, gravity, wind_ned)
    dx = np.empty(N_STATE)
    dx[:N_BODY] = rigid_body_derivative(x[:N_BODY], force, moment, model.mass_kg, model.inertia_kg_m2,
                                        np.array([model.engine_momentum_kg_m2_s, 0.0, 0.0]))
    dx[POWER] = power_rate(model.engine, x[POWER], commanded_power(model.engine, u[0]))
    return dx, force


def load_factors(model: AircraftModel, x: np.ndarray, u: np.ndarray, gravity: float = G0) -> tuple[float, float]:
    """Normal and lateral load factors [g]: the specific force (total less gravity) over g, normal
    positive up (-z body), lateral positive right (+y body).

    Parameters
    ----------
    model : AircraftModel
        The aircraft.
    x : numpy.ndarray
        (14,) state.
    u : numpy.ndarray
        (4,) controls.
    gravity : float
        Acceleration of gravity [m/s^2].

    Returns
    -------
    nz, ny : float
    """
    force, _, _ = forces_moments(model, x, u, gravity)
    specific = force / model.mass_kg - gravity * dcm_body_from_ned(x[QUAT])[:, 2]
    return -specific[2] / gravity, specific[1] / gravity


__all__ = ["STATE_NAMES", "CONTROL_NAMES", "N_STATE", "POWER", "derivative", "derivative_and_force", "forces_moments",
           "coefficients", "wind_angles", "load_factors"]
