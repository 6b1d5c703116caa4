"""Time simulation of the nonlinear model: fixed-step RK4 (the paper's method) or an adaptive
Runge-Kutta (DOP853) for cross-checks, open loop, with a linear controller in the loop, or with
any Python control-force function ``u(t, x)``.

The compiled paths hand the kernels the model's arrays (:meth:`HoseModel.kernel_args`) and the
closed loop's (:func:`hosedrogue.model.integrate.loop_arrays`); the Python-control path takes the same RK4
step (:func:`hosedrogue.model.steppers.rk4`) as a plain Python function over the model's derivative.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
import scipy.integrate

from ..analysis.equilibrium import Equilibrium, solve_equilibrium
from ..controllers.linear import LinearController
from ..model import drogue_actuator as DA
from ..results.surfaces import surface_fields
from ..controllers.sampled import SampledController
from ..model import chain_dynamics as CD, layout as LY
from ..model.integrate import (LoopArrays, applied_force, closed_loop_deriv, loop_arrays, loop_states, rk4_run,
                               sensor_noise, step_status)
from ..model.status import status_text
from ..model.steppers import rk4
from ..model.system import HoseModel
from ..spec.params import PAPER, Actuator, ParameterError, Params, Sensor
from ..spec.sections import Controller
from ..results.statistics import turbulence_window
from ..results.run import SimulationResult, stop_message
from .budget import check_duration, check_integrator, check_run

ControlFunction = Callable[[float, np.ndarray], "np.ndarray | tuple[float, float]"]


def simulate(
    params: Params = PAPER,
    duration_s: float = 10.0,
    x0: np.ndarray | None = None,
    control: LinearController | SampledController | ControlFunction | None = None,
    equilibrium: Equilibrium | None = None,
    actuator: Actuator = Actuator(),
    sensor: Sensor = Sensor(),
    seed: int | None = None,
    model: HoseModel | None = None,
    sample_time_s: float = 0.0,
    drogue_actuator=None,
) -> SimulationResult:
    """Simulate the hose-drogue system.

    Parameters
    ----------
    params : Params
        Model, environment and numerics (``params.numerics.integrator``, ``step_s`` [s]).
    duration_s : float
        Simulated time [s].
    x0 : array (4n,), optional
        Initial state [q, qd] [rad, rad/s]; default the balance position at rest.
    control : LinearController, SampledController, Controller or callable, optional
        A :class:`LinearController` acting on the drogue's offset [m] from its balance position
        (compiled, fast; sampled-data with ``sample_time_s`` > 0); a sampled-data drogue
        controller of the user (a :class:`~hosedrogue.controllers.sampled.SampledController` of
        role ``"drogue"``, or a ``Controller(type="python", ...)``; called every sample time with
        the measurement, its force held in between: docs/controllers.md); or ``u(t, x) ->
        (u_hor, u_ver)`` [N] of time [s] and state, called at every RK4 stage (Python, slower;
        fixed-step RK4 only, no actuator or sensor model).
    equilibrium : Equilibrium, optional
        Reuse a solved balance position.
    actuator : Actuator
        Force [N] and rate [N/s] limits of the control force.
    sensor : Sensor
        Noise [m] on the measured drogue offset.
    seed : int, optional
        Overrides ``params.turbulence.seed`` (and seeds the sensor noise).
    model : HoseModel, optional
        Reuse a model built from ``params`` (ignored parameters otherwise).
    sample_time_s : float
        With a :class:`LinearController`: 0 (continuous, the default), or its zero-order-hold
        discretization called every ``sample_time_s`` [s] (a whole multiple of the RK4 step),
        compiled end to end, the sensor's delay included.
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue steers itself with these control surfaces: the controller's force command
        (continuous or sampled) is mixed to them at the dynamic pressure at the drogue, and their
        deflections make the force (docs/model.md §10); with ``command = "deflection"`` a user's
        sampled-data controller commands the deflections [rad] itself. ``actuator`` must then
        have no limits. Not with a Python ``control`` function.

    Returns
    -------
    SimulationResult
        The saved time series; ``completed`` is False when the run stopped early.
    """
    check_duration(duration_s)
    check_run(params, duration_s)  # its step and output grids reach duration_s; its output fits in memory
    if seed is not None:
        params = params.replace(turbulence={"seed": int(seed)})
    if model is None:
        model = HoseModel(params, duration_s=duration_s)
    elif not model.gusts_cover(duration_s):
        raise ParameterError(f"model: its gust record ends at {model.gusts.t_off_s:g} s, before the run's "
                             f"{duration_s:g} s; build it with HoseModel(params, duration_s={duration_s:g})")
    if equilibrium is None:
        equilibrium = solve_equilibrium(params, model=model)
    nh = model.state_size  # 4n, or 6n for elastic links
    check_integrator(model.params, "fixed-length")
    x0 = equilibrium.state if x0 is None else np.asarray(x0, dtype=np.float64)
    if x0.shape != (nh,) or not np.all(np.isfinite(x0)):
        raise ParameterError(f"x0: must be a finite array of shape ({nh},), got shape {x0.shape}")
    y_ref = equilibrium.drogue_position_m[1:].copy()
    control = sampled_controller(control)
    if model.elastic and (isinstance(control, SampledController) or sample_time_s):
        raise ParameterError("controller: a sampled-data controller runs the rigid fixed-length chain "
                             "(hose.axial_stiffness_n = inf); an elastic hose takes a continuous controller")
    if isinstance(control, SampledController):
        return _run_sampled(params, duration_s, x0, control, equilibrium, actuator, sensor, model, drogue_actuator)
    if sample_time_s:
        if not isinstance(control, LinearController):
            raise ParameterError(f"sample_time_s = {sample_time_s!r}: a sampled-data built-in controller needs "
                                 "control = a LinearController")
        return _run_linear_sampled(params, duration_s, x0, control, equilibrium, actuator, sensor, model,
                                   sample_time_s, drogue_actuator)

    outs = None  # derived outputs: the compiled RK4 loop saves them with the states
    surfaces = {}
    if callable(control) and not isinstance(control, LinearController):
        if drogue_actuator is not None:
            raise ParameterError("drogue_actuator: a Python control function commands the force itself; give a "
                                 "LinearController to command the drogue's control surfaces")
        ts, xs, us, status, t_stop = _run_python_control(model, params, x0, duration_s, control)
    else:
        ts, xs, us, status, t_stop, outs, surfaces = _run_compiled(model, params, x0, duration_s, control, y_ref,
                                                                   actuator, sensor, drogue_actuator)

    if outs is None:
        outs = _derived_outputs(model, ts, xs, us)
    completed = status == LY.OK
    message = "completed" if completed else stop_message(float(ts[-1]), status_text(status, params), t_stop)
    return SimulationResult(
        t_s=ts,
        states=xs,
        joints_m=outs[0],
        drogue_position_m=outs[0][:, -1, :],
        drogue_velocity_m_s=outs[1],
        drogue_drag_n=outs[2],
        tow_force_n=outs[3],
        exit_tension_n=outs[4],
        control_force_n=us,
        completed=completed,
        message=message,
        equilibrium_m=equilibrium.drogue_position_m.copy(),
        meta={"seed": params.turbulence.seed, "params": params.to_dict()},
        statistics_window_s=turbulence_window(params.turbulence),
        **surfaces,
    )


def sampled_controller(control):
    """``control`` with a ``Controller(type="python")`` section turned into its
    :class:`~hosedrogue.controllers.sampled.SampledController` (anything else as it is).

    Parameters
    ----------
    control : Any
        What :func:`simulate` was given.

    Returns
    -------
    Any
    """
    if isinstance(control, Controller):
        if control.type != "python":
            raise ParameterError(f"control = Controller(type={control.type!r}): give the designed LinearController "
                                 "(hosedrogue.run designs the scenario's), or a Controller of type 'python'")
        return SampledController("drogue", control.entry, control.sample_time_s, dict(control.options))
    if isinstance(control, SampledController) and control.role != "drogue":
        raise ParameterError(f"control: a {control.role} controller; the drogue's controller has role 'drogue'")
    return control


def _run_sampled(params, duration_s, x0, control: SampledController, equilibrium, actuator, sensor,
                 model, drogue_actuator) -> SimulationResult:
    """A user's sampled-data drogue controller: the stepper driven by it (:mod:`.drive`)."""
    from .drive import control_step, drive
    from .stepper import FixedLengthStepper

    built = {"drogue": control.build()}  # a bad entry or factory is an error before the run
    dt = control_step({"drogue": control}, params.numerics.step_s)
    stepper = FixedLengthStepper(params, duration_s, control_step_s=dt, x0=x0, equilibrium=equilibrium,
                                 actuator=actuator, sensor=sensor, model=model, drogue_actuator=drogue_actuator)
    return drive(stepper, {"drogue": control}, built)


def _run_linear_sampled(params, duration_s, x0, control: LinearController, equilibrium, actuator, sensor, model,
                        sample_time_s, drogue_actuator) -> SimulationResult:
    """A built-in linear controller in sampled-data mode, compiled end to end
    (:meth:`hosedrogue.simulation.stepper.FixedLengthStepper.run_linear`)."""
    from .stepper import FixedLengthStepper

    if drogue_actuator is not None:
        drogue_actuator.check_force_command()
    stepper = FixedLengthStepper(params, duration_s, control_step_s=sample_time_s, x0=x0, equilibrium=equilibrium,
                                 actuator=actuator, sensor=sensor, model=model, drogue_actuator=drogue_actuator)
    return stepper.run_linear(control)


def _run_compiled(model, params, x0, duration_s, control, y_ref, actuator, sensor, drogue_actuator):
    """The compiled closed loop (RK4 or DOP853) with a linear controller (or none) and, if given,
    the drogue's control surfaces; returns (ts, xs, us, status, t_stop, outs or None, the
    surfaces' result fields)."""
    if drogue_actuator is not None:
        drogue_actuator.check_hose(params.hose.axial_stiffness_n)  # the surfaces' kernels: rigid links
        drogue_actuator.check_loop(actuator == Actuator(), None)  # the surfaces make the force, its limits
        drogue_actuator.check_force_command()
        if params.numerics.integrator == "rk4":
            drogue_actuator.check_step(params.numerics.step_s)
    n = model.n
    ctrl = control if control is not None else LinearController.static_zero()
    noise = sensor_noise(sensor, duration_s, params.turbulence.seed)
    loop = loop_arrays(ctrl, y_ref, actuator, noise, sensor.sample_time_s, drogue_actuator)
    z0 = closed_loop_state(x0, ctrl, actuator, drogue_actuator)
    outs = None
    if model.elastic:
        ts, zs, us, status, t_stop, outs = _run_elastic(model, z0, duration_s, loop)
    elif params.numerics.integrator == "rk4":
        ts, zs, us, status, t_stop, outs = _run_rk4(model, z0, duration_s, loop)
    else:
        ts, zs, us, status, t_stop = _run_adaptive(model, z0, duration_s, loop)
    surfaces = {}
    if drogue_actuator is not None:
        ns, na = drogue_actuator.surfaces, 4 * n + ctrl.n_states
        surfaces = surface_fields(zs[:, na:na + ns], us[:, 3:3 + ns], us[:, 2], drogue_actuator)
    return ts, zs[:, : model.state_size], us[:, :2], status, t_stop, outs, surfaces


def closed_loop_state(x0: np.ndarray, ctrl: LinearController, actuator: Actuator, drogue_actuator=None) -> np.ndarray:
    """The closed-loop initial state ``[x0, xc = 0, (ua = 0 or the surfaces at rest)]``.

    Parameters
    ----------
    x0 : array (4n,)
        Hose state [q, qd] [rad, rad/s].
    ctrl : LinearController
        Controller (its states start at zero).
    actuator : Actuator
        A rate-limited actuator adds the applied force [N] (starting at zero) to the state.
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        Control surfaces add their deflections [rad] (and servo rates [rad/s]), starting at zero.

    Returns
    -------
    array
    """
    return np.concatenate([x0, loop_states(ctrl, actuator, drogue_actuator)])


def fixed_steps(params: Params, duration_s: float) -> tuple[float, int]:
    """The RK4 step [s] and the number of steps covering ``duration_s`` [s].

    Parameters
    ----------
    params : Params
        ``params.numerics.step_s`` [s] is the step.
    duration_s : float
        Simulated time [s].

    Returns
    -------
    (float, int)
        Step [s] and step count (``round(duration_s / step_s)``, >= 1).
    """
    h = params.numerics.step_s
    nsteps = int(round(duration_s / h))
    if nsteps < 1:
        raise ParameterError(f"duration_s = {duration_s!r}: shorter than one step ({h} s)")
    return h, nsteps


def _run_rk4(model: HoseModel, z0, duration_s, loop: LoopArrays):
    h, nsteps = fixed_steps(model.params, duration_s)
    every = model.params.numerics.output_every
    nsave = nsteps // every + 1
    ts = np.empty(nsave)
    zs = np.empty((nsave, z0.size))
    us = np.empty((nsave, output_width(loop.act)))
    outs = output_arrays(nsave, model.n)
    max_yaw = math.radians(model.params.numerics.max_yaw_deg)
    status, saved, t_stop = rk4_run(z0, h, nsteps, every, *model.kernel_args(), *loop, max_yaw,
                                    ts, zs, us, *outs)
    return ts[:saved], zs[:saved], us[:saved], status, t_stop, tuple(o[:saved] for o in outs)


def _run_elastic(model: HoseModel, z0, duration_s, loop: LoopArrays):
    """The fixed-length elastic chain, compiled: RK4 or the SDIRK (``numerics.integrator``)."""
    from ..model.elastic_loop import elastic_run
    from ..model.layout import SCHEME_RK4, SCHEME_SDIRK2

    h, nsteps = fixed_steps(model.params, duration_s)
    every = model.params.numerics.output_every
    nsave = nsteps // every + 1
    ts = np.empty(nsave)
    zs = np.empty((nsave, z0.size))
    us = np.empty((nsave, 2))
    outs = output_arrays(nsave, model.n)
    scheme = SCHEME_SDIRK2 if model.params.numerics.integrator == "sdirk2" else SCHEME_RK4
    max_yaw = math.radians(model.params.numerics.max_yaw_deg)
    status, saved, t_stop = elastic_run(z0, h, nsteps, every, scheme, model.params.numerics.sdirk_corrections,
                                        model.l, model.M, model.J, model.ps,
                                        model.env, model.gust_values, *loop, max_yaw, ts, zs, us, *outs)
    return ts[:saved], zs[:saved], us[:saved], status, t_stop, tuple(o[:saved] for o in outs)


def output_width(act: np.ndarray) -> int:
    """Columns of the compiled loop's saved force rows: the force (2) and, for a drogue with
    control surfaces, the dynamic pressure [Pa] and each surface's rate [rad/s].

    Parameters
    ----------
    act : array
        The loop's actuator array (:class:`hosedrogue.model.integrate.LoopArrays`).

    Returns
    -------
    int
    """
    return 2 if not DA.is_actuated(act) else 3 + int(act[DA.DA_NS])


def output_arrays(count: int, n: int) -> tuple[np.ndarray, ...]:
    """Empty derived-output arrays for the compiled loop to fill.

    Parameters
    ----------
    count : int
        Number of saved states [-].
    n : int
        Number of links [-].

    Returns
    -------
    tuple of numpy.ndarray
        Joint positions (count, n+1, 3) [m], drogue velocity [m/s], drogue drag [N] and
        tow-point force [N] (count, 3 each), exit tension [N] (count,).
    """
    return (np.empty((count, n + 1, 3)), np.empty((count, 3)), np.empty((count, 3)), np.empty((count, 3)),
            np.empty(count))


def _run_adaptive(model: HoseModel, z0, duration_s, loop: LoopArrays):
    num = model.params.numerics
    h_out = num.step_s * num.output_every
    t_eval = np.arange(0.0, duration_s + 0.5 * h_out, h_out)
    t_eval = t_eval[t_eval <= duration_s + 1e-12]
    u = np.empty(2)
    args = (*model.kernel_args(), *loop, CD.make_workspace(model.n))
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
    us = np.empty((ts.size, output_width(loop.act)))
    ws = CD.make_workspace(model.n)
    for i in range(ts.size):
        if DA.is_actuated(loop.act):  # the surfaces' force needs the drogue's air: a whole evaluation
            closed_loop_deriv(ts[i], zs[i], *args, np.empty_like(zs[i]), us[i])
            continue
        applied_force(ts[i], zs[i], 4 * n, model.l, loop.Cc, loop.Dc, loop.y_ref, loop.act, loop.noise,
                      loop.noise_dt, ws, u)
        us[i] = u
    if sol.status == 1:
        return ts, zs, us, LY.YAW_LIMIT, float(sol.t_events[0][0])
    if sol.status < 0:
        return ts, zs, us, LY.STEP_LIMIT, float(ts[-1] if ts.size else 0.0)
    if not np.all(np.isfinite(zs)):
        return ts, zs, us, LY.NONFINITE, float(ts[-1])
    return ts, zs, us, LY.OK, duration_s


def _python_rate(t, z, model, hg, guess, dz):
    """dz/dt of the hose with a Python control function, in the steppers' form
    (:mod:`hosedrogue.model.steppers`): ``model`` is ``(HoseModel, control)``, the force
    ``control(t, z)`` [N] applied at every stage; hg and guess are not read (no implicit stage)."""
    hose, control = model
    dz[:] = hose.derivative(t, z, _force_of(control, t, z))


def _force_of(control, t, x) -> np.ndarray:
    """The control function's force (u_hor, u_ver) [N] at (t, x)."""
    return np.asarray(control(t, x), dtype=np.float64).reshape(2)


#: The RK4 step over a Python control function: the package's one RK4 step (:func:`rk4`), not compiled.
_python_rk4_step, _ = rk4(_python_rate, compiled=False)


def _run_python_control(model, params, x0, duration_s, control):
    """RK4 with a Python control function: the right-hand side stays compiled."""
    h, nsteps = fixed_steps(params, duration_s)
    every = params.numerics.output_every
    max_yaw = math.radians(params.numerics.max_yaw_deg)
    n = model.n
    x = x0.copy()
    work = np.empty((5, x.size))
    ts, xs, us = [0.0], [x.copy()], [_force_of(control, 0.0, x)]
    for step in range(1, nsteps + 1):
        _python_rk4_step((step - 1) * h, x, h, (model, control), work)  # x in place
        t = step * h
        status = step_status(x, n, max_yaw)  # the compiled loops' check: non-finite, then the yaw limit
        if status != LY.OK:
            return np.array(ts), np.array(xs), np.array(us), status, t
        if step % every == 0:
            ts.append(t)
            xs.append(x.copy())
            us.append(_force_of(control, t, x))
    return np.array(ts), np.array(xs), np.array(us), LY.OK, duration_s


def _derived_outputs(model: HoseModel, ts, xs, us):
    outs = output_arrays(ts.size, model.n)
    if model.elastic:
        from ..model.elastic import elastic_outputs_series

        elastic_outputs_series(np.ascontiguousarray(ts), np.ascontiguousarray(xs), np.ascontiguousarray(us),
                               model.l, model.M, model.J, model.ps, model.env, model.gust_values, *outs)
        return outs
    CD.outputs_series(np.ascontiguousarray(ts), np.ascontiguousarray(xs), np.ascontiguousarray(us),
                     *model.kernel_args(), *outs)
    return outs
