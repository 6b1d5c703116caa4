"""Time simulation of the nonlinear model: fixed-step RK4 (the paper's method) or an adaptive
Runge-Kutta (DOP853) for cross-checks, open loop, with a linear controller in the loop, or with
any Python control-force function ``u(t, x)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.integrate

from .analysis.equilibrium import Equilibrium, solve_equilibrium
from .controllers.linear import LinearController
from .model import kernels as K
from .model.integrate import rk4_run
from .model.system import HoseModel
from .params import PAPER, ParameterError, Params
from .results import SimulationResult

ControlFunction = Callable[[float, np.ndarray], "np.ndarray | tuple[float, float]"]

_STATUS_TEXT = {
    K.NONFINITE: "the state became non-finite (numerical divergence)",
    K.YAW_LIMIT: "a link's yaw passed the limit where the angle coordinates become singular (likely the paper's almost undamped zigzag modes growing in turbulence; for long runs use the model preset: --config converged or [model] preset = \"converged\", docs/long-runs.md)",
    K.STEP_LIMIT: "the adaptive integrator could not meet its tolerance (step size limit)",
}


@dataclass(frozen=True)
class Actuator:
    """Limits on the control force: magnitude per axis [N] and rate [N/s] (inf: none).

    With a finite rate the applied force follows the command through a first-order lag of
    ``time_constant_s`` whose slope is clipped to the rate limit.
    """

    max_force_n: float = math.inf
    max_rate_n_s: float = math.inf
    time_constant_s: float = 0.01

    def __post_init__(self):
        for name in ("max_force_n", "max_rate_n_s", "time_constant_s"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not v > 0 or math.isnan(v):
                raise ParameterError(f"actuator.{name} = {v!r}: must be a number > 0 (inf for no limit)")
        if not math.isfinite(self.time_constant_s):
            raise ParameterError(f"actuator.time_constant_s = {self.time_constant_s!r}: must be finite")

    @property
    def rate_limited(self) -> bool:
        return math.isfinite(self.max_rate_n_s)

    def as_array(self) -> np.ndarray:
        return np.array([self.max_force_n, self.max_force_n, self.max_rate_n_s, self.time_constant_s])


@dataclass(frozen=True)
class Sensor:
    """White position noise on the measured drogue offset: std [m] per sample of ``sample_time_s``."""

    noise_std_m: float = 0.0
    sample_time_s: float = 0.01

    def __post_init__(self):
        if not (self.noise_std_m >= 0 and math.isfinite(self.noise_std_m)):
            raise ParameterError(f"sensor.noise_std_m = {self.noise_std_m!r}: must be a finite number >= 0 m")
        if not (self.sample_time_s > 0 and math.isfinite(self.sample_time_s)):
            raise ParameterError(f"sensor.sample_time_s = {self.sample_time_s!r}: must be a finite number > 0 s")


def simulate(
    params: Params = PAPER,
    duration_s: float = 10.0,
    x0: np.ndarray | None = None,
    control: LinearController | ControlFunction | None = None,
    equilibrium: Equilibrium | None = None,
    actuator: Actuator = Actuator(),
    sensor: Sensor = Sensor(),
    seed: int | None = None,
    model: HoseModel | None = None,
) -> SimulationResult:
    """Simulate the hose-drogue system.

    Parameters
    ----------
    params : Params
        Model, environment and numerics (``params.numerics.integrator``, ``step_s``).
    duration_s : float
        Simulated time [s].
    x0 : array (4n,), optional
        Initial state [q, qd]; default the balance position at rest.
    control : LinearController or callable, optional
        A :class:`LinearController` acting on the drogue's offset from its balance position
        (compiled, fast), or ``u(t, x) -> (u_hor, u_ver)`` [N] (Python, slower).
    equilibrium : Equilibrium, optional
        Reuse a solved balance position.
    seed : int, optional
        Overrides ``params.turbulence.seed`` (and seeds the sensor noise).
    """
    if not (isinstance(duration_s, (int, float)) and math.isfinite(duration_s) and duration_s > 0):
        raise ParameterError(f"duration_s = {duration_s!r}: must be a finite number > 0 s")
    if seed is not None:
        params = params.replace(turbulence={"seed": int(seed)})
    if model is None:
        model = HoseModel(params)
    if equilibrium is None:
        equilibrium = solve_equilibrium(params, model=model)
    n = model.n
    x0 = equilibrium.state if x0 is None else np.asarray(x0, dtype=np.float64)
    if x0.shape != (4 * n,) or not np.all(np.isfinite(x0)):
        raise ParameterError(f"x0: must be a finite array of shape ({4 * n},), got shape {x0.shape}")
    y_ref = equilibrium.drogue_position_m[1:].copy()
    num = params.numerics

    if callable(control) and not isinstance(control, LinearController):
        ts, xs, us, status, t_stop = _run_python_control(model, params, x0, duration_s, control)
    else:
        ctrl = control if control is not None else LinearController.static_zero()
        noise = _sensor_noise(sensor, duration_s, params.turbulence.seed)
        z0 = np.concatenate([x0, np.zeros(ctrl.n_states + (2 if actuator.rate_limited else 0))])
        if num.integrator == "rk4":
            ts, zs, us, status, t_stop = _run_rk4(model, z0, duration_s, ctrl, y_ref, actuator, noise, sensor)
        else:
            ts, zs, us, status, t_stop = _run_adaptive(model, z0, duration_s, ctrl, y_ref, actuator, noise, sensor)
        xs = zs[:, : 4 * n]

    outs = _derived_outputs(model, ts, xs, us)
    completed = status == K.OK
    message = "completed" if completed else f"stopped at t = {t_stop:.4f} s: {_STATUS_TEXT[status]}"
    return SimulationResult(
        t_s=ts,
        states=xs,
        joints_m=outs[0],
        drogue_velocity_m_s=outs[1],
        drogue_drag_n=outs[2],
        tow_force_n=outs[3],
        control_n=us,
        completed=completed,
        message=message,
        equilibrium_m=equilibrium.drogue_position_m.copy(),
        meta={"seed": params.turbulence.seed, "params": params.to_dict()},
    )


def _sensor_noise(sensor: Sensor, duration_s: float, seed: int) -> np.ndarray:
    count = int(math.ceil(duration_s / sensor.sample_time_s)) + 2
    if sensor.noise_std_m == 0.0:
        return np.zeros((1, 2))
    # an independent stream: the sensor noise must not shift the gust draws of the same seed
    rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence([seed, 1])))
    return sensor.noise_std_m * rng.standard_normal((count, 2))


def _steps(params: Params, duration_s: float) -> tuple[float, int, int]:
    h = params.numerics.step_s
    nsteps = int(round(duration_s / h))
    if nsteps < 1:
        raise ParameterError(f"duration_s = {duration_s!r}: shorter than one step ({h} s)")
    return h, nsteps, params.numerics.output_every


def _run_rk4(model, z0, duration_s, ctrl, y_ref, actuator, noise, sensor):
    h, nsteps, every = _steps(model.params, duration_s)
    nsave = nsteps // every + 1
    ts = np.empty(nsave)
    zs = np.empty((nsave, z0.size))
    us = np.empty((nsave, 2))
    u_max = actuator.as_array()
    max_yaw = math.radians(model.params.numerics.max_yaw_deg)
    status, saved, t_stop = rk4_run(
        z0, 0.0, h, nsteps, every, model.l, model.M, model.S, model.J, model.ps, model.env,
        model.gust_values, ctrl.A, ctrl.B, ctrl.C, ctrl.D, y_ref, u_max, noise,
        sensor.sample_time_s, max_yaw, ts, zs, us,
    )
    return ts[:saved], zs[:saved], us[:saved], status, t_stop


def _run_adaptive(model, z0, duration_s, ctrl, y_ref, actuator, noise, sensor):
    from .model.integrate import applied_force, closed_loop_deriv

    num = model.params.numerics
    h_out = num.step_s * num.output_every
    t_eval = np.arange(0.0, duration_s + 0.5 * h_out, h_out)
    t_eval = t_eval[t_eval <= duration_s + 1e-12]
    u_max = actuator.as_array()
    u = np.empty(2)
    args = (model.l, model.M, model.S, model.J, model.ps, model.env, model.gust_values,
            ctrl.A, ctrl.B, ctrl.C, ctrl.D, y_ref, u_max, noise, sensor.sample_time_s,
            K.make_workspace(model.n))
    max_yaw = math.radians(num.max_yaw_deg)
    n = model.n

    def f(t, z):
        dz = np.empty_like(z)
        closed_loop_deriv(t, z, *args, dz, u)
        return dz

    def yaw_event(t, z):
        return max_yaw - np.max(np.abs(z[1 : 2 * n : 2]))

    yaw_event.terminal = True
    sol = scipy.integrate.solve_ivp(f, (0.0, duration_s), z0, method="DOP853", t_eval=t_eval,
                                    rtol=num.rtol, atol=num.atol, events=yaw_event)
    zs = sol.y.T.copy()
    ts = sol.t.copy()
    us = np.empty((ts.size, 2))
    for i in range(ts.size):
        applied_force(ts[i], zs[i], 4 * n, model.l, ctrl.C, ctrl.D, y_ref, u_max, noise,
                      sensor.sample_time_s, u)
        us[i] = u
    if sol.status == 1:
        return ts, zs, us, K.YAW_LIMIT, float(sol.t_events[0][0])
    if sol.status < 0:
        return ts, zs, us, K.STEP_LIMIT, float(ts[-1] if ts.size else 0.0)
    if not np.all(np.isfinite(zs)):
        return ts, zs, us, K.NONFINITE, float(ts[-1])
    return ts, zs, us, K.OK, duration_s


def _run_python_control(model, params, x0, duration_s, control):
    """RK4 with a Python control function: the right-hand side stays compiled."""
    h, nsteps, every = _steps(params, duration_s)
    max_yaw = math.radians(params.numerics.max_yaw_deg)
    n = model.n
    x = x0.copy()
    ts, xs, us = [0.0], [x.copy()], []

    def u_of(t, state):
        u = np.asarray(control(t, state), dtype=np.float64).reshape(2)
        return u

    def f(t, state):
        return model.derivative(t, state, u_of(t, state))

    us.append(u_of(0.0, x))
    for step in range(1, nsteps + 1):
        t = (step - 1) * h
        k1 = f(t, x)
        k2 = f(t + h / 2, x + h / 2 * k1)
        k3 = f(t + h / 2, x + h / 2 * k2)
        k4 = f(t + h, x + h * k3)
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        t = step * h
        if not np.all(np.isfinite(x)):
            return np.array(ts), np.array(xs), np.array(us), K.NONFINITE, t
        if np.max(np.abs(x[1 : 2 * n : 2])) > max_yaw:
            return np.array(ts), np.array(xs), np.array(us), K.YAW_LIMIT, t
        if step % every == 0:
            ts.append(t)
            xs.append(x.copy())
            us.append(u_of(t, x))
    return np.array(ts), np.array(xs), np.array(us), K.OK, duration_s


def _derived_outputs(model: HoseModel, ts, xs, us):
    n = model.n
    N = ts.size
    joints = np.empty((N, n + 1, 3))
    vel = np.empty((N, 3))
    drag = np.empty((N, 3))
    tow = np.empty((N, 3))
    K.outputs_series(np.ascontiguousarray(ts), np.ascontiguousarray(xs), np.ascontiguousarray(us),
                     model.l, model.M, model.S, model.J, model.ps, model.env, model.gust_values,
                     joints, vel, drag, tow)
    return joints, vel, drag, tow
