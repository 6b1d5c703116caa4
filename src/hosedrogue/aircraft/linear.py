"""The receiver's linear model about a trim, and its modes.

States (13, :data:`STATE_NAMES`, the book's state vector of Stevens, Lewis & Johnson, in SI):
airspeed, angle of attack, sideslip, roll, pitch, yaw, body rates p, q, r, north, east, altitude,
engine power. Inputs (4): throttle [-], elevator, aileron, rudder [deg]. Outputs (15): the 13 states
and the normal and lateral load factors [g]. The Jacobians are central differences of
:func:`euler_derivative` (the aircraft's equations with Euler-angle and wind-axis kinematics) with the
steps of :data:`STATE_STEPS` and :data:`INPUT_STEPS`: small enough that a trim within
a step of a table breakpoint is rare (the tables are piecewise linear: across a breakpoint the
difference gives the mean of the two slopes), large enough that round-off stays near 1e-9 of each
derivative. At sea level the altitude's difference is a forward one (the atmosphere ends at 0 m):
its error, step x curvature of the density, is about 1e-7 of that column.

Modes are read from the eight states of the aircraft's motion about its centre of gravity
(airspeed, alpha, beta, phi, theta, p, q, r), with altitude and engine power held: the classical
short period and phugoid (longitudinal pairs, faster and slower; when one of them has split into
two real roots, as the F-16's short period does at its reference centre of gravity 0.35, the two
real roots carry its name, the faster family being the short period), Dutch roll (the lateral
pair), roll subsidence and spiral (the lateral real roots, faster and slower). An eigenvector is
lateral when most of its size (airspeed relative to the trim's, angles in rad, rates in rad/s) is
in beta, phi, p, r.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .dynamics import POWER, derivative, load_factors, wind_angles
from .rigid_body import euler_from_quaternion, quaternion_from_euler
from .trim import Trim

STATE_NAMES = ("airspeed_m_s", "alpha_rad", "beta_rad", "phi_rad", "theta_rad", "psi_rad", "p_rad_s", "q_rad_s",
               "r_rad_s", "north_m", "east_m", "altitude_m", "power_pct")
INPUT_NAMES = ("throttle", "elevator_deg", "aileron_deg", "rudder_deg")
OUTPUT_NAMES = STATE_NAMES + ("nz_g", "ny_g")

#: Central-difference steps of the states (units of :data:`STATE_NAMES`) and inputs.
STATE_STEPS = np.array([1e-4, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-3, 1e-3, 1e-3, 1e-4])
INPUT_STEPS = np.array([1e-6, 1e-4, 1e-4, 1e-4])

#: The eight states the modes are read from, and which of them are lateral.
MODE_STATES = (0, 1, 2, 3, 4, 6, 7, 8)
_LATERAL = {2, 3, 6, 8}
_ALTITUDE = 11


def euler_state(x: np.ndarray) -> np.ndarray:
    """The 13 Euler-angle states of the aircraft's 14-state ``x`` (steady air).

    Parameters
    ----------
    x : numpy.ndarray
        (14,) state of :mod:`hosedrogue.aircraft.dynamics`.

    Returns
    -------
    numpy.ndarray
        (13,) :data:`STATE_NAMES`.
    """
    vt, alpha, beta = wind_angles(x[3:6])
    return np.array([vt, alpha, beta, *euler_from_quaternion(x[6:10]), *x[10:13], x[0], x[1], -x[2], x[POWER]])


def body_state(xe: np.ndarray) -> np.ndarray:
    """The aircraft's 14-state of the Euler-angle state ``xe`` (inverse of :func:`euler_state`).

    Parameters
    ----------
    xe : numpy.ndarray
        (13,) :data:`STATE_NAMES`.

    Returns
    -------
    numpy.ndarray
        (14,) state.
    """
    vt, alpha, beta, phi, theta, psi = xe[:6]
    x = np.empty(14)
    x[0:3] = xe[9], xe[10], -xe[11]
    x[3:6] = vt * np.array([math.cos(alpha) * math.cos(beta), math.sin(beta), math.sin(alpha) * math.cos(beta)])
    x[6:10] = quaternion_from_euler(phi, theta, psi)
    x[10:13] = xe[6:9]
    x[POWER] = xe[12]
    return x


def euler_derivative(model, xe: np.ndarray, u: np.ndarray, gravity: float) -> np.ndarray:
    """d/dt of the 13 Euler-angle states: the body accelerations of the aircraft's equations turned
    into airspeed, alpha and beta rates, and the Euler-angle kinematics
    (phi' = p + tan(theta) (q sin(phi) + r cos(phi)), theta' = q cos(phi) - r sin(phi),
    psi' = (q sin(phi) + r cos(phi)) / cos(theta)).

    Parameters
    ----------
    model : AircraftModel
        The aircraft.
    xe : numpy.ndarray
        (13,) :data:`STATE_NAMES`.
    u : numpy.ndarray
        (4,) controls.
    gravity : float
        [m/s^2].

    Returns
    -------
    numpy.ndarray
        (13,) derivative.
    """
    x = body_state(xe)
    dx = derivative(model, x, u, gravity)
    (uu, v, w), (ud, vd, wd) = x[3:6], dx[3:6]
    vt, beta, phi, theta = xe[0], xe[2], xe[3], xe[4]
    p, q, r = xe[6:9]
    vtd = (uu * ud + v * vd + w * wd) / vt
    sp, cp = math.sin(phi), math.cos(phi)
    return np.array([vtd, (uu * wd - w * ud) / (uu * uu + w * w), (vt * vd - v * vtd) / (vt * vt * math.cos(beta)),
                     p + math.tan(theta) * (q * sp + r * cp), q * cp - r * sp, (q * sp + r * cp) / math.cos(theta),
                     dx[10], dx[11], dx[12], dx[0], dx[1], -dx[2], dx[POWER]])


@dataclass(frozen=True)
class Mode:
    """One mode of the linear model."""

    name: str  #: short period, phugoid, Dutch roll, roll, spiral (or "other")
    eigenvalues: tuple  #: its eigenvalue(s) [1/s], complex
    frequency_rad_s: float  #: undamped natural frequency [rad/s] (|lambda|)
    damping: float  #: damping ratio [-] (-Re/|lambda|; 1 or -1 for a real root)
    time_constant_s: float  #: -1/Re(lambda) [s] (negative: time to grow by e)

    def as_dict(self) -> dict:
        """The mode's numbers, eigenvalues as [re, im] pairs."""
        return {"name": self.name, "eigenvalues": [[float(e.real), float(e.imag)] for e in self.eigenvalues],
                "frequency_rad_s": self.frequency_rad_s, "damping": self.damping,
                "time_constant_s": self.time_constant_s}


@dataclass(frozen=True)
class ReceiverLinearModel:
    """x' = A x + B u, y = C x + D u about ``trim``; deviations in the units of the names."""

    A: np.ndarray  #: (13, 13)
    B: np.ndarray  #: (13, 4)
    C: np.ndarray  #: (15, 13)
    D: np.ndarray  #: (15, 4)
    trim: Trim  #: the trim linearized about
    modes: tuple  #: tuple of :class:`Mode`

    @property
    def ss(self):
        """python-control StateSpace with named states, inputs and outputs."""
        import control

        return control.ss(self.A, self.B, self.C, self.D, states=list(STATE_NAMES), inputs=list(INPUT_NAMES),
                          outputs=list(OUTPUT_NAMES), name="receiver")


def _jacobians(model, xe0, u0, gravity):
    def outputs(xe, u):
        nz, ny = load_factors(model, body_state(xe), u, gravity)
        return np.concatenate([xe, [nz, ny]])

    n, m = xe0.size, u0.size
    A, C = np.empty((n, n)), np.empty((n + 2, n))
    B, D = np.empty((n, m)), np.empty((n + 2, m))
    for i, h in enumerate(STATE_STEPS):
        xp, xm = xe0.copy(), xe0.copy()
        xp[i] += h
        # the atmosphere ends at 0 m: at sea level the altitude's difference is a forward one
        down = 0.0 if i == _ALTITUDE and xe0[i] - h < 0.0 else h
        xm[i] -= down
        A[:, i] = (euler_derivative(model, xp, u0, gravity) - euler_derivative(model, xm, u0, gravity)) / (h + down)
        C[:, i] = (outputs(xp, u0) - outputs(xm, u0)) / (h + down)
    for j, h in enumerate(INPUT_STEPS):
        up, um = u0.copy(), u0.copy()
        up[j] += h
        um[j] -= h
        B[:, j] = (euler_derivative(model, xe0, up, gravity) - euler_derivative(model, xe0, um, gravity)) / (2 * h)
        D[:, j] = (outputs(xe0, up) - outputs(xe0, um)) / (2 * h)
    C[:n] = np.eye(n)  # the states are outputs exactly
    D[:n] = 0.0
    return A, B, C, D


def modes(A: np.ndarray, airspeed_m_s: float) -> tuple:
    """The modes of the linear model's state matrix (see the module's docstring).

    Parameters
    ----------
    A : numpy.ndarray
        (13, 13) state matrix of :data:`STATE_NAMES`.
    airspeed_m_s : float
        The trim's airspeed [m/s]: an eigenvector's airspeed component is weighed relative to it.

    Returns
    -------
    tuple of Mode
        Longitudinal first, then lateral; a real root is a mode entry of its own.
    """
    idx = list(MODE_STATES)
    lam, vec = np.linalg.eig(A[np.ix_(idx, idx)])
    lateral_rows = [k for k, s in enumerate(idx) if s in _LATERAL]
    groups = {"long": [], "lat": []}
    weight = np.ones(len(idx))
    weight[0] = 1.0 / airspeed_m_s  # airspeed as a fraction of itself, beside angles in radians
    for k in range(lam.size):
        if lam[k].imag < 0:
            continue
        v = np.abs(weight * vec[:, k]) ** 2
        groups["lat" if v[lateral_rows].sum() > 0.5 * v.sum() else "long"].append(lam[k])
    out = []
    for family, (fast, slow) in (("long", ("short period", "phugoid")), ("lat", ("Dutch roll", None))):
        pairs = sorted((e for e in groups[family] if e.imag > 0), key=abs, reverse=True)
        reals = sorted((e for e in groups[family] if e.imag == 0), key=abs, reverse=True)
        if family == "lat":
            named = [(fast, p) for p in pairs[:1]] + [("roll-spiral", p) for p in pairs[1:2]]
            named += list(zip(("roll", "spiral") if len(pairs) == 1 else (), reals))
        elif len(pairs) == 2:
            named = [(fast, pairs[0]), (slow, pairs[1])]
        elif len(pairs) == 1:  # one oscillation and two real roots: the faster of the two is the short period
            pair_fast = not reals or abs(pairs[0]) > abs(reals[0])
            named = [(fast if pair_fast else slow, pairs[0])] + [(slow if pair_fast else fast, e) for e in reals[:2]]
        else:
            named = [(fast, e) for e in reals[:2]] + [(slow, e) for e in reals[2:4]]
        used = {id(e) for _, e in named}
        named += [("other", e) for e in pairs + reals if id(e) not in used]
        out.extend(_mode(name, (e, e.conjugate()) if e.imag > 0 else (e,)) for name, e in named)
    return tuple(out)


def _mode(name: str, eig: tuple) -> Mode:
    e = eig[0]
    wn = abs(e)
    return Mode(name, eig, float(wn), float(-e.real / wn) if wn > 0 else math.nan,
                float(-1.0 / e.real) if e.real != 0 else math.inf)


def linearize_receiver(trim: Trim) -> ReceiverLinearModel:
    """The linear model of ``trim.model`` about ``trim`` (same gravity).

    Parameters
    ----------
    trim : Trim
        A trim from :func:`hosedrogue.aircraft.trim.trim`.

    Returns
    -------
    ReceiverLinearModel
    """
    xe0 = euler_state(trim.state)
    A, B, C, D = _jacobians(trim.model, xe0, np.asarray(trim.controls, float), trim.gravity_m_s2)
    return ReceiverLinearModel(A, B, C, D, trim, modes(A, trim.airspeed_m_s))
