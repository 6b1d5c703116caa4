"""The receiver as an aircraft in the engagement (``[receiver] model``; docs/receiver.md, "In the
engagement"): a co-simulation of the aircraft and the hose at the control step.

Every control step the aircraft (:mod:`hosedrogue.aircraft`, in the package's ICAO air) is flown
over the step first - RK4 at ``aircraft_step_s``, its inner loop (:mod:`hosedrogue.aircraft.autopilot`)
sampled at the same period and tracking the docking controller's held velocity command, the wind
at its centre of gravity the hose's air there (free stream, the tanker's wake and the same gust
record, ``uniform`` or ``frozen`` as the scenario says) - and the probe tip's path over the step is
then the cubic in time through the tip's position and velocity at both ends (cubic Hermite; the
tip is the mount point ``probe_mount_m`` moved with the airframe), fed to the compiled engagement
as the FMU's probe path is (``EP_FEED``). The bow wave's source keeps its offset from the tip in
body axes, turned with the aircraft's attitude: held over each step at the mean of the offsets at
its two ends (second order in the step).

The coupling is one way: the probe's load on the drogue is not applied to the aircraft (the
largest of 100 approaches in moderate turbulence, 1738 N, is 1.9 % of the F-16's 91.2 kN weight).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..aircraft.autopilot import design_inner_loop
from ..aircraft.dynamics import derivative, wind_angles
from ..aircraft.linear import euler_state
from ..aircraft.model_file import load_model
from ..aircraft.rigid_body import cross3, dcm_body_from_ned, euler_from_quaternion, normalized, quaternion_from_euler
from ..aircraft.trim import trim
from ..errors import ParameterError
from ..jsonio import plain
from ..model import layout as LY
from ..model.chain_loads import still_air_velocity
from ..results.run import EngagementResult, stop_message
from ..spec.params import Params
from ..spec.sections import Receiver
from .stepper import EngagementStepper


#: The starts trimmed in this process (the trim and the inner loop's design, about a second of
#: CPU), by everything they depend on: a campaign's runs differ only in their gusts, which the
#: start leaves out, so they share one.
_STARTS: dict = {}


def hermite_cubic(p0, v0, p1, v1, h: float):
    """The cubic p(s) = p0 + v0 s + a s^2 / 2 + j s^3 / 6 through (p0, v0) at s = 0 and (p1, v1)
    at s = h: its acceleration a at 0 and its jerk j.

    Parameters
    ----------
    p0, v0, p1, v1 : numpy.ndarray
        (3,) positions [m] and velocities [m/s].
    h : float
        The interval [s].

    Returns
    -------
    a, j : numpy.ndarray
        (3,) [m/s^2], [m/s^3].
    """
    dp = np.asarray(p1) - np.asarray(p0)
    return (6.0 * dp - 2.0 * h * (2.0 * v0 + v1)) / h ** 2, (-12.0 * dp + 6.0 * h * (v0 + v1)) / h ** 3


class AircraftReceiver:
    """The aircraft flying behind the tanker: its state, its inner loop's reference and its flight so far.

    Parameters
    ----------
    receiver : Receiver
        ``model``, ``probe_mount_m``, ``aircraft_step_s``, ``max_speed_m_s`` (bounds the command).
    params : Params
        The flight (airspeed [m/s], altitude [m]) the tanker and the hose fly.
    """

    def __init__(self, receiver: Receiver, params: Params):
        if not params.tanker_motion.is_level:
            raise ParameterError(f"receiver.model = {receiver.model!r}: the aircraft receiver flies behind a tanker "
                                 "in straight and level flight; remove [tanker_motion]")
        self.model = dataclasses.replace(load_model(receiver.model), atmosphere="icao")
        self.source = receiver.model
        self.mount = np.asarray(receiver.probe_mount_m, dtype=np.float64)
        self.h = receiver.aircraft_step_s
        self.vmax = np.asarray(receiver.max_speed_m_s, dtype=np.float64)
        self.V0, self.altitude = params.flight.airspeed_m_s, params.flight.altitude_m
        self._design: tuple | None = None

    # --- frames ------------------------------------------------------------------------------
    def tip(self, x: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
        """The probe tip's position and velocity [m, m/s] in the tanker frame S_p for the state x at time t."""
        c_nb = dcm_body_from_ned(x[6:10]).T
        p = x[0:3] + c_nb @ self.mount - np.array([self.V0 * t, 0.0, -self.altitude])
        v = c_nb @ (x[3:6] + cross3(x[10:13], self.mount)) - np.array([self.V0, 0.0, 0.0])
        return p, v

    def euler(self, x: np.ndarray) -> np.ndarray:
        """The inner loop's Euler-angle state of x: north, east and altitude the probe tip's (NED, inertial)."""
        xe = euler_state(x)
        tip = x[0:3] + dcm_body_from_ned(x[6:10]).T @ self.mount
        xe[9:12] = tip[0], tip[1], -tip[2]
        return xe

    def wind_ned(self, x: np.ndarray, t: float) -> np.ndarray:
        """The wind at the centre of gravity [m/s] (NED: the tanker's S_p while it flies level, north)."""
        wx, wy, wz = still_air_velocity(x[0] - self.V0 * t, x[1], x[2] + self.altitude, t, self.env, self.gust)
        return np.array([wx + self.V0, wy, wz])

    # --- the start ---------------------------------------------------------------------------
    def start(self, tip_m: np.ndarray, closure_m_s: float, env: np.ndarray, gust: np.ndarray, gravity: float) -> None:
        """Trim the aircraft at its start: the probe tip at ``tip_m`` in S_p, moving forward at the
        closure speed, at its own altitude (the tanker's less its centre of gravity's depth in
        S_p), in the steady air there (the gust-free air: free stream and wake), and design the
        inner loop about that trim (once per process and start: the trim does not depend on the seed).

        Parameters
        ----------
        tip_m : numpy.ndarray
            (3,) the probe's start point [m] in S_p.
        closure_m_s : float
            Forward speed relative to the tanker at the start [m/s].
        env, gust : numpy.ndarray
            The engagement model's air (``model.env``) and gust record (``model.gust_values``).
        gravity : float
            [m/s^2], the hose's.
        """
        self.env, self.gust, self.g = env, gust, gravity
        if self._design is None:
            tip = np.asarray(tip_m, dtype=np.float64)
            key = (self.source, tuple(self.mount), self.h, self.V0, self.altitude, tuple(tip), float(closure_m_s),
                   float(gravity), env.tobytes())
            if key not in _STARTS:
                if len(_STARTS) >= 8:
                    _STARTS.pop(next(iter(_STARTS)))
                _STARTS[key] = self._trim(tip, closure_m_s)
            self._design = _STARTS[key]
            self.gust = gust
        x0, loop, ref = self._design
        self.x, self.loop = x0.copy(), loop
        self.xe0 = ref.copy()
        self.r = np.array([ref[9], ref[10], -ref[11]])  # the tip's reference point, NED
        self.t, self.cmd0 = 0.0, np.array([closure_m_s, 0.0, 0.0])
        self.times, self.states, self.controls = [0.0], [self.x.copy()], [loop.trim.controls.copy()]

    def _trim(self, tip: np.ndarray, closure: float):
        """(x0, inner loop, reference Euler state) of the start (see :meth:`start`)."""
        self.gust = np.zeros_like(self.gust)  # the steady air at the start
        cg = tip - self.mount
        # the centre of gravity depends on the attitude the trim finds, and the air there on it: a
        # fixed point that converges about 25 times per pass behind the tanker (1.4 m, 0.06 m, ...;
        # three passes left 9e-5 m, the start 6e-5 m/s off its trimmed airspeed in the wake's
        # gradient); to 1e-9 m, seven passes
        for _ in range(20):
            x = np.zeros(14)
            x[0:3] = cg[0], cg[1], cg[2] - self.altitude
            wind = self.wind_ned(x, 0.0)
            v_air = np.array([self.V0 + closure, 0.0, 0.0]) - wind
            airspeed = float(np.linalg.norm(v_air))
            t = trim(self.model, airspeed, self.altitude - cg[2], climb_deg=math.degrees(math.asin(-v_air[2] / airspeed)),
                     gravity=self.g)
            psi = math.atan2(v_air[1], v_air[0])
            q = quaternion_from_euler(t.bank_rad, t.theta_rad, psi)
            c_bn = dcm_body_from_ned(q)
            cg, moved = tip - c_bn.T @ self.mount, cg
            if np.abs(cg - moved).max() < 1e-9:
                break
        else:
            raise ParameterError(f"receiver.model = {self.source!r}: no trimmed start with the probe tip at {tip.tolist()} m "
                                 f"(its centre of gravity still moves {np.abs(cg - moved).max():.3g} m after 20 passes)")
        x = t.state.copy()
        x[0:3] = cg[0], cg[1], cg[2] - self.altitude
        x[6:10] = q
        x[3:6] = c_bn @ np.array([self.V0 + closure, 0.0, 0.0])
        loop = design_inner_loop(t, self.h, self.mount)
        return x, loop, self.euler(x)

    # --- flying ------------------------------------------------------------------------------
    def reference(self, cmd: np.ndarray) -> np.ndarray:
        """The inner loop's reference Euler state for the held command ``cmd`` (S_p velocity [m/s])."""
        ref = self.xe0.copy()
        vx = self.V0 + cmd[0]
        ref[0] = math.sqrt(vx * vx + cmd[1] ** 2 + cmd[2] ** 2)
        ref[4] += math.atan2(-cmd[2], vx) - math.atan2(-self.cmd0[2], self.V0 + self.cmd0[0])
        ref[5] += math.atan2(cmd[1], vx) - math.atan2(self.cmd0[1], self.V0 + self.cmd0[0])
        ref[9:12] = self.r[0], self.r[1], -self.r[2]
        return ref

    def fly(self, cmd, duration_s: float) -> None:
        """Fly ``duration_s`` (whole aircraft steps) with the velocity command ``cmd`` held (clipped
        to the receiver's speed bounds): RK4 with the wind of each stage, the inner loop sampled at
        every step, the reference point moving at the command."""
        cmd = np.clip(np.asarray(cmd, dtype=np.float64), -self.vmax, self.vmax)
        h = self.h
        vel = cmd + np.array([self.V0, 0.0, 0.0])
        for _ in range(int(round(duration_s / h))):
            u = self.loop.controls(self.euler(self.x), self.reference(cmd))
            t, x = self.t, self.x

            def f(tt, xx):
                return derivative(self.model, xx, u, self.g, self.wind_ned(xx, tt))

            k1 = f(t, x)
            k2 = f(t + 0.5 * h, x + 0.5 * h * k1)
            k3 = f(t + 0.5 * h, x + 0.5 * h * k2)
            k4 = f(t + h, x + h * k3)
            self.x = normalized(x + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4))
            self.r = self.r + h * vel
            self.t = t + h
            self.times.append(self.t)
            self.states.append(self.x.copy())
            self.controls.append(u)
            if not np.all(np.isfinite(self.x)):
                raise FloatingPointError(f"the aircraft's state is no longer finite at t = {self.t:.4f} s")

    def flight(self) -> dict:
        """The aircraft's flight so far: ``t_s`` (n,), ``state`` (n, 14)
        (:data:`hosedrogue.aircraft.dynamics.STATE_NAMES`), ``controls`` (n, 4) (row 0 the trim's,
        row k > 0 those held over the step that ends at ``t_s[k]``), ``probe_tip_m`` (n, 3) in S_p.

        Returns
        -------
        dict
        """
        t, x = np.array(self.times), np.array(self.states)
        return {"t_s": t, "state": x, "controls": np.array(self.controls),
                "probe_tip_m": np.array([self.tip(xi, ti)[0] for xi, ti in zip(x, t)])}


    def columns(self, t_s: np.ndarray) -> dict[str, np.ndarray]:
        """The aircraft's time series at the run's output times ``t_s`` (:data:`COLUMNS`): the
        state interpolated linearly between the aircraft's steps (the quaternion normalized
        again; at an output time on the aircraft's grid, the state itself), the controls those
        the inner loop holds from that time on (the last step's at the end).

        Parameters
        ----------
        t_s : numpy.ndarray
            (N,) output times [s] within the flight so far.

        Returns
        -------
        dict
            Column name -> (N,) array, in :data:`COLUMNS` order.
        """
        t, x, u = np.array(self.times), np.array(self.states), np.array(self.controls)
        xs = np.column_stack([np.interp(t_s, t, x[:, i]) for i in range(x.shape[1])])
        # the step that starts at each output time (a millionth of a step's slack for the sum of steps' round-off)
        k = np.minimum(np.searchsorted(t, np.asarray(t_s) + 1e-6 * self.h, side="right"), len(t) - 1)
        rows = []
        for xi, ti in zip(xs, t_s):
            xi = normalized(xi)
            att = euler_from_quaternion(xi[6:10])
            air = wind_angles(xi[3:6] - dcm_body_from_ned(xi[6:10]) @ self.wind_ned(xi, ti))
            rows.append((*(xi[0:3] - np.array([self.V0 * ti, 0.0, -self.altitude])), *att, *air))
        a = np.array(rows).reshape(-1, 9)
        cols = dict(zip(COLUMNS[:9], a.T))
        cols["aircraft_throttle"] = u[k, 0]
        for i, name in enumerate(COLUMNS[10:], start=1):
            cols[name] = np.radians(u[k, i])
        return cols

    def summary(self, cols: dict[str, np.ndarray]) -> dict:
        """What ``run.json`` records of the aircraft (``"aircraft"``): its model, the trim it
        started from (:meth:`hosedrogue.aircraft.trim.Trim.as_dict`, degrees) and the largest
        departure of its attitude, airspeed, angle of attack and throttle from their values at
        the start over the run's output times (``cols``, :meth:`columns`).

        Returns
        -------
        dict
            Strict-JSON ready (:func:`hosedrogue.jsonio.plain`).
        """
        peaks = {}
        for stem, unit in (("roll", "_rad"), ("pitch", "_rad"), ("yaw", "_rad"), ("airspeed", "_m_s"),
                           ("alpha", "_rad"), ("beta", "_rad"), ("throttle", "")):
            c = cols[f"aircraft_{stem}{unit}"]
            peaks[f"peak_{stem}_change{unit}"] = float(np.max(np.abs(c - c[0])))
        return plain({"model": self.source, "probe_mount_m": self.mount.tolist(), "step_s": self.h,
                      "trim": self.loop.trim.as_dict(), **peaks})


#: The aircraft's columns after the engagement's (timeseries.csv; SI, the units in the names): its
#: centre of gravity in S_p, its attitude (roll, pitch, yaw from S_p's axes), airspeed, angle of
#: attack and sideslip in the air there, the throttle (0-1) and the surfaces' deflections (signed
#: as the model's tables define them).
COLUMNS = ("aircraft_x_m", "aircraft_y_m", "aircraft_z_m", "aircraft_roll_rad", "aircraft_pitch_rad",
           "aircraft_yaw_rad", "aircraft_airspeed_m_s", "aircraft_alpha_rad", "aircraft_beta_rad",
           "aircraft_throttle", "aircraft_elevator_rad", "aircraft_aileron_rad", "aircraft_rudder_rad")


@dataclasses.dataclass(frozen=True, kw_only=True)
class AircraftEngagementResult(EngagementResult):
    """An :class:`~hosedrogue.results.run.EngagementResult` whose receiver was an aircraft: its
    time series after the engagement's (:data:`COLUMNS`), its summary in ``meta["aircraft"]``."""

    aircraft_columns: dict  #: column name -> (N,) array at ``t_s`` (:data:`COLUMNS`)

    def extra_columns(self) -> dict[str, np.ndarray]:
        """The engagement's columns, then the aircraft's."""
        return {**super().extra_columns(), **self.aircraft_columns}


class AircraftEngagementStepper(EngagementStepper):
    """:class:`~hosedrogue.engagement.stepper.EngagementStepper` whose probe is the aircraft's (see
    the module's docstring): :meth:`step`'s ``receiver`` command is the inner loop's velocity
    command.

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and numerics (the flight straight and level).
    duration_s : float
        Length of the run [s].
    receiver : Receiver
        With a ``model``; ``aircraft_step_s`` [s] must divide the control step.
    **options
        The other keyword arguments of the stepper (``control_step_s``, ``reel``, ``probe``,
        ``bow_wave``, ...), not ``receiver_pass_through``: the aircraft feeds the probe's path.
    """

    def __init__(self, params: Params, duration_s: float, *, receiver: Receiver, **options):
        self.aircraft = AircraftReceiver(receiver, params)
        super().__init__(params, duration_s, receiver=receiver, receiver_pass_through=True, **options)
        steps = self.control_step_s / receiver.aircraft_step_s
        if abs(steps - round(steps)) > 1e-9 * steps:
            raise ParameterError(f"receiver.aircraft_step_s = {receiver.aircraft_step_s!r}: must divide the control "
                                 f"step {self.control_step_s!r} s a whole number of times")

    def _restart(self, seed) -> None:
        super()._restart(seed)
        ep = self.run.ep
        if not hasattr(self, "_bow_body"):
            self._bow_body = ep[[LY.EP_BW_DX, LY.EP_BW_DY, LY.EP_BW_DZ]].copy()
        tip = ep[[LY.EP_P0X, LY.EP_P0Y, LY.EP_P0Z]].copy()
        self.aircraft.start(tip, float(ep[LY.EP_VC]), self.model.env, self.model.gust_values,
                            float(self.model.ps[LY.PS_G]))

    def _on_chain(self) -> None:
        super()._on_chain()
        # the recorded outputs read the tip from the receiver's states, which follow the fed path
        # (RK4 integrates its quadratic velocity exactly), not from the record's copy of the
        # parameters, whose fed cubic is that of the step the record began in
        self._rec_ep[LY.EP_FEED] = 0.0

    def _advance(self) -> None:
        ac = self.aircraft
        h = min(self.spc, self.total_steps - self.step_index) * self.h
        t0 = self.t_s
        p0, v0 = ac.tip(ac.x, t0)
        ep = self.run.ep
        bow0 = dcm_body_from_ned(ac.x[6:10]).T @ self._bow_body
        try:
            ac.fly(self._commands[list(self._slots["receiver"])], h)
        except (FloatingPointError, ValueError, ZeroDivisionError, ParameterError) as exc:
            self._finish(False, stop_message(self._last_kept_s(), f"the receiver aircraft: {exc}", t0))
            return
        p1, v1 = ac.tip(ac.x, ac.t)
        if ep[LY.EP_BW] != LY.BW_OFF:  # held over the step at the mean of its ends: second order in the step
            ep[[LY.EP_BW_DX, LY.EP_BW_DY, LY.EP_BW_DZ]] = 0.5 * (bow0 + dcm_body_from_ned(ac.x[6:10]).T @ self._bow_body)
        a, j = hermite_cubic(p0, v0, p1, v1, h)
        self.move_receiver(v0, a, j)
        super()._advance()

    def result(self) -> AircraftEngagementResult:
        """The run so far (:meth:`EngagementStepper.result`) with the aircraft's time series and summary.

        Returns
        -------
        AircraftEngagementResult
        """
        res = super().result()
        cols = self.aircraft.columns(res.t_s)
        fields = {f.name: getattr(res, f.name) for f in dataclasses.fields(res)}
        fields["meta"] = {**res.meta, "aircraft": self.aircraft.summary(cols)}
        return AircraftEngagementResult(**fields, aircraft_columns=cols)
