"""The receiver's inner loop (docs/receiver.md, "The inner loop"): it stabilizes the F-16 - at
150 m/s and 3000 m (xcg 0.35) statically unstable, at the approach scenarios' 151 m/s and 8000 m
stable but, like every aircraft, neutral in position and heading - and its gain is the one its
sampled loop is stable with."""

import dataclasses

import control
import numpy as np
import pytest

from hosedrogue.aircraft import load_model, trim
from hosedrogue.aircraft.autopilot import design_inner_loop, point_transform
from hosedrogue.aircraft.linear import body_state, euler_state
from hosedrogue.aircraft.rigid_body import dcm_body_from_ned

MOUNT = np.array([8.5, 0.7, -0.4])


F16 = dataclasses.replace(load_model("f16"), atmosphere="icao")


@pytest.fixture(scope="module")
def loop():
    return design_inner_loop(trim(F16, 151.0, 8000.0), 0.01, MOUNT)


@pytest.mark.parametrize("airspeed, altitude, unstable", [(151.0, 8000.0, 0.0), (150.0, 3000.0, 0.1)])
def test_the_inner_loop_stabilizes_the_f16(airspeed, altitude, unstable):
    """Open loop: north, east and heading are integrators (eigenvalues 0 to the differences'
    round-off, 1e-9) and at 3000 m the short period has a root above 0.1 1/s (0.133, docs/receiver.md);
    closed loop: every root in the left half-plane."""
    loop = design_inner_loop(trim(F16, airspeed, altitude), 0.01, MOUNT)
    assert np.linalg.eigvals(loop.linear.A).real.max() > unstable - 1e-9
    assert loop.poles.real.max() < -0.1


def test_the_sampled_loop_is_stable(loop):
    # the sampled loop, formed here from the ZOH model and the gain (not dlqr's own poles)
    T = point_transform(loop.trim, MOUNT)
    sysd = control.c2d(control.ss(T @ loop.linear.A @ np.linalg.inv(T), T @ loop.linear.B, np.eye(13), 0.0), 0.01)
    z = np.linalg.eigvals(sysd.A - sysd.B @ loop.K)
    assert np.abs(z).max() < 1.0
    # dlqr's poles are the same: log(z) / T sorted alike; 1e-6 1/s is far above the round-off of an
    # eigenvalue solve and a complex log (about 1e-13 of the poles, up to 17 1/s) and far below their spacing
    assert np.allclose(np.sort_complex(np.log(z.astype(complex)) / 0.01), np.sort_complex(loop.poles), atol=1e-6)


def test_the_held_point_is_the_mount_point_to_first_order(loop):
    """T's attitude columns against the point's offset C_NB lever evaluated exactly: a change of
    1e-4 rad leaves a second-order remainder of about lever * 1e-8 = 1e-7 m."""
    T = point_transform(loop.trim, MOUNT)
    xe0 = euler_state(loop.trim.state)

    def point(xe):
        x = body_state(xe)
        p = x[0:3] + dcm_body_from_ned(x[6:10]).T @ MOUNT
        return np.array([p[0], p[1], -p[2]])

    for i in (3, 4, 5):
        d = np.zeros(13)
        d[i] = 1e-4
        # the rotation's second-order term: mount arm 8.5 m x (1e-4 rad)^2 = 8.5e-8 m, bounded by 2e-7 m
        assert np.allclose(point(xe0 + d) - point(xe0), (T @ d)[9:12], atol=2e-7)
