"""The rigid body alone: exact limiting cases and invariants, and the attitude kinematics against
scipy's rotations (an independent implementation)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from hosedrogue.aircraft.rigid_body import (QUAT, RATE, VEL, dcm_body_from_ned, euler_from_quaternion, normalized,
                                            quaternion_from_euler, rigid_body_derivative)
from hosedrogue.aircraft.simulate import rk4_step

MASS = 9295.4  # kg, the F-16's
#: An asymmetric inertia with a product of inertia (the F-16's, kg m^2), so Euler's equations couple.
INERTIA = np.array([[12875.0, 0.0, -1331.4], [0.0, 75674.0, 0.0], [-1331.4, 0.0, 85552.0]])
ROTOR = np.array([216.9, 0.0, 0.0])  # kg m^2/s, the F-16's engine


def test_attitude_kinematics_match_scipy(rng):
    for _ in range(20):
        phi, theta, psi = rng.uniform(-np.pi, np.pi), rng.uniform(-1.5, 1.5), rng.uniform(-np.pi, np.pi)
        q = quaternion_from_euler(phi, theta, psi)
        ref = Rotation.from_euler("ZYX", [psi, theta, phi])  # body attitude: yaw, then pitch, then roll
        # C_BN maps NED vectors to body axes: the inverse of the body attitude's rotation matrix
        np.testing.assert_allclose(dcm_body_from_ned(q), ref.as_matrix().T, atol=1e-15)
        np.testing.assert_allclose(euler_from_quaternion(q), (phi, theta, psi), atol=1e-12)


def _torque_free(x):
    return rigid_body_derivative(x, np.zeros(3), np.zeros(3), MASS, INERTIA, ROTOR)


def _tumble():
    x = np.zeros(13)
    x[VEL] = [120.0, -3.0, 7.0]
    x[QUAT] = quaternion_from_euler(0.3, -0.4, 1.0)
    x[RATE] = [1.2, -0.7, 0.9]  # rad/s: a tumble near neither principal axis
    return x


def _invariants(x):
    c_nb = dcm_body_from_ned(x[QUAT]).T
    w = x[RATE]
    return {"H_N": c_nb @ (INERTIA @ w + ROTOR), "T_rot": 0.5 * w @ INERTIA @ w, "v_N": c_nb @ x[VEL]}


def _integrate(f, x, dt, n):
    for _ in range(n):
        x = normalized(rk4_step(f, x, dt))
    return x


def _relative_errors(x, ref):
    inv = _invariants(x)
    return [np.linalg.norm(inv[k] - ref[k]) / np.linalg.norm(ref[k]) for k in ("H_N", "T_rot", "v_N")]


def test_torque_free_motion_conserves_momenta_and_energy_to_the_integrators_order():
    """No force, no moment (a rotor spinning inside): the angular momentum in the inertial frame,
    the rotational energy and the inertial velocity are constants of the exact motion (the body-axis
    velocity turns as the body tumbles). RK4's error in each falls at least as dt^4: halving the
    step divides it by 16 or more (measured 16.0, 29.7 and 16.0: the energy's leading error term
    nearly cancels; 12 allows for the next order's share); at dt = 1 ms over 5 s it is at
    round-off (below 1e-11 of the values)."""
    x0 = _tumble()
    ref = _invariants(x0)
    coarse, fine = (_relative_errors(_integrate(_torque_free, x0, dt, int(round(10.0 / dt))), ref)
                    for dt in (0.02, 0.01))
    for c, f in zip(coarse, fine):
        assert c / f > 12.0, (coarse, fine)
    assert max(_relative_errors(_integrate(_torque_free, x0, 0.001, 5000), ref)) < 1e-11


def _gravity_only(g):
    def f(x):
        weight_b = MASS * g * dcm_body_from_ned(x[QUAT])[:, 2]
        return rigid_body_derivative(x, weight_b, np.zeros(3), MASS, INERTIA, ROTOR)

    def energy(x):
        v_n = dcm_body_from_ned(x[QUAT]).T @ x[VEL]
        return 0.5 * MASS * v_n @ v_n + 0.5 * x[RATE] @ INERTIA @ x[RATE] + MASS * g * (-x[2])

    return f, energy


def test_gravity_only_non_rotating_projectile_is_integrated_exactly():
    """A projectile that does not rotate: its centre of gravity follows the exact parabola, which RK4
    integrates exactly (a quadratic in time), and its energy (kinetic plus potential, height -down)
    is constant: both to round-off (1e-9 m over 1 km; 1e-12 of the energy) at a coarse 50 ms step."""
    g = 9.80665
    f, energy = _gravity_only(g)
    x0 = _tumble()
    x0[RATE] = 0.0
    v0 = dcm_body_from_ned(x0[QUAT]).T @ x0[VEL]
    x = _integrate(f, x0, 0.05, 200)
    t = 10.0
    np.testing.assert_allclose(x[:3], x0[:3] + v0 * t + 0.5 * np.array([0, 0, g]) * t * t, rtol=0, atol=1e-9)
    assert energy(x) == pytest.approx(energy(x0), rel=1e-12)


def test_gravity_only_tumbling_body_conserves_energy_to_the_integrators_order():
    """A tumbling projectile: the energy is still constant; RK4's error in it falls at least as dt^4
    (ratio above 12 for a halved step) and is at round-off (1e-11) at 1 ms over 5 s."""
    f, energy = _gravity_only(9.80665)
    x0 = _tumble()
    e0 = energy(x0)
    err = [abs(energy(_integrate(f, x0, dt, int(round(10.0 / dt)))) - e0) / e0 for dt in (0.02, 0.01)]
    assert err[0] / err[1] > 12.0, err
    assert abs(energy(_integrate(f, x0, 0.001, 5000)) - e0) / e0 < 1e-11


def test_cross3_is_numpys_cross_bit_for_bit():
    """cross3 replaces numpy.cross on the F-16's hot path: the same bits, or every aircraft run changes."""
    from hosedrogue.aircraft.rigid_body import cross3

    rng = np.random.default_rng(11)
    scale = 10.0 ** rng.integers(-8, 9, size=(20000, 2, 1))  # magnitudes from body rates to moments of inertia
    pairs = rng.normal(size=(20000, 2, 3)) * scale
    got = np.array([cross3(a, b) for a, b in pairs])
    want = np.cross(pairs[:, 0], pairs[:, 1])
    assert np.array_equal(got.view(np.int64), want.view(np.int64))
    assert np.array_equal(cross3([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0])  # x cross y = z
