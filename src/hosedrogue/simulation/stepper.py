"""The stepping API of the fixed-length hose: an object that holds a run's state and advances the
compiled loop one control step at a time with the drogue's force command held, returning the
measurement (docs/controllers.md, "Stepping a run").

::

    stepper = FixedLengthStepper(params, 60.0, control_step_s=0.01)
    m = stepper.reset(seed=7)
    while not stepper.done:
        m = stepper.step(drogue=my_law(m))
    result = stepper.result()          # the usual SimulationResult

:class:`StepperBase` holds what the fixed-length and the engagement steppers share: the control
step on the RK4 grid, the sensor's delay in samples and its noise, the measurement, the
commands' checks and the run's end.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis.equilibrium import Equilibrium, solve_equilibrium
from ..controllers.linear import LinearController
from ..controllers.sampled import COMMANDS, Measurement, command_problem, discretize, discretize_anti_windup
from ..errors import ParameterError
from .budget import check_duration, check_integrator, check_run, whole_multiple
from ..model import chain_dynamics as CD, layout as LY
from ..model.integrate import loop_arrays, loop_states, save_state, sensor_noise
from ..model.sampled import (C_SAVED, C_SIZE, C_SPC, C_STEP, C_TOTAL, M_SIZE, RAW_SIZE, deliver, fl_advance, fl_linear_sampled_run, fl_raw,
                             held_command)
from ..model.status import status_text
from ..model.system import HoseModel
from ..results.run import SimulationResult, stop_message
from ..results.statistics import turbulence_window
from ..results.surfaces import surface_fields
from ..spec.params import PAPER, Actuator, Params, Sensor


def sensor_noise3(sensor: Sensor, duration_s: float, seed: int) -> np.ndarray:
    """Sensor noise samples of the drogue position [m] (k, 3), axes x, y, z, zero-order held for
    ``sensor.sample_time_s``: y and z are the built-in controllers' noise
    (:func:`~hosedrogue.model.integrate.sensor_noise`, the same draws), x an independent stream
    of the turbulence seed; ``(1, 3)`` zeros without noise.

    Parameters
    ----------
    sensor : Sensor
        Noise standard deviation [m] and sample time [s].
    duration_s : float
        Simulated time [s] the samples cover.
    seed : int
        The run's turbulence seed.

    Returns
    -------
    numpy.ndarray (k, 3)
    """
    yz = sensor_noise(sensor, duration_s, seed)
    if sensor.noise_std_m == 0.0:
        return np.zeros((1, 3))
    rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence([seed, 2])))
    x = sensor.noise_std_m * rng.standard_normal(yz.shape[0])
    return np.ascontiguousarray(np.column_stack([x, yz]))


class StepperBase:
    """What the steppers share: the control step on the RK4 grid, the sensor's delay and the
    measurement, the held commands and their checks, the run's clock and end.

    Subclasses set ``h`` (RK4 step [s]), ``ctr`` (the kernels' counters, ``C_*`` of
    :mod:`hosedrogue.model.sampled`), ``_slots`` (role -> indices of the role's numbers in
    ``_commands``, the held commands' storage) and ``record``, and implement ``_restart(seed)``,
    ``_advance()``, ``_save_final()`` and ``result()``.
    """

    #: The roles whose commands :meth:`step` takes (a subclass's subset of ROLES).
    roles: tuple = ()

    def _setup_sensor(self, sensor: Sensor, control_step_s: float, h: float) -> None:
        self.sensor = sensor
        self.spc = whole_multiple(control_step_s, h, "control_step_s", "numerics.step_s")
        self.control_step_s = self.spc * h
        self.delay = 0 if sensor.delay_s == 0.0 else whole_multiple(sensor.delay_s, self.control_step_s,
                                                                    "sensor.delay_s", "the control step")
        self.ring = np.zeros((self.delay + 1, RAW_SIZE))
        self.mbuf = np.zeros(M_SIZE)
        self.measurement = Measurement.reading(self.mbuf)
        self.ctr = np.zeros(C_SIZE, dtype=np.int64)

    # --- the run's clock and end ----------------------------------------------------------------
    @property
    def step_index(self) -> int:
        """Global RK4 steps done [-]."""
        return int(self.ctr[C_STEP])

    @property
    def t_s(self) -> float:
        """The run's time [s] (global RK4 steps times the step)."""
        return int(self.ctr[C_STEP]) * self.h

    @property
    def done(self) -> bool:
        """True once the run has ended (its duration, a failed state, a miss, or :meth:`stop`)."""
        return self._done

    @property
    def completed(self) -> bool:
        """True when the run reached its end without a failure."""
        return self._completed

    @property
    def message(self) -> str:
        """"completed", "running", or when and why the run stopped."""
        return self._message

    def stop(self, reason: str) -> None:
        """End the run here, marked incomplete (e.g. a controller that failed): its message is
        ``"stopped at t = T s: reason"``, T the time of the last state kept (the state now, if it is
        on the output grid, else the last output time before it), which is the result's last time.

        Parameters
        ----------
        reason : str
            One line: why, and when it happened if that is not T.
        """
        if not self._done:
            self._finish(False, "")
            self._message = stop_message(self._last_kept_s(), reason)

    def _last_kept_s(self) -> float:
        """The time of the last state kept [s] (the stepper's time when it keeps no series)."""
        saved = int(self.ctr[C_SAVED])
        return float(self._rec[0][saved - 1]) if self.record and saved else self.t_s

    def _finish(self, completed: bool, message: str, state_valid: bool = True) -> None:
        """End the run; a valid state on the output grid is saved as the last row (a failed one is not)."""
        self._done = True
        self._completed = completed
        self._message = message
        if state_valid and self.record:
            self._save_final()

    def reset(self, seed: int | None = None) -> Measurement:
        """Start the run again from its initial state with the turbulence and sensor noise of
        ``seed`` (default: the last one; at first the parameters').

        Parameters
        ----------
        seed : int, optional
            Turbulence seed, >= 0 (the sensor noise is an independent stream of it).

        Returns
        -------
        Measurement
            The measurement at t = 0 (the stepper's one object, updated in place by :meth:`step`).
        """
        if seed is not None and (isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0):
            raise ParameterError(f"seed = {seed!r}: must be an integer >= 0")
        self._done = False
        self._completed = False
        self._message = "running"
        self.ctr[:] = 0
        self.ctr[C_TOTAL] = self.total_steps
        self.ctr[C_SPC] = self.spc
        self._restart(None if seed is None else int(seed))
        return self.measurement

    def step(self, drogue=None, reel=None, receiver=None, samples: int = 1) -> Measurement:
        """Hold the given commands (None: keep the previous one) and advance ``samples`` control
        steps of the compiled loop (fewer if the run ends first).

        Parameters
        ----------
        drogue : array_like (2,) or (n_s,), optional
            Force (u_y_n, u_z_n) [N] at the drogue (through the actuator's limits, or mixed to
            the control surfaces); with ``[drogue_actuator] command = "deflection"`` one
            deflection command [rad] per surface.
        reel : float, optional
            Take-up speed command [m/s], positive reeling in (an engagement with ``reel.law =
            "python"``; the motor's torque and speed limits apply).
        receiver : array_like (3,), optional
            Probe-tip velocity command (v_x, v_y, v_z) [m/s] in the tanker frame (an engagement
            with a receiver; through its response).
        samples : int
            Control steps to advance, >= 1.

        Returns
        -------
        Measurement
            At the new time (the sensor delay included); the same object every call.

        Raises
        ------
        ParameterError
            A command for a role this run does not command, of the wrong shape or not finite.
        RuntimeError
            The run has ended (:attr:`done`); :meth:`reset` starts it again.
        """
        if self._done:
            raise RuntimeError(f"the run has ended ({self._message}); call reset() to start it again")
        for role, value in (("drogue", drogue), ("reel", reel), ("receiver", receiver)):
            if value is not None:
                problem = self.hold(role, value)
                if problem is not None:
                    raise ParameterError(f"{role} = {value!r}: {problem}")
        for _ in range(samples):
            if self._done:
                break
            self._advance()
        return self.measurement

    def hold(self, role: str, value) -> str | None:
        """Hold ``value`` as the command of ``role`` from now on (checked; nothing is held if bad).

        Parameters
        ----------
        role : str
            ``"drogue"``, ``"reel"`` or ``"receiver"``.
        value : array_like or float
            The command (:meth:`step`).

        Returns
        -------
        str or None
            None, or what is wrong ("returned NaN ...", the shape): the text a controller's
            failure message takes.
        """
        if role not in self._slots:
            return f"this run takes no {role} command (it commands {', '.join(self.roles) or 'nothing'})"
        return self.holder(role)(value)

    def holder(self, role: str):
        """The function that holds a command of ``role`` (:meth:`hold` without the look-up: the
        loop of a run calls it at every sample).

        Parameters
        ----------
        role : str
            One of :attr:`roles`.

        Returns
        -------
        callable
            ``value -> None`` or what is wrong with it.
        """
        cmd, slots = self._commands, self._slots[role]

        def bad(value):
            return command_problem(role, value, len(slots))[0] or f"returned {value!r}, expected {COMMANDS[role]}"

        if len(slots) == 1:
            i = slots[0]

            def hold1(value):
                try:
                    a = float(value)
                except (TypeError, ValueError):
                    return bad(value)
                if a - a != 0.0:  # NaN or inf
                    return bad(value)
                cmd[i] = a
            return hold1
        if len(slots) == 2:
            i, j = slots

            def hold2(value):
                try:
                    a, b = value
                    a, b = float(a), float(b)
                except (TypeError, ValueError):
                    return bad(value)
                if a - a != 0.0 or b - b != 0.0:
                    return bad(value)
                cmd[i] = a
                cmd[j] = b
            return hold2
        if len(slots) > 3:  # one deflection per control surface
            def hold_n(value):
                problem, values = command_problem(role, value, len(slots))
                if problem is not None:
                    return problem
                for i, v in zip(slots, values):
                    cmd[i] = v
            return hold_n
        i, j, k = slots

        def hold3(value):
            try:
                a, b, c = value
                a, b, c = float(a), float(b), float(c)
            except (TypeError, ValueError):
                return bad(value)
            if a - a != 0.0 or b - b != 0.0 or c - c != 0.0:
                return bad(value)
            cmd[i] = a
            cmd[j] = b
            cmd[k] = c
        return hold3


class FixedLengthStepper(StepperBase):
    """A fixed-length run advanced one control step at a time, the drogue's force held.

    Parameters
    ----------
    params : Params
        Model, environment and numerics (RK4; ``numerics.step_s`` [s], ``output_every``).
    duration_s : float
        Length of the run [s] (its gust record is drawn for it); the run is done there.
    control_step_s : float
        Time between commands [s], a whole multiple of ``numerics.step_s``.
    x0 : array (4n,), optional
        Initial hose state [rad, rad/s]; default the balance position at rest.
    equilibrium : Equilibrium, optional
        A solved balance position to reuse.
    actuator : Actuator
        Force [N] and rate [N/s] limits the held force goes through.
    sensor : Sensor
        Noise [m] on the measured drogue position, its delay [s] (a whole multiple of the control step).
    seed : int, optional
        Overrides ``params.turbulence.seed`` (and seeds the sensor noise).
    record : bool
        Keep the time series for :meth:`result` (False: only the measurement, for speed).
    model : HoseModel, optional
        Reuse a model built from ``params`` (its gusts must cover the run).
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue steers itself with these control surfaces (docs/model.md §10): the held force
        is mixed to them at the dynamic pressure of each evaluation, or with ``command =
        "deflection"`` the held command is their deflections [rad]; ``actuator`` must then have
        no limits.
    """

    roles = ("drogue",)

    def __init__(self, params: Params = PAPER, duration_s: float = 10.0, *, control_step_s: float,
                 x0: np.ndarray | None = None, equilibrium: Equilibrium | None = None,
                 actuator: Actuator = Actuator(), sensor: Sensor = Sensor(), seed: int | None = None,
                 record: bool = True, model: HoseModel | None = None, drogue_actuator=None):
        check_duration(duration_s)
        if seed is not None:
            params = params.replace(turbulence={"seed": int(seed)})
        self.params = params
        self.h, self.total_steps = check_run(params, duration_s)  # the grids reach duration_s; the output fits
        self.every = params.numerics.output_every
        self.duration_s = float(duration_s)
        if model is None or not model.gusts_cover(duration_s):
            model = HoseModel(params, duration_s=duration_s)
        self.model = model.rigid_only("the fixed-length stepper")
        check_integrator(params, "fixed-length stepper")
        self.equilibrium = equilibrium if equilibrium is not None else solve_equilibrium(params, model=model)
        n = model.n
        x0 = self.equilibrium.state if x0 is None else np.asarray(x0, dtype=np.float64)
        if x0.shape != (4 * n,) or not np.all(np.isfinite(x0)):
            raise ParameterError(f"x0: must be a finite array of shape ({4 * n},), got shape {np.shape(x0)}")
        self.actuator = actuator
        if drogue_actuator is not None:
            drogue_actuator.check_loop(actuator == Actuator(), None)  # the surfaces make the force, its limits
            drogue_actuator.check_step(params.numerics.step_s)
        self.drogue_actuator = drogue_actuator
        self.hold_controller = held_command(drogue_actuator)
        nh = self.hold_controller.n_states
        self.nx = 4 * n
        self.z0 = np.concatenate([x0, loop_states(self.hold_controller, actuator, drogue_actuator)])
        self.z = self.z0.copy()
        self._commands = self.z[self.nx:self.nx + nh]  # the hold controller's states are the command
        self._slots = {"drogue": tuple(range(nh))}
        width = 2 if drogue_actuator is None else 3 + drogue_actuator.surfaces  # force (q, servo rates)
        self.balance = self.equilibrium.drogue_position_m.copy()
        self._setup_sensor(sensor, control_step_s, self.h)
        self.record = bool(record)
        nsave = self.total_steps // self.every + 1 if self.record else 1
        self._rec = (np.empty(nsave), np.empty((nsave, self.z0.size)), np.empty((nsave, width)),
                     np.empty((nsave, n + 1, 3)), np.empty((nsave, 3)), np.empty((nsave, 3)), np.empty((nsave, 3)),
                     np.empty(nsave))
        self.ws = CD.make_workspace(n)
        self.work = np.empty((5, self.z0.size))
        self.u = np.empty(width)
        self.max_yaw = math.radians(params.numerics.max_yaw_deg)
        self.seed = params.turbulence.seed
        self._model_seed = self.seed
        self.reset()

    def _restart(self, seed: int | None) -> None:
        if seed is not None:
            self.seed = seed
        if self.seed != self._model_seed:
            self.params = self.params.replace(turbulence={"seed": self.seed})
            self.model = HoseModel(self.params, duration_s=self.duration_s)
            self._model_seed = self.seed
        loop = loop_arrays(self.hold_controller, self.balance[1:], self.actuator, np.zeros((1, 2)), 1.0,
                           self.drogue_actuator)
        self.noise3 = sensor_noise3(self.sensor, self.duration_s, self.seed)
        self.z[:] = self.z0
        self._args = self.model.kernel_args() + tuple(loop)
        self._call = (self.ctr, self.z, self.h, self.every, *self._args, self.max_yaw, self.record, *self._rec,
                      self.ws, self.work, self.u, self.ring, self.delay, self.control_step_s, self.noise3,
                      self.sensor.sample_time_s, self.balance, self.mbuf)
        fl_raw(0.0, self.z, *self._args, self.ws, self.work, self.u, self.ring[0])
        deliver(self.ring, 0, self.delay, self.control_step_s, self.noise3, self.sensor.sample_time_s, self.balance,
                self.mbuf)

    def _advance(self) -> None:
        status = fl_advance(*self._call)
        if status != LY.OK:
            self._finish(False, stop_message(self._last_kept_s(), status_text(status, self.params), self.t_s), state_valid=False)
        elif self.ctr[C_STEP] >= self.total_steps:
            self._finish(True, "completed")

    def _save_final(self) -> None:
        if self.ctr[C_STEP] % self.every == 0:
            i = int(self.ctr[C_SAVED])
            save_state(i, self.t_s, self.z, *self._args, self.ws, self.work, self.u, *self._rec)
            self.ctr[C_SAVED] = i + 1

    def run_linear(self, controller: LinearController) -> SimulationResult:
        """Run from the reset state to the end with a built-in linear controller in sampled-data
        mode, compiled end to end: its zero-order-hold discretization at the control step reads
        the measured drogue offset from the balance position and sets the held force
        (:func:`hosedrogue.model.sampled.fl_linear_sampled_run`; the law, anti-windup included, of
        :class:`~hosedrogue.controllers.sampled.DiscreteLinearController` through :meth:`step`).

        Parameters
        ----------
        controller : LinearController
            The continuous design.

        Returns
        -------
        SimulationResult
        """
        if self.step_index != 0 or self._done:
            raise RuntimeError("run_linear starts from the reset state; call reset() first")
        if self.drogue_actuator is not None:
            self.drogue_actuator.check_force_command()
        Ad, Bd, Cd, Dd = discretize(controller, self.control_step_s)
        Bw = discretize_anti_windup(controller, self.control_step_s) if self.drogue_actuator else np.zeros_like(Bd)
        status, saved, done = fl_linear_sampled_run(
            self.z, self.total_steps, self.spc, self.h, self.every, *self._args, self.max_yaw, *self._rec,
            self.ring, self.delay, self.noise3, self.sensor.sample_time_s, self.balance, Ad, Bd, Cd, Dd, Bw, self.nx)
        self.ctr[C_STEP] = done
        self.ctr[C_SAVED] = saved
        if status == LY.OK:
            self._finish(True, "completed", state_valid=False)  # the kernel saved the last row
        else:
            self._finish(False, stop_message(self._last_kept_s(), status_text(status, self.params), self.t_s), state_valid=False)
        return self.result()

    def result(self) -> SimulationResult:
        """The run so far as the usual :class:`~hosedrogue.results.run.SimulationResult` (``completed``
        False and ``message`` saying why if it stopped early or is still running).

        Returns
        -------
        SimulationResult
        """
        if not self.record:
            raise RuntimeError("this stepper keeps no time series (record=False)")
        saved = int(self.ctr[C_SAVED])
        ts, zs, us, joints, dvel, ddrag, tow, tension = (a[:saved].copy() for a in self._rec)
        surfaces = {}
        if self.drogue_actuator is not None:
            ns, na = self.drogue_actuator.surfaces, self.nx + self.hold_controller.n_states
            surfaces = surface_fields(zs[:, na:na + ns], us[:, 3:3 + ns], us[:, 2], self.drogue_actuator)
        return SimulationResult(
            t_s=ts, states=zs[:, :self.nx], joints_m=joints, drogue_position_m=joints[:, -1, :],
            drogue_velocity_m_s=dvel, drogue_drag_n=ddrag, tow_force_n=tow, exit_tension_n=tension,
            control_force_n=us[:, :2].copy(), completed=self._completed, message=self._message,
            equilibrium_m=self.balance.copy(), meta={"seed": self.seed, "params": self.params.to_dict()},
            statistics_window_s=turbulence_window(self.params.turbulence), **surfaces)
