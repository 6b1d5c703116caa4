"""The receiver as an aircraft in the engagement (docs/receiver.md, "In the engagement"): the
trimmed aircraft holds the straight approach, its probe tip is the mount point moved with the
airframe, the compiled engagement's probe is the aircraft's tip, and the co-simulation converges as
its coupling step is halved."""

import dataclasses
import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from hosedrogue.aircraft import fly, trim
from hosedrogue.aircraft.linear import euler_state
from hosedrogue.engagement.aircraft_receiver import AircraftEngagementStepper, AircraftReceiver, hermite_cubic
from hosedrogue.errors import ParameterError
from hosedrogue.scenarios import load_scenario
from hosedrogue.spec.sections import Receiver

SCENARIO = load_scenario("approach-f16-moderate")
ENG = SCENARIO.engagement


def _stepper(dt, duration, params=SCENARIO.params, bow_wave=ENG.bow_wave, mount=(8.5, 0.0, 0.0)):
    receiver = dataclasses.replace(ENG.receiver, sample_time_s=dt, probe_mount_m=mount)
    return AircraftEngagementStepper(params, duration, control_step_s=dt, reel=ENG.reel, probe=ENG.probe,
                                     bow_wave=bow_wave, receiver=receiver)


def _fly(st, dt, duration, command):
    for k in range(int(round(duration / dt))):
        st.step(receiver=command(k * dt))
        if st.done:
            break
    return st


def test_the_trimmed_aircraft_holds_the_straight_approach():
    """Steady air (no gust, no wake): the aircraft trimmed at the tanker's speed plus the 1 m/s
    closure flies the straight line at the closure speed. The trim leaves accelerations below
    1e-9 m/s^2 (its acceptance), 0.5e-9 t^2 = 1.3e-8 m after 5 s; the attitude within 1e-9 rad."""
    params = SCENARIO.params.replace(turbulence={"enabled": False}, wake={"enabled": False})
    st = _fly(_stepper(0.02, 5.0, params, bow_wave=None), 0.02, 5.0, lambda t: (1.0, 0.0, 0.0))
    assert st.completed
    ac = st.aircraft
    fl = ac.flight()
    start = fl["probe_tip_m"][0]
    straight = start + np.outer(fl["t_s"], [1.0, 0.0, 0.0])
    assert np.abs(fl["probe_tip_m"] - straight).max() < 1.3e-8
    xe = np.array([euler_state(x) for x in fl["state"]])
    assert np.abs(xe[:, 1:9] - xe[0, 1:9]).max() < 1e-9


def test_the_probe_tip_is_the_mount_point_moved_with_the_airframe():
    """The tip against scipy's rotation of the mount by the Euler angles (to round-off of 10 km
    coordinates, 1e-9 m), and its velocity against central differences of the tip's positions
    along a flight with an elevator step and an aileron doublet: their error is O(h^2), so it
    falls 4 times (3.5 allowed: the next term) when h halves."""
    params = SCENARIO.params
    ac = AircraftReceiver(dataclasses.replace(ENG.receiver, probe_mount_m=(8.5, 0.7, -0.4)), params)
    t0 = trim(ac.model, 151.0, 8000.0)
    x0 = t0.state.copy()
    x0[0:3] = -20.0, 0.0, -8000.0
    law = lambda t, x: t0.controls + [0.0, 1.0 if t > 0.2 else 0.0, 2.0 if 0.5 < t < 1.0 else 0.0, 0.0]
    errors = []
    for h in (0.004, 0.002):
        flight = fly(ac.model, x0, law, 2.0, h / 2.0)
        tips = np.array([ac.tip(x, t)[0] for x, t in zip(flight.x, flight.t)])
        vel = np.array([ac.tip(x, t)[1] for x, t in zip(flight.x, flight.t)])
        # independent: NED position plus the mount turned by the Euler angles (scipy), less the tanker's
        for x, t, p in zip(flight.x[::50], flight.t[::50], tips[::50]):
            xe = euler_state(x)
            r = Rotation.from_euler("ZYX", [xe[5], xe[4], xe[3]])
            q = x[0:3] + r.apply(ac.mount) - [ac.V0 * t, 0.0, -ac.altitude]
            assert np.abs(q - p).max() < 1e-9
        # central differences over 2 (h/2) = h, at the times after the controls' last jump
        k = np.arange(int(round(1.2 / (h / 2))), len(flight.t) - 1)
        diff = (tips[k + 1] - tips[k - 1]) / h
        errors.append(np.abs(diff - vel[k]).max())
    assert errors[0] / errors[1] > 3.5


def test_hermite_cubic_meets_both_ends():
    p0, v0, p1, v1, h = np.array([1.0, 2, 3]), np.array([0.5, -1, 2]), np.array([1.2, 1.9, 3.1]), np.array([0.4, -2, 1]), 0.02
    a, j = hermite_cubic(p0, v0, p1, v1, h)
    assert np.allclose(p0 + v0 * h + a * h ** 2 / 2 + j * h ** 3 / 6, p1, atol=1e-14)
    assert np.allclose(v0 + a * h + j * h ** 2 / 2, v1, atol=1e-11)


@pytest.fixture(scope="module")
def coupled():
    """The approach in moderate turbulence with the bow wave, flown with a lateral and vertical
    command that changes every 80 ms, at coupling steps of 80, 40, 20 and 10 ms (the aircraft's
    own flight the same in all: its step and inner loop stay at 10 ms)."""
    def command(t):
        tk = math.floor(t / 0.08 + 1e-9) * 0.08
        return 1.0, 0.5 * math.sin(3.0 * tk), 0.3 * math.cos(2.0 * tk)

    return {dt: _fly(_stepper(dt, 1.6), dt, 1.6, command) for dt in (0.08, 0.04, 0.02, 0.01)}


def test_the_engagement_probe_is_the_aircraft_tip(coupled):
    """At every coupling step's end the compiled engagement's probe is the aircraft's tip (the
    cubic's end, to round-off: 1e-9 m)."""
    st = coupled[0.02]
    res = st.result()
    fl = st.aircraft.flight()
    t, probe = np.asarray(res.t_s), res.probe_position_m
    for i in np.flatnonzero(np.isclose(np.remainder(t + 1e-9, 0.02), 0.0, atol=1e-6)):
        j = int(round(t[i] / 0.01))
        assert np.abs(probe[i] - fl["probe_tip_m"][j]).max() < 1e-9


def test_the_coupling_converges_at_second_order(coupled):
    """The drogue after 1.6 s (the hose feels the aircraft through the bow wave before contact):
    against the 10 ms coupling, its difference falls as h^2 - by (8^2 - 1) / (4^2 - 1) = 4.2 and
    (4^2 - 1) / (2^2 - 1) = 5 - when the step halves (3.5 and 4 allowed: the next order)."""
    drogue = {dt: st.outputs()["joints_m"][-1] for dt, st in coupled.items()}
    e = [np.abs(drogue[dt] - drogue[0.01]).max() for dt in (0.08, 0.04, 0.02)]
    assert e[0] / e[1] > 3.5 and e[1] / e[2] > 4.0


def test_bad_receiver_fields_are_one_line_errors(tmp_path):
    with pytest.raises(ParameterError, match=r"^receiver.model = 'f17': "):
        Receiver(model="f17")
    with pytest.raises(ParameterError, match=r"^receiver.probe_mount_m = \[-1.0, 0.0, 0.0\]: .*forward > 0"):
        Receiver(model="f16", probe_mount_m=(-1.0, 0.0, 0.0))
    with pytest.raises(ParameterError, match=r"^receiver.aircraft_step_s = 0.015: must divide"):
        Receiver(model="f16", aircraft_step_s=0.015)
    with pytest.raises(ParameterError, match=r"^receiver.probe_mount_m"):
        Receiver(model="f16", probe_mount_m=(8.5, 0.0))
    turning = SCENARIO.params.replace(tanker_motion={"bank_deg": 25.0})
    with pytest.raises(ParameterError, match=r"^receiver.model = 'f16': .*straight and level"):
        AircraftReceiver(ENG.receiver, turning)


def test_the_aircraft_flies_in_the_hose_turbulence(coupled):
    """approach-moderate's gusts are uniform: every point sees the tow point's gust. The aircraft's
    wind less its steady part is the gust the hose's air carries at the same time (to round-off),
    and moderate turbulence moves it by more than 0.5 m/s over the run."""
    from hosedrogue.model.chain_loads import still_air_velocity

    st = coupled[0.02]
    ac, model = st.aircraft, st.model
    calm = np.zeros_like(model.gust_values)
    gusts = []
    for x, t in zip(ac.flight()["state"][::10], ac.flight()["t_s"][::10]):
        steady = still_air_velocity(x[0] - ac.V0 * t, x[1], x[2] + ac.altitude, t, model.env, calm)
        hose = np.subtract(still_air_velocity(-3.0, 0.5, 4.0, t, model.env, model.gust_values),
                           still_air_velocity(-3.0, 0.5, 4.0, t, model.env, calm))
        gust = ac.wind_ned(x, t) - np.array(steady) - [ac.V0, 0.0, 0.0]
        assert np.abs(gust - hose).max() < 1e-12
        gusts.append(gust)
    assert np.ptp(np.array(gusts), axis=0).max() > 0.5
