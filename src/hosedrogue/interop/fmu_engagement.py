"""The engagement FMU, independent of pythonfmu: its interface table (:data:`ENGAGEMENT_FMU`), the
start values of its scenario (:func:`fmu_starts`; the scenario it freezes:
:mod:`hosedrogue.interop.fmu_frozen`) and its simulation
(:class:`EngagementCore`), which is an :class:`~hosedrogue.engagement.stepper.EngagementStepper`
of that scenario: the compiled engagement loop advanced in whole control samples with the FMU's
inputs held (docs/interop.md, "The engagement FMU").

Frame S_p of the tanker (x forward, y right, z down, origin at the tow point), SI units:

=======================================  ==========  ==========================================
variable                                 causality   meaning
=======================================  ==========  ==========================================
``altitude_m``, ``airspeed_m_s``         parameter   flight condition [m], [m/s]
``wake_enabled``                         parameter   tanker wake on/off
``sample_time_s``                        parameter   the control sample the FMU steps in [s]
``probe_position_input``                 parameter   probe fed by positions (else velocities)
``probe_velocity_feed``                  parameter   with positions: the velocities given too
``probe_cmd_x_m`` .. ``_z_m``            input       probe-tip position at the step's end [m]
``probe_cmd_vx_m_s`` .. ``_vz_m_s``      input       probe-tip velocity (command) [m/s]
``reel_speed_cmd_m_s``                   input       take-up speed command [m/s] (law "python")
``u_y_n``, ``u_z_n``                     input       control force at the drogue [N]
``drogue_x_m`` .. ``drogue_vz_m_s``      output      drogue position [m], velocity [m/s]
``probe_x_m`` .. ``probe_vz_m_s``        output      probe-tip position [m], velocity [m/s]
``coupled``                              output      the probe holds the drogue
``probe_load_n``, ``probe_force_*_n``    output      the probe's force on the drogue [N]
``exit_tension_n``, ``hose_length_m``    output      reel exit tension [N], free length [m]
``reel_speed_m_s``                       output      take-up speed [m/s]
=======================================  ==========  ==========================================
"""

from __future__ import annotations

import dataclasses
import json
import math
import numpy as np

from ..errors import ParameterError
from ..spec.sections import Sensor
from .fmu_interface import FmuInterface, FmuVariable, StepFailure

#: Relative tolerance of a master's communication time against the FMU's own [-]: round-off of
#: the decimal times (the grid itself is exact: whole integration steps).
TIME_RTOL = 1e-9

_FLIGHT = ("altitude_m", "airspeed_m_s", "wake_enabled")
_AXES = (("x", "forward"), ("y", "right"), ("z", "down"))
_PROBE_POSITION = tuple(f"probe_cmd_{a}_m" for a, _ in _AXES)
_PROBE_VELOCITY = tuple(f"probe_cmd_v{a}_m_s" for a, _ in _AXES)
#: the variables the probe tip's start point depends on: the balance position (velocity input)
#: or the position inputs at the end of initialization (position input)
_PROBE_START = _FLIGHT + ("probe_position_input",) + _PROBE_POSITION
#: the variables the tip's start velocity depends on: the velocity inputs with the velocity feed
_PROBE_START_V = ("probe_position_input", "probe_velocity_feed") + _PROBE_VELOCITY

#: The engagement FMU: the hose on its reel, the drogue and the receiver's probe of a frozen scenario.
ENGAGEMENT_FMU = FmuInterface(
    kind="engagement",
    model_name="HoseDrogueEngagement",
    slave_module="hosedrogue.interop.fmu_slave",
    summary=("Probe-and-drogue refuelling engagement: the hose of varying length on its reel, the drogue, and the "
             "receiver's probe flown by the inputs through the capture test and the coupling (hosedrogue's "
             "engagement model, a scenario frozen at export); frame S_p: x forward, y right, z down, origin at the "
             "tow point; SI units"),
    notes=("The FMU starts at rest at the balance position of the flight condition (the parameters), solved when "
           "initialization ends, and runs the frozen scenario's duration_s (the DefaultExperiment's stop time; its "
           "turbulence record is drawn for it). It advances in whole control samples of sample_time_s (a whole "
           "multiple of the scenario's integration step numerics.step_s: RK4, or the SDIRK of an elastic hose); a "
           "communication step must be a whole multiple of sample_time_s and start where the FMU is, else the FMU "
           "refuses it (fmi2Discard, nothing advanced, the reason logged). The inputs are held over the step. "
           "probe_position_input true: the probe tip moves from "
           "where it is to probe_cmd_x/y/z_m, which it reaches at the end of the step (no receiver response: the "
           "master's path passes through; the tip starts at the position inputs' values at the end of "
           "initialization) on a parabola of constant acceleration from its position with the slope there of "
           "the parabola through the last three positions (where it was a step before, where it is, the input; "
           "on the first step the straight line), so a smooth path is followed to O(h^3) in position (a kink in "
           "the path overshoots the chord by at most |dv| h / 8 in the step after it); with probe_velocity_feed "
           "true on the cubic from its position and velocity (probe_cmd_vx/vy/vz_m_s at the end of the step "
           "before; at the start their values at the end of initialization) to the position and velocity inputs, "
           "to O(h^4) in position. The tip is that curve as a function of time, met by the hose at every "
           "integration stage's time as a prescribed probe path is; false: probe_cmd_vx/vy/vz_m_s is the velocity "
           "command of the receiver's response (the scenario's [receiver]: lag, speed and acceleration bounds; "
           "the tip starts at the [probe] start point moving forward at its closure speed). reel_speed_cmd_m_s "
           "commands a reel of "
           "law \"python\" (unused with a built-in law), u_y_n/u_z_n the drogue's force through the [actuator] (or "
           "the [drogue_actuator]'s control surfaces, mixed at the measured dynamic pressure) until "
           "the probe couples (unused with a built-in drogue controller). Outputs are those of the state at the "
           "communication point, with the commands of the step that led there (no direct feedthrough). A run that "
           "fails (non-finite state, yaw limit, the reel at an end stop), ends (a miss or failed latch at the coupler "
           "plane, the end of duration_s) or gets a non-finite input returns fmi2Discard and logs its time and "
           "reason (status fmi2Discard, category logStatusDiscard; pythonfmu forwards log messages only with the "
           "importer's debug logging on)."),
    variables=(
        FmuVariable("altitude_m", "parameter", "flight altitude", field="flight.altitude_m"),
        FmuVariable("airspeed_m_s", "parameter", "true airspeed", field="flight.airspeed_m_s"),
        FmuVariable("wake_enabled", "parameter", "tanker wake on/off", kind="Boolean", field="wake.enabled"),
        FmuVariable("sample_time_s", "parameter", "control sample: the FMU advances in whole samples (a whole "
                    "multiple of numerics.step_s); communication steps are whole multiples of it"),
        FmuVariable("probe_position_input", "parameter", "true: the probe tip follows the position inputs "
                    "probe_cmd_x/y/z_m; false: the velocity command inputs probe_cmd_vx/vy/vz_m_s through the "
                    "receiver's response", kind="Boolean"),
        FmuVariable("probe_velocity_feed", "parameter", "with probe_position_input: the velocity inputs give the "
                    "tip's velocity at the end of each step too: within a step it moves on the cubic from its "
                    "position and the velocity given to the position and velocity inputs (else on the parabola "
                    "leaving with the slope of the parabola through the last three positions)", kind="Boolean"),
        *(FmuVariable(f"probe_cmd_{a}_m", "input", f"probe-tip position along S_p {a} ({d}) at the end of the "
                      "communication step (probe_position_input; at the end of initialization: where the tip starts)")
          for a, d in _AXES),
        *(FmuVariable(f"probe_cmd_v{a}_m_s", "input", f"probe-tip velocity command along S_p {a} ({d}), through the "
                      "receiver's response (probe_position_input false); with probe_position_input and "
                      "probe_velocity_feed: the tip's velocity at the end of the communication step (at the end of "
                      "initialization: its start velocity)") for a, d in _AXES),
        FmuVariable("reel_speed_cmd_m_s", "input", "take-up speed command, positive reeling in, followed by the "
                    "drive within the motor's limits (a reel of law \"python\"; unused with a built-in law)"),
        FmuVariable("u_y_n", "input", "control force at the drogue along S_p y (right) until the probe couples "
                    "(unused with a built-in drogue controller)"),
        FmuVariable("u_z_n", "input", "control force at the drogue along S_p z (down) until the probe couples "
                    "(unused with a built-in drogue controller)"),
        *(FmuVariable(f"drogue_{a}_m", "output", f"drogue position along S_p {a}", initial_depends_on=_FLIGHT)
          for a, _ in _AXES),
        *(FmuVariable(f"drogue_v{a}_m_s", "output", f"drogue velocity along S_p {a}, relative to the tow point")
          for a, _ in _AXES),
        *(FmuVariable(f"probe_{a}_m", "output", f"probe-tip position along S_p {a}", initial_depends_on=_PROBE_START)
          for a, _ in _AXES),
        *(FmuVariable(f"probe_v{a}_m_s", "output", f"probe-tip velocity along S_p {a} (at the start: "
                      + ("the probe's closure speed" if a == "x" else "0") + ", or with the velocity feed the "
                      "velocity inputs)", initial_depends_on=_PROBE_START_V) for a, _ in _AXES),
        FmuVariable("coupled", "output", "the probe has captured the drogue and holds it", kind="Boolean"),
        FmuVariable("probe_load_n", "output", "magnitude of the probe's force on the drogue (0 until coupled)"),
        *(FmuVariable(f"probe_force_{a}_n", "output", f"the probe's force on the drogue along S_p {a} (the "
                      "receiver's probe feels its opposite)") for a, _ in _AXES),
        # the bow wave of a probe at its start point acts on the hose: the tension depends on where that is
        FmuVariable("exit_tension_n", "output", "hose tension at the reel exit", initial_depends_on=_PROBE_START),
        FmuVariable("hose_length_m", "output", "free hose length from the reel exit to the drogue"),
        FmuVariable("reel_speed_m_s", "output", "take-up speed, positive reeling in"),
    ),
)


class EngagementCore:
    """The engagement FMU's simulation, independent of pythonfmu (tested directly and through fmpy).

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The frozen scenario (:func:`~hosedrogue.interop.fmu_frozen.fmu_scenario`).
    altitude_m, airspeed_m_s : float
        Flight condition [m], [m/s].
    wake_enabled : bool
        Tanker wake on or off.
    sample_time_s : float
        Control sample [s], a whole multiple of ``numerics.step_s``.
    position_input : bool
        The probe follows positions (passing through, no receiver response) instead of velocity
        commands: within a step on a parabola leaving with the slope of the parabola through the
        last three positions (:meth:`_probe_motion`).
    velocity_feed : bool
        With ``position_input``: the velocity inputs are the tip's velocity at the end of each
        step, and within a step the tip moves on the cubic through both ends' positions and
        velocities instead.
    probe_start_m : array_like (3,), optional
        Where the probe tip starts [m] (the position input at the end of initialization); default
        the ``[probe]`` start point.
    probe_start_velocity_m_s : array_like (3,), optional
        With ``velocity_feed``: the tip's velocity at the start [m/s] (the velocity inputs at the
        end of initialization); default the closure speed forward.
    equilibria : dict, optional
        Balance positions solved before, by flight condition (filled in; a rebuild during
        initialization reuses them).

    Raises
    ------
    ParameterError
        A flight condition or sample time the model cannot take.
    """

    def __init__(self, scenario, *, altitude_m: float, airspeed_m_s: float, wake_enabled: bool,
                 sample_time_s: float, position_input: bool, velocity_feed: bool = False, probe_start_m=None,
                 probe_start_velocity_m_s=None, equilibria: dict | None = None):
        from ..engagement.balance import engagement_equilibrium
        from ..engagement.chain import initial_chain
        from ..engagement.stepper import EngagementStepper
        from ..scenarios.runner import drogue_controller
        from ..simulation.stepper import whole_multiple

        params = scenario.params.replace(flight={"altitude_m": float(altitude_m), "airspeed_m_s": float(airspeed_m_s)},
                                         wake={"enabled": bool(wake_enabled)})
        whole_multiple(float(sample_time_s), params.numerics.step_s, "sample_time_s", "numerics.step_s")
        sc = dataclasses.replace(scenario, params=params)
        e = sc.engagement
        key = json.dumps([float(altitude_m), float(airspeed_m_s), bool(wake_enabled)])
        equilibria = {} if equilibria is None else equilibria
        if key not in equilibria:
            equilibria[key] = engagement_equilibrium(params, initial_chain(params), sc.duration_s, controlled=True)[0]
        control = drogue_controller(sc)
        self.scenario, self.position_input = sc, bool(position_input)
        self.velocity_feed = self.position_input and bool(velocity_feed)
        start_v = probe_start_velocity_m_s if self.velocity_feed else None
        self.commands_reel = e.reel.law == "python"
        self.stepper = EngagementStepper(
            params, sc.duration_s, control_step_s=float(sample_time_s), reel=e.reel, probe=e.probe,
            bow_wave=e.bow_wave, receiver=e.receiver, control=control, drogue_command=control is None,
            actuator=sc.loop.actuator, sensor=Sensor(), equilibrium=equilibria[key], record=False,
            drogue_actuator=sc.loop.drogue_actuator,
            receiver_pass_through=self.position_input, probe_start_m=probe_start_m if self.position_input else None,
            probe_start_velocity_m_s=start_v)
        self.m = self.stepper.reset()
        self._v_start = self.m.probe_velocity_m_s.copy()  # with the velocity feed: the next step's start velocity
        self._previous = None  # positions only: (where the tip was one step before [m], that step [s])
        self.t0_s = 0.0  #: the FMU's time at the run's t = 0 [s] (the experiment's start time)

    @property
    def t_s(self) -> float:
        """The FMU's time [s]: the experiment's start time plus the run's."""
        return self.t0_s + self.stepper.t_s

    @property
    def end_s(self) -> float:
        """The FMU's time at the end of the run [s]."""
        return self.t0_s + self.stepper.duration_s

    def _commands(self, inputs: dict, h_s: float) -> dict:
        """The stepper's commands from the held inputs (a non-finite input refuses the step)."""
        for name, value in inputs.items():
            if not math.isfinite(value):
                raise StepFailure(self.t_s, f"input {name} = {value!r}: must be a finite number", final=False)
        commands = {}
        if self.position_input:
            self._motion = self._probe_motion(inputs, h_s)
        else:
            commands["receiver"] = tuple(inputs[n] for n in _PROBE_VELOCITY)
        if self.commands_reel:
            commands["reel"] = inputs["reel_speed_cmd_m_s"]
        if "drogue" in self.stepper.roles:
            commands["drogue"] = (inputs["u_y_n"], inputs["u_z_n"])
        return commands

    def _probe_motion(self, inputs: dict, h_s: float) -> tuple:
        """The tip's velocity [m/s] and acceleration [m/s^2] at the step's start and its jerk
        [m/s^3] over the step, which take it from where it is to the position input at the step's
        end.

        With the velocity feed the cubic (Hermite) from where the tip is at the velocity given for
        the step's start (the velocity inputs of the step before) to the position and velocity
        inputs: a smooth path followed to O(h^4) in position, O(h^3) in velocity. Else the
        parabola leaving with the slope at the step's start of the parabola through the last
        three positions (where the tip was one step before, where it is, the input; on the first
        step the straight line): O(h^3) in position.
        """
        p0, p1 = self.m.probe_position_m.copy(), np.array([inputs[n] for n in _PROBE_POSITION])
        chord = (p1 - p0) / h_s
        if self.velocity_feed:
            v0 = self._v_start
            v1 = np.array([inputs[n] for n in _PROBE_VELOCITY])
            self._v_start = v1  # if the step is taken
            return v0, (6.0 * chord - 4.0 * v0 - 2.0 * v1) / h_s, (6.0 * (v0 + v1) - 12.0 * chord) / (h_s * h_s)
        if self._previous is not None:
            p_prev, h0 = self._previous
            w = h0 + h_s
            v0 = chord * (h0 / w) + (p0 - p_prev) / h0 * (h_s / w)
        else:
            v0 = chord
        self._previous = (p0, h_s)
        return v0, 2.0 * (chord - v0) / h_s, np.zeros(3)

    def _ended(self) -> str:
        """Why the run is over (it failed, or ended at a miss or at its duration)."""
        st = self.stepper
        if not st.completed:
            return st.message.split(": ", 1)[1] if st.message.startswith("stopped at") else st.message
        result = st.outcome["result"]
        if result not in ("captured", "no contact"):
            return (f"the probe's contact at t = {self.t0_s + st.outcome['contact_time_s']:.6g} s ended the run: "
                    f"{result}")
        return (f"the run ended at t = {self.end_s:.6g} s, the frozen scenario's duration_s = {st.duration_s:g} s "
                "(export a longer one to go on)")

    def step(self, t_s: float, h_s: float, inputs: dict) -> None:
        """Advance from ``t_s`` by ``h_s`` [s], a whole number of control samples, with ``inputs`` held.

        Parameters
        ----------
        t_s : float
            Communication point at the start of the step [s]; must be the FMU's time.
        h_s : float
            Communication step [s], a whole multiple of the sample time.
        inputs : dict
            Every input of :data:`ENGAGEMENT_FMU` by name, in the unit of its name.

        Raises
        ------
        StepFailure
            ``final``: the run failed or ended during the step (the reason; its time); not
            ``final``: the step was refused before advancing (a time other than the FMU's, a step
            that is not a whole multiple of the sample time, a non-finite input).
        """
        from ..simulation.stepper import whole_multiple

        st = self.stepper
        if abs(t_s - self.t_s) > TIME_RTOL * max(1.0, abs(self.t_s)):
            raise StepFailure(t_s, f"the FMU is at t = {self.t_s!r} s, not {t_s!r} s (it steps on from where it is)",
                              final=False)
        try:
            samples = whole_multiple(h_s, st.control_step_s, "the communication step", "sample_time_s")
        except ParameterError as exc:
            raise StepFailure(t_s, str(exc), final=False) from None
        if st.done:
            raise StepFailure(self.t_s, self._ended())
        commands = self._commands(inputs, samples * st.control_step_s)
        target = st.step_index + samples * st.spc
        if self.position_input:
            st.move_receiver(*self._motion)
        self.m = st.step(samples=samples, **commands)
        if st.step_index < target:
            raise StepFailure(self.t_s, self._ended())

    def outputs(self) -> dict:
        """The outputs of :data:`ENGAGEMENT_FMU` at the current state.

        Returns
        -------
        dict
            By name: floats in the unit of the name, ``coupled`` a bool.
        """
        m, force = self.m, self.stepper.probe_force_n
        values = {}
        for i, (a, _) in enumerate(_AXES):
            values[f"drogue_{a}_m"] = float(m.drogue_position_m[i])
            values[f"drogue_v{a}_m_s"] = float(m.drogue_velocity_m_s[i])
            values[f"probe_{a}_m"] = float(m.probe_position_m[i])
            values[f"probe_v{a}_m_s"] = float(m.probe_velocity_m_s[i])
            values[f"probe_force_{a}_n"] = float(force[i])
        values["coupled"] = bool(m.coupled)
        values["probe_load_n"] = float(np.linalg.norm(force))
        values["exit_tension_n"] = float(m.exit_tension_n)
        values["hose_length_m"] = float(m.hose_length_m)
        values["reel_speed_m_s"] = float(m.reel_speed_m_s)
        return values


def fmu_starts(scenario, sample_time_s: float) -> dict:
    """The start values of the engagement FMU's parameters and inputs for a frozen scenario.

    The position inputs start at the ``[probe]`` start point at the scenario's flight condition
    (solved here), the velocity inputs at the probe's closure speed forward: without inputs the
    tip closes on the drogue in a straight line, as the scenario's prescribed probe does.

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The frozen scenario (:func:`~hosedrogue.interop.fmu_frozen.fmu_scenario`).
    sample_time_s : float
        The start of ``sample_time_s`` [s] (:func:`default_sample_time`).

    Returns
    -------
    dict
        Name -> value (float in the unit of its name, or bool).
    """
    p = scenario.params
    core = EngagementCore(scenario, altitude_m=p.flight.altitude_m, airspeed_m_s=p.flight.airspeed_m_s,
                          wake_enabled=p.wake.enabled, sample_time_s=sample_time_s, position_input=False)
    out = core.outputs()
    starts = {"altitude_m": p.flight.altitude_m, "airspeed_m_s": p.flight.airspeed_m_s,
              "wake_enabled": bool(p.wake.enabled), "sample_time_s": float(sample_time_s),
              "probe_position_input": False, "probe_velocity_feed": False, "reel_speed_cmd_m_s": 0.0, "u_y_n": 0.0,
              "u_z_n": 0.0}
    starts.update({f"probe_cmd_{a}_m": out[f"probe_{a}_m"] for a, _ in _AXES})
    starts.update({f"probe_cmd_v{a}_m_s": v for (a, _), v in zip(_AXES, (scenario.engagement.probe.closure_speed_m_s,
                                                                           0.0, 0.0))})
    return starts

