"""The stepping API of the engagement: an object that holds a run's state and advances the
compiled loop one control step at a time with the commands held - the receiver's probe-tip
velocity, the reel's take-up speed, the drogue's force - returning the measurement
(docs/controllers.md, "Stepping a run").

::

    stepper = EngagementStepper(params, 4.5, control_step_s=0.02, probe=Probe(), receiver=Receiver())
    m = stepper.reset(seed=3)
    while not stepper.done:
        m = stepper.step(receiver=(1.0, -0.5 * m.relative_position_m[1], 0.0))
    result = stepper.result()          # the usual EngagementResult

A control step integrates with :func:`hosedrogue.model.engagement.steps.eng_advance`; the
events that end a compiled segment (a remesh, a chart switch, the coupler plane) are handled in
between as :func:`~hosedrogue.engagement.driver.simulate_engagement` does
(:mod:`hosedrogue.engagement.events`), so a stepped run and a run of the same commands through
``simulate_engagement`` are the same run.
"""

from __future__ import annotations

import math

import numpy as np

from ..controllers.linear import LinearController
from ..errors import ParameterError
from ..model import chain_dynamics as CD, layout as LY
from ..model.elastic import make_elastic_workspace
from ..model.engagement import chain as EC, outputs as EO, probe as EPR, steps as ES
from ..model.sampled import C_ORIGIN, C_SAVED, C_SPC, C_STEP, C_TARGET, C_TOTAL, deliver, held_command
from ..spec.params import Actuator, Params, Sensor
from ..spec.sections import BowWave, Pilot, Probe, Receiver, Reel
from ..simulation.stepper import StepperBase, sensor_noise3
from .chain import MERGE_RATIO, SPLIT_RATIO, SWITCH_YAW_DEG, chain_model
from .driver import prepare, step_record
from .events import FAILURES, failure_reason, segment_event
from ..results.run import stop_message
from .result import EngagementResult, assemble_result, coupler_geometry, segment_outputs

class EngagementStepper(StepperBase):
    """An engagement advanced one control step at a time, its commands held in between.

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and numerics (the integrator, ``numerics.step_s`` [s], ``output_every``).
    duration_s : float
        Length of the run [s] (its gust record is drawn for it); the run is done there, or at a
        miss or failed latch, or at a failed state.
    control_step_s : float
        Time between commands [s], a whole multiple of ``numerics.step_s``.
    reel : Reel, optional
        The drum unit; law "python": its take-up speed is commanded (:meth:`step` ``reel=``).
    probe : Probe, optional
        The receiver's probe (start point, capture test, coupling).
    bow_wave : BowWave, optional
        The receiver's forebody flow.
    pilot : Pilot, optional
        The pilot model flying the probe (not with a receiver).
    receiver : Receiver, optional
        The probe flown by a velocity command (:meth:`step` ``receiver=``) through this
        response (its ``entry`` is not needed here).
    control : LinearController, optional
        A built-in drogue controller compiled in the loop (continuous).
    drogue_command : bool
        The drogue's force is commanded (:meth:`step` ``drogue=``) instead.
    actuator : Actuator
        Force [N] and rate [N/s] limits of the drogue's force.
    sensor : Sensor
        Noise [m] on the measured drogue position, its delay [s] (a whole multiple of the control step).
    x0 : array (4n,), optional
        Initial hose state [rad, rad/s].
    equilibrium : Equilibrium, optional
        A solved balance position of the initial mesh to reuse.
    seed : int, optional
        Overrides ``params.turbulence.seed``.
    length_rate_m_s : float
        Initial L' [m/s].
    record : bool
        Keep the time series for :meth:`result` (False: only the measurement, for speed).
    energy : bool
        :meth:`result` also evaluates the energy terms [J].
    gravity_m_s2 : float, optional
        Overrides g [m/s^2].
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue's control surfaces (docs/model.md §10): the built-in ``control`` or the held
        drogue command (a force, or with ``command = "deflection"`` one deflection [rad] per
        surface) commands them.
    receiver_pass_through : bool
        With a receiver: the probe tip moves as :meth:`move_receiver` says, without the
        receiver's response (no lag, no speed or acceleration bound) - for a probe path fed from
        outside (the engagement FMU's position input).
    probe_start_m : array_like (3,), optional
        With a receiver: where the probe tip starts [m] in the tanker frame, instead of the
        ``[probe]`` start point (its standoff and offsets from the drogue's balance position).
    probe_start_velocity_m_s : array_like (3,), optional
        With a receiver: the tip's velocity at the start [m/s], instead of the closure speed forward.
    """

    def __init__(self, params: Params, duration_s: float, *, control_step_s: float, reel: Reel | None = None,
                 probe: Probe | None = None, bow_wave: BowWave | None = None, pilot: Pilot | None = None,
                 receiver: Receiver | None = None, control: LinearController | None = None,
                 drogue_command: bool = False, actuator: Actuator = Actuator(), sensor: Sensor = Sensor(),
                 x0=None, equilibrium=None, seed: int | None = None, length_rate_m_s: float = 0.0,
                 record: bool = True, energy: bool = False, gravity_m_s2: float | None = None,
                 drogue_actuator=None, receiver_pass_through: bool = False, probe_start_m=None,
                 probe_start_velocity_m_s=None):
        if receiver is None and (receiver_pass_through or probe_start_m is not None
                                 or probe_start_velocity_m_s is not None):
            raise ParameterError("receiver_pass_through, probe_start_m, probe_start_velocity_m_s: only with a receiver "
                                 "(the probe it flies)")
        if receiver is not None and receiver.model and not receiver_pass_through:
            raise ParameterError(f"receiver.model = {receiver.model!r}: an aircraft receiver is flown by "
                                 "hosedrogue.engagement.aircraft_receiver.AircraftEngagementStepper (simulate, "
                                 "montecarlo, fly), not by this stepper or what builds on it (the environment, the FMU)")
        if drogue_command:
            control = held_command(drogue_actuator)
        elif drogue_actuator is not None:
            drogue_actuator.check_force_command()  # a built-in controller (or none) commands a force
        self.start = prepare(params, duration_s, reel=reel, probe=probe, bow_wave=bow_wave, pilot=pilot,
                             receiver=receiver, control=control, actuator=actuator, sensor=sensor if
                             not drogue_command else Sensor(), x0=x0, equilibrium=equilibrium, seed=seed,
                             length_rate_m_s=length_rate_m_s, gravity_m_s2=gravity_m_s2,
                             drogue_actuator=drogue_actuator, measured_rest=True)
        nd = control.n_states if drogue_command else 2  # the drogue command's numbers
        st = self.start
        self.pass_through = bool(receiver_pass_through)
        if receiver is not None:
            self._set_receiver_start(probe_start_m, probe_start_velocity_m_s)
        self.params, self.probe, self.duration_s = st.params, probe, float(duration_s)
        self.h = params.numerics.step_s
        self.total_steps = st.total_steps
        self.every = params.numerics.output_every
        self.max_yaw = math.radians(params.numerics.max_yaw_deg)
        self.record, self.energy, self.gravity_m_s2 = bool(record), bool(energy), gravity_m_s2
        self._setup_sensor(sensor, control_step_s, self.h)
        self.roles = tuple(r for r, on in (("drogue", drogue_command), ("reel", st.reel.law == "python"),
                                           ("receiver", receiver is not None)) if on)
        # the held commands (u_y, u_z or one deflection per surface, take-up speed, v_x, v_y, v_z),
        # written into the state's slots before every control step
        self._commands = np.zeros(nd + 4)
        self._slots = {"drogue": tuple(range(nd)), "reel": (nd,), "receiver": (nd + 1, nd + 2, nd + 3)}
        self._dM, self._out = np.empty(2), np.empty(LY.O_SIZE)  # the last evaluation's outputs (probe_force_n)
        self._slots = {role: self._slots[role] for role in self.roles}
        if receiver is not None:
            self._commands[nd + 1] = st.ep[LY.EP_VC]
        self.balance = st.drogue_eq.copy()
        self.seed = st.params.turbulence.seed
        self._model_seed = self.seed
        self.model = st.model
        self.reset()

    # --- the run's state ---------------------------------------------------------------------------
    def _restart(self, seed: int | None) -> None:
        st = self.start
        if seed is not None:
            self.seed = seed
        if self.seed != self._model_seed:
            self.params = st.params.replace(turbulence={"seed": self.seed})
            model = chain_model(self.params, st.chain, self.duration_s)
            if self.gravity_m_s2 is not None:
                model.ps[LY.PS_G] = float(self.gravity_m_s2)
            self.model = model
            self._model_seed = self.seed
        self.noise3 = sensor_noise3(self.sensor, self.duration_s, self.seed)
        self.run = st.new_run()
        self.run.segments = []  # the stepper records into its own buffers (the first row: t = 0)
        self._closed = []
        self._commands[:] = 0.0
        if "receiver" in self.roles:
            self._commands[self._slots["receiver"][0]] = st.ep[LY.EP_VC]
        self.ctr[C_TOTAL] = self.total_steps
        self.ctr[C_SPC] = self.spc
        self._on_chain()
        if self.record:
            self._ts[0] = 0.0
            self._zs[0] = self.run.z
            self.ctr[C_SAVED] = 1
        EO.eng_raw(0.0, self.run.z, *self._model_args, self._ws, self._ws2, self._dM, self._out, self.ring[0])
        deliver(self.ring, 0, self.delay, self.control_step_s, self.noise3, self.sensor.sample_time_s,
                self.balance, self.mbuf)

    def _on_chain(self) -> None:
        """Arrays of the current discretization (after a reset or an event): the scratch, a new
        recording buffer, the command's places in the state and the kernel's argument tuple."""
        run, model = self.run, self.model
        chain, n, nz = run.chain, run.chain.n, run.z.size
        self._ws, self._ws2 = CD.make_workspace(n), CD.make_workspace(n)
        self._work = np.empty((8, nz))
        self._zprev = np.empty(nz)
        rows = (self.total_steps - int(self.ctr[C_STEP])) // self.every + 2 if self.record else 1
        self._ts, self._zs = np.empty(rows), np.empty((rows, nz))
        self._rec_chain, self._rec_ep = chain, run.ep.copy()
        self.ctr[C_SAVED] = 0
        self._places = self._command_places(run)
        self._model_args = (n, chain.l.copy(), chain.M.copy(), chain.J.copy(), model.ps, model.env, model.gust_values,
                            run.ep, chain.chart, run.loop)
        limits = (float(self.max_yaw), math.radians(SWITCH_YAW_DEG), float(SPLIT_RATIO * chain.l_nom),
                  float(MERGE_RATIO * chain.l_nom), n >= 2)
        # the steps' scratch, one per discretization as the driver's segment keeps one for all its
        # steps (rigid links read neither the elastic workspace nor the pairs)
        scratch = (self._work, self._ws, self._ws2, self._dM, self._out, make_elastic_workspace(n),
                   EC.elastic_pairs(n, run.ep[LY.EP_PIL] != 0.0, run.ep[LY.EP_RCV] != 0.0))
        self._call = (self.ctr, run.z, self.h, self.every, *self._model_args, run.hist, limits, self._zprev, self._ts,
                      self._zs, self.record, scratch, self.ring, self.delay, self.control_step_s, self.noise3,
                      self.sensor.sample_time_s, self.balance, self.mbuf, run.loads)

    def _set_receiver_start(self, probe_start_m, probe_start_velocity_m_s) -> None:
        """The receiver's start point and, passing through, its response replaced by the fed
        path (``EP_FEED``): from the start point at the start velocity in a straight line until
        :meth:`move_receiver` says otherwise."""
        st = self.start
        b = EC.tail_start(st.chain.n, st.ep) + LY.Z_TAIL  # after the 4n rigid or the 6n elastic hose entries
        if probe_start_m is not None:
            p = np.asarray(probe_start_m, dtype=np.float64)
            if p.shape != (3,) or not np.all(np.isfinite(p)):
                raise ParameterError(f"probe_start_m = {probe_start_m!r}: must be 3 finite numbers [m]")
            st.z[b + LY.RCV_X:b + LY.RCV_X + 3] = p
            st.ep[[LY.EP_P0X, LY.EP_P0Y, LY.EP_P0Z]] = p
        if probe_start_velocity_m_s is not None:
            v = np.asarray(probe_start_velocity_m_s, dtype=np.float64)
            if v.shape != (3,) or not np.all(np.isfinite(v)):
                raise ParameterError(f"probe_start_velocity_m_s = {probe_start_velocity_m_s!r}: must be 3 finite "
                                     "numbers [m/s]")
            st.z[b + LY.RCV_VX:b + LY.RCV_VX + 3] = v
        if self.pass_through:
            st.ep[LY.EP_FEED] = 1.0
            st.ep[LY.EP_FEED_T0] = 0.0
            st.ep[LY.EP_FEED_P:LY.EP_FEED_P + 3] = st.z[b + LY.RCV_X:b + LY.RCV_X + 3]
            st.ep[LY.EP_FEED_V:LY.EP_FEED_V + 3] = st.z[b + LY.RCV_VX:b + LY.RCV_VX + 3]
            st.ep[LY.EP_FEED_A:LY.EP_FEED_J + 3] = 0.0

    def move_receiver(self, velocity_m_s, acceleration_m_s2, jerk_m_s3=(0.0, 0.0, 0.0)) -> None:
        """Passing through (``receiver_pass_through``): from now on, until the next call, the
        probe tip moves from where it is on the cubic in time of this velocity, acceleration
        and jerk.

        The tip is that cubic as a function of time (``EP_FEED``,
        :func:`hosedrogue.model.engagement.probe.fed_tip`), evaluated at each integrator
        stage's time as a prescribed path is, so a path fed from outside meets the hose as the
        same path prescribed in the run does; the receiver's states follow it.

        Parameters
        ----------
        velocity_m_s : array_like (3,)
            The tip's velocity now [m/s], tanker frame.
        acceleration_m_s2 : array_like (3,)
            Its acceleration now [m/s^2] (0 and no jerk: a straight line at constant speed).
        jerk_m_s3 : array_like (3,)
            Its rate of change of acceleration until the next call [m/s^3] (0: a parabola).
        """
        if not self.pass_through:
            raise ParameterError("move_receiver: only with receiver_pass_through (else the receiver's response "
                                 "follows the command of step(receiver=...))")
        run = self.run
        ep, b = run.ep, EC.tail_start(run.chain.n, run.ep) + LY.Z_TAIL
        p0 = EPR.fed_tip(self.t_s, ep)[0]  # where the path fed so far has the tip now
        ep[LY.EP_FEED_T0] = self.t_s
        ep[LY.EP_FEED_P:LY.EP_FEED_P + 3] = p0
        ep[LY.EP_FEED_V:LY.EP_FEED_V + 3] = velocity_m_s
        ep[LY.EP_FEED_A:LY.EP_FEED_A + 3] = acceleration_m_s2
        ep[LY.EP_FEED_J:LY.EP_FEED_J + 3] = jerk_m_s3
        run.z[b + LY.RCV_X:b + LY.RCV_X + 3] = p0
        run.z[b + LY.RCV_VX:b + LY.RCV_VX + 3] = velocity_m_s

    def _command_places(self, run) -> list:
        """(index in the held commands, index in the state) of every commanded number."""
        b = EC.tail_start(run.chain.n, run.ep) + LY.Z_TAIL
        places = []
        slots = self._slots
        if "drogue" in self.roles:
            nx = b + int(run.ep[LY.EP_NPIL])
            places += [(i, nx + i) for i in slots["drogue"]]
        if "reel" in self.roles:
            places.append((slots["reel"][0], b + int(run.ep[LY.EP_REEL_SLOT]) - 1))
        if "receiver" in self.roles:
            places += [(j, b + LY.RCV_CX + i) for i, j in enumerate(slots["receiver"])]
        return places

    def _close_record(self) -> None:
        saved = int(self.ctr[C_SAVED])
        if self.record and saved:
            self._closed.append((self._rec_chain, self._rec_ep, self._ts[:saved].copy(), self._zs[:saved].copy(),
                                 self._places))
        self.ctr[C_SAVED] = 0

    # --- one control step ----------------------------------------------------------------------------
    def _advance(self) -> None:
        run = self.run
        z, cmd = run.z, self._commands
        for i, j in self._places:
            z[j] = cmd[i]
        if self.record and int(self.ctr[C_STEP]) % self.every == 0 and (self.ctr[C_SAVED] or self._closed):
            # the row saved at this instant shows the command that acts from it (as the fixed-length loop's)
            saved = int(self.ctr[C_SAVED])
            row, places = (self._zs[saved - 1], self._places) if saved else (self._closed[-1][3][-1],
                                                                             self._closed[-1][4])
            for i, j in places:
                row[j] = cmd[i]
        target = min(int(self.ctr[C_STEP]) + self.spc, self.total_steps)
        self.ctr[C_TARGET] = target
        while True:
            code = ES.eng_advance(*self._call)
            run.step = int(self.ctr[C_STEP])
            run.t = run.step * self.h
            if code == LY.OK:
                break
            if self._event(code):
                return
            if run.step >= target:
                break
        if run.step >= self.total_steps:
            self._finish(True, "completed")

    def _event(self, code: int) -> bool:
        """Handle what ended a compiled segment before the control step's end; True if the run ends."""
        run = self.run
        if code in FAILURES:
            self._finish(False, stop_message(self._last_kept_s(), failure_reason(run, code), run.t), state_valid=False)
            return True
        self._close_record()
        self.ctr[C_ORIGIN] = self.ctr[C_STEP]  # the next compiled segment counts its times from here, as the driver's
        if segment_event(run, code, self.params, self.model, self._zprev, self.h, self.probe):
            self._finish(True, "completed", state_valid=False)  # a miss or a failed latch ends the run
            return True
        self._on_chain()
        return False

    def _save_final(self) -> None:
        """Nothing to add: the kernel saves every state on the output grid as it reaches it."""

    def _last_kept_s(self) -> float:
        """The time of the last state kept [s] (the stepper's time when it keeps no series)."""
        saved = int(self.ctr[C_SAVED])
        if self.record and saved:
            return float(self._ts[saved - 1])
        return float(self._closed[-1][2][-1]) if self.record and self._closed else self.t_s

    # --- the result ------------------------------------------------------------------------------
    @property
    def probe_force_n(self) -> np.ndarray:
        """The probe's force on the drogue [N] (tanker frame; zero until coupled) at the time of
        the last measurement, without the sensor (the receiver feels its opposite)."""
        return self._out[LY.O_FPX:LY.O_FPZ + 1].copy()

    @property
    def outcome(self) -> dict:
        """The capture test's outcome so far (``result``, miss [m], closure speed [m/s], contact time [s])."""
        return self.run.outcome

    def hose_shape(self) -> tuple[np.ndarray, np.ndarray]:
        """The hose and the probe as they are now (the state, not the measurement: no sensor noise
        or delay), for drawing a run that keeps no time series.

        Returns
        -------
        joints_m : numpy.ndarray (n+1, 3)
            Joint positions [m] in S_p, from the hose's exit (row 0) to the drogue (row n).
        probe_m : numpy.ndarray (3,)
            Probe tip position [m] in S_p.
        """
        out = self.outputs()
        return out["joints_m"], out["probe_position_m"]

    def result(self) -> EngagementResult:
        """The run so far as the usual :class:`~hosedrogue.results.run.EngagementResult` (``completed``
        False and ``message`` saying why if it stopped early or is still running).

        Returns
        -------
        EngagementResult
        """
        if not self.record:
            raise RuntimeError("this stepper keeps no time series (record=False)")
        st, run = self.start, self.run
        saved = int(self.ctr[C_SAVED])
        segments = [rec[:4] for rec in self._closed]
        if saved:
            segments.append((self._rec_chain, self._rec_ep, self._ts[:saved].copy(), self._zs[:saved].copy()))
        return assemble_result(self.params, segments, run.events, dict(run.outcome), self.model, st.drogue_eq,
                               self.energy, self._completed, self._message, run.delta_total, st.t_set, st.reel,
                               self.probe, loop=run.loop, step_loads=step_record(self.params, run),
                               drogue_actuator=st.drogue_actuator)

    def outputs(self) -> dict:
        """The run's outputs at the current state, computed from it without recording it: what a
        live display shows between the output times (the same compiled output kernel and coupler
        geometry as :meth:`result`'s time series, so at an output time the two agree to the bit).

        Returns
        -------
        dict
            ``t_s`` [s]; ``joints_m`` (n+1, 3) the joints from the tow point to the drogue [m] in
            S_p; ``drogue_velocity_m_s`` (3,); ``probe_position_m``, ``probe_velocity_m_s`` (3,)
            [m, m/s] (the start point and zero without a probe); ``probe_force_n`` (3,) [N];
            ``exit_tension_n`` [N]; ``hose_length_m`` [m]; ``links`` [-]; ``coupled`` [-];
            ``plane_distance_m`` (probe tip aft of the coupler plane, positive aft) [m],
            ``miss_distance_m`` (radial, in the plane) [m] and ``closure_speed_m_s`` [m/s].
        """
        run = self.run
        n = run.chain.n
        joints, jvel, scal = segment_outputs(np.array([self.t_s]), run.z[None, :], run.chain, self.model, run.ep,
                                             run.loop)[:3]
        dpl, miss, vclose = coupler_geometry(joints, jvel, scal)
        return {"t_s": self.t_s, "joints_m": joints[0], "drogue_velocity_m_s": jvel[0, -1].copy(),
                "probe_position_m": scal[0, [LY.O_PX, LY.O_PY, LY.O_PZ]],
                "probe_velocity_m_s": scal[0, [LY.O_VPX, LY.O_VPY, LY.O_VPZ]],
                "probe_force_n": scal[0, [LY.O_FPX, LY.O_FPY, LY.O_FPZ]], "exit_tension_n": float(scal[0, LY.O_T0]),
                "hose_length_m": float(run.z[EC.tail_start(n, run.ep) + LY.Z_L]), "links": n, "coupled": bool(run.ep[LY.EP_COUPLED]),
                "plane_distance_m": float(dpl[0]), "miss_distance_m": float(miss[0]),
                "closure_speed_m_s": float(vclose[0])}
