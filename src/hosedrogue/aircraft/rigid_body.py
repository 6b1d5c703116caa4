"""A rigid body in six degrees of freedom over a flat, non-rotating Earth (body axes, quaternion).

Frames: N, north-east-down, taken as inertial (flat Earth: the Earth's rotation, about 7e-5
rad/s, and curvature are left out, as Stevens, Lewis & Johnson's F-16 model does); B, body axes
(x forward, y right, z down) at the centre of gravity. The state (:data:`STATE_NAMES`):

* position of the centre of gravity in N [m] (north, east, down),
* velocity of the centre of gravity in body axes [m/s] (u, v, w),
* attitude: the unit quaternion q = (q0, q1, q2, q3), scalar first, of the rotation from N to B,
* angular velocity of B in body axes [rad/s] (p, q, r).

The attitude is a quaternion rather than Euler angles: its kinematics are polynomial and have no
singularity (Euler angles have one at 90 deg pitch), so a manoeuvring receiver, or a tumbling
body in a test, is integrated everywhere; Euler angles (``euler_from_quaternion``) are for
output and for the linear model (:mod:`hosedrogue.aircraft.linear`), whose modes are read in them.

Equations (Newton-Euler about the centre of gravity, with a rotor of constant angular momentum
h fixed in the body, the engine):

    m (dv/dt + w x v) = F                      dq/dt = q (x) (0, w) / 2
    J dw/dt + w x (J w + h) = M                dp_N/dt = C_NB v

F and M (body axes) include gravity's force m C_BN g. The quaternion's norm is not imposed in the
derivative; :func:`normalized` restores it, and the integrator (:mod:`hosedrogue.aircraft.simulate`)
does so after each step.
"""

from __future__ import annotations

import numpy as np

#: Names of the 13 rigid-body states, in order.
STATE_NAMES = ("north_m", "east_m", "down_m", "u_m_s", "v_m_s", "w_m_s", "q0", "q1", "q2", "q3",
               "p_rad_s", "q_rad_s", "r_rad_s")
POS = slice(0, 3)
VEL = slice(3, 6)
QUAT = slice(6, 10)
RATE = slice(10, 13)
N_BODY = 13


def dcm_body_from_ned(q: np.ndarray) -> np.ndarray:
    """The direction-cosine matrix C_BN (NED vector to body axes) of the unit quaternion ``q``.

    Parameters
    ----------
    q : numpy.ndarray
        (4,) quaternion, scalar first.

    Returns
    -------
    numpy.ndarray
        (3, 3) matrix.
    """
    q0, q1, q2, q3 = q
    return np.array([
        [q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 + q0 * q3), 2 * (q1 * q3 - q0 * q2)],
        [2 * (q1 * q2 - q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3, 2 * (q2 * q3 + q0 * q1)],
        [2 * (q1 * q3 + q0 * q2), 2 * (q2 * q3 - q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3],
    ])


def quaternion_from_euler(phi: float, theta: float, psi: float) -> np.ndarray:
    """Quaternion of the yaw-pitch-roll (psi, theta, phi) rotation from NED to body axes.

    Parameters
    ----------
    phi, theta, psi : float
        Roll, pitch and yaw (heading) [rad].

    Returns
    -------
    numpy.ndarray
        (4,) unit quaternion, scalar first.
    """
    c = np.cos(np.array([phi, theta, psi]) / 2)
    s = np.sin(np.array([phi, theta, psi]) / 2)
    return np.array([c[0] * c[1] * c[2] + s[0] * s[1] * s[2], s[0] * c[1] * c[2] - c[0] * s[1] * s[2],
                     c[0] * s[1] * c[2] + s[0] * c[1] * s[2], c[0] * c[1] * s[2] - s[0] * s[1] * c[2]])


def euler_from_quaternion(q: np.ndarray) -> tuple[float, float, float]:
    """Roll, pitch and yaw [rad] of the unit quaternion ``q`` (inverse of :func:`quaternion_from_euler`).

    Parameters
    ----------
    q : numpy.ndarray
        (4,) quaternion, scalar first.

    Returns
    -------
    phi, theta, psi : float
    """
    c = dcm_body_from_ned(q)
    return (float(np.arctan2(c[1, 2], c[2, 2])), float(np.arcsin(np.clip(-c[0, 2], -1.0, 1.0))),
            float(np.arctan2(c[0, 1], c[0, 0])))


def normalized(x: np.ndarray) -> np.ndarray:
    """A copy of the state ``x`` with its quaternion scaled to unit norm.

    Parameters
    ----------
    x : numpy.ndarray
        A state whose first 13 entries are laid out as :data:`STATE_NAMES`.

    Returns
    -------
    numpy.ndarray
    """
    y = np.array(x, dtype=float)
    y[QUAT] /= np.linalg.norm(y[QUAT])
    return y


def cross3(a, b) -> np.ndarray:
    """The cross product a x b of two 3-vectors, bit for bit ``numpy.cross``'s (the same products
    and differences in its order, none fused) without its axis handling, which made ``numpy.cross``
    about a quarter of an F-16 docking run's CPU.

    Parameters
    ----------
    a, b : array_like
        (3,) vectors.

    Returns
    -------
    numpy.ndarray
        (3,) a x b.
    """
    a0, a1, a2 = np.asarray(a, dtype=float).tolist()
    b0, b1, b2 = np.asarray(b, dtype=float).tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def rigid_body_derivative(x: np.ndarray, force_b: np.ndarray, moment_b: np.ndarray, mass_kg: float,
                          inertia: np.ndarray, rotor_momentum_b: np.ndarray) -> np.ndarray:
    """d/dt of the 13 rigid-body states under a body-axis force and moment (gravity included in them).

    Parameters
    ----------
    x : numpy.ndarray
        (13,) state, :data:`STATE_NAMES`.
    force_b : numpy.ndarray
        (3,) total force on the body in body axes [N].
    moment_b : numpy.ndarray
        (3,) total moment about the centre of gravity in body axes [N m].
    mass_kg : float
        Mass [kg].
    inertia : numpy.ndarray
        (3, 3) inertia matrix about the centre of gravity in body axes [kg m^2].
    rotor_momentum_b : numpy.ndarray
        (3,) angular momentum of rotors spinning in the body, relative to it [kg m^2/s].

    Returns
    -------
    numpy.ndarray
        (13,) derivative.
    """
    v = x[VEL]
    w = x[RATE]
    q = x[QUAT]
    dx = np.empty(N_BODY)
    dx[POS] = dcm_body_from_ned(q).T @ v
    dx[VEL] = force_b / mass_kg - cross3(w, v)
    p, qq, r = w
    dx[QUAT] = 0.5 * np.array([-q[1] * p - q[2] * qq - q[3] * r, q[0] * p + q[2] * r - q[3] * qq,
                               q[0] * qq + q[3] * p - q[1] * r, q[0] * r + q[1] * qq - q[2] * p])
    dx[RATE] = np.linalg.solve(inertia, moment_b - cross3(w, inertia @ w + rotor_momentum_b))
    return dx
