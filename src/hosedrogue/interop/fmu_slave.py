"""The pythonfmu slave classes inside an exported FMU (see :mod:`hosedrogue.interop.fmu`).

Importing this module needs ``pythonfmu`` (the ``fmu`` extra; inside an FMU, the copy pythonfmu
puts in its ``resources``). The FMU's generated entry-point script imports its slave class from
here, so the FMU always runs the installed model code.

:class:`InterfaceSlave` registers the variables of an
:class:`~hosedrogue.interop.fmu_interface.FmuInterface` and completes pythonfmu's model description
from it; :class:`HoseDrogue` is the fixed-length FMU on top of it, :class:`HoseDrogueEngagement`
the engagement FMU.
"""

from __future__ import annotations

from pythonfmu import Boolean, DefaultExperiment, Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Real
from pythonfmu import __version__ as PYTHONFMU_VERSION
from pythonfmu.enums import Fmi2Status

from ..version import __version__
from .fmu_core import HOSE_FMU, HoseDrogueCore, fmu_params, load_exported_params, parameter_starts
from .fmu_engagement import ENGAGEMENT_FMU, EngagementCore
from .fmu_frozen import frozen_summary, load_exported_scenario
from .fmu_interface import FmuInterface, StepFailure, check_interface
from .fmu_description import complete_model_description

#: Stop time of the FMUs' ``DefaultExperiment`` [s] (a start for an importer; any stop time works).
DEFAULT_STOP_S = 10.0

#: References to the FMU entry-point script's globals, one per execution of the script (see
#: :func:`hold_entry_point_globals`); they are never released.
_ENTRY_POINT_GLOBALS: list[dict] = []


def hold_entry_point_globals(namespace: dict) -> None:
    """Hold one more reference to the globals of the FMU's entry-point script (the script calls this).

    pythonfmu 0.7's binary, each time it instantiates an FMU, executes the entry-point script in
    the module's globals and then releases a reference to that dict which it never owned
    (``findClass``: ``Py_DECREF`` of the borrowed ``PyModule_GetDict`` result). The dict is freed
    while the module still uses it, and whatever Python allocates next in its place loses a
    reference later: in a Python host that surfaced as emptied modules (``scipy.optimize``), a
    class the next instantiation could not find, and segmentation faults in a later garbage
    collection. Every execution of the script holds one reference here, at least as many as the
    binary takes away, so the dict lives as long as the process (a few hundred bytes per FMU
    instance).

    Parameters
    ----------
    namespace : dict
        The script's ``globals()``.
    """
    _ENTRY_POINT_GLOBALS.append(namespace)


class InterfaceSlave(Fmi2Slave):
    """A pythonfmu slave whose variables are those of :attr:`interface` (set by a subclass).

    Parameters
    ----------
    **kwargs
        Passed by pythonfmu: ``instance_name``, ``resources`` (the unpacked FMU's resources
        folder), ``visible``.
    """

    interface: FmuInterface
    #: What this export froze, for the model description (:func:`~.fmu_description.model_description_text`).
    details: str = ""

    def register_interface(self, output, starts: dict) -> None:
        """Register the interface's variables as attributes of this slave, in the table's order.

        Parameters
        ----------
        output : callable
            ``output(name) -> float or bool``: an output's current value (computed when it is read).
        starts : dict
            Start value of each parameter, and of the inputs whose start is not the table's, by
            name (in the unit of its name, or bool).
        """
        for v in self.interface.variables:
            description = v.description
            kind = Boolean if v.kind == "Boolean" else Real
            if v.causality == "output":
                # FMI 2.0: a Boolean is never continuous
                variability = Fmi2Variability.discrete if v.kind == "Boolean" else Fmi2Variability.continuous
                self.register_variable(kind(v.name, causality=Fmi2Causality.output, variability=variability,
                                            initial=Fmi2Initial.calculated, description=description,
                                            getter=lambda name=v.name: output(name)))
                continue
            if v.causality == "parameter":
                setattr(self, v.name, starts[v.name])
                causality, variability = Fmi2Causality.parameter, Fmi2Variability.fixed
            else:
                setattr(self, v.name, float(starts.get(v.name, v.start)))
                causality, variability = Fmi2Causality.input, Fmi2Variability.continuous
            self.register_variable(kind(v.name, causality=causality, variability=variability, description=description))

    def to_xml(self, model_options: dict | None = None):
        """pythonfmu's model description, completed from :attr:`interface` (units, model structure).

        Parameters
        ----------
        model_options : dict, optional
            FMU options, passed to pythonfmu.

        Returns
        -------
        xml.etree.ElementTree.Element
        """
        root = super().to_xml(model_options or {})
        return complete_model_description(root, self.interface,
                                          f"hosedrogue {__version__} (PythonFMU {PYTHONFMU_VERSION})", self.details)

    def log_failure(self, failure: StepFailure) -> None:
        """Log why a step was not taken, through the FMI logger (status fmi2Discard, category
        ``logStatusDiscard``: what ``fmi2DoStep`` returns then).

        Parameters
        ----------
        failure : StepFailure
            The time and the reason.
        """
        self.log(f"hosedrogue: {failure}", Fmi2Status.discard, "logStatusDiscard")


class HoseDrogue(InterfaceSlave):
    """FMI 2.0 co-simulation slave of the fixed-length hose (:data:`~hosedrogue.interop.fmu_core.HOSE_FMU`).

    Outputs are computed when read, from the current state and the current inputs (the tow
    tension feeds through from the force and gust inputs); before initialization ends they are
    those of the balance position of the current parameters.

    Parameters
    ----------
    **kwargs
        Passed by pythonfmu: ``instance_name``, ``resources`` (the unpacked FMU's resources
        folder, which holds the exported parameter set), ``visible``.
    """

    interface = HOSE_FMU
    author = "hosedrogue"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        check_interface(self.resources, self.interface)
        self._base = load_exported_params(self.resources)
        self.version = __version__
        self.default_experiment = DefaultExperiment(start_time=0.0, stop_time=DEFAULT_STOP_S,
                                                    step_size=self._base.numerics.step_s)
        self._core: HoseDrogueCore | None = None
        self._core_key = None  # the parameters the core was built for, until initialization ends
        self._started = False
        self._steps = 0
        self._failure: StepFailure | None = None
        self._values: dict[str, float] = {}
        self._values_key = None
        self.register_interface(self._output, parameter_starts(self.interface, self._base))

    def _flight(self) -> tuple[float, float, bool]:
        return float(self.altitude_m), float(self.airspeed_m_s), bool(self.wake_enabled)

    def _inputs(self) -> tuple[float, ...]:
        return tuple(float(getattr(self, v.name)) for v in self.interface.of("input"))

    def _model(self) -> HoseDrogueCore:
        """The simulation: fixed once initialization ends, rebuilt for new parameters before."""
        if not self._started and self._core_key != self._flight():
            self._core = HoseDrogueCore(fmu_params(self._base, *self._flight()))
            self._core_key = self._flight()
        return self._core

    def _hold_inputs(self, core: HoseDrogueCore) -> tuple[float, float]:
        u_y, u_z, gust_u, gust_v, gust_w = self._inputs()
        core.set_gust((gust_u, gust_v, gust_w))
        core.set_force((u_y, u_z))
        return u_y, u_z

    def _output(self, name: str) -> float:
        key = (self._steps if self._started else self._flight(), self._inputs())
        if key != self._values_key:
            core = self._model()
            self._hold_inputs(core)
            self._values = core.outputs()
            self._values_key = key
        return self._values[name]

    def exit_initialization_mode(self):
        """Build the model for the parameters set by the importer; it starts at their balance position."""
        self._model()
        self._started = True

    def do_step(self, current_time: float, step_size: float) -> bool:
        """Advance by ``step_size`` [s] with the inputs held; False (fmi2Discard) if the run failed.

        The reason (time, non-finite state or yaw limit) goes to the FMI logger with status
        fmi2Discard, category ``logStatusDiscard``; every later step fails the same way.

        Parameters
        ----------
        current_time : float
            Communication point at the start of the step [s].
        step_size : float
            Communication step [s].

        Returns
        -------
        bool
            True if the step was taken.
        """
        if self._failure is None:
            core = self._model()
            try:
                core.step(current_time, step_size, self._hold_inputs(core))
            except StepFailure as exc:
                self._failure = exc
            else:
                self._steps += 1
                return True
        self.log_failure(self._failure)
        return False


class HoseDrogueEngagement(InterfaceSlave):
    """FMI 2.0 co-simulation slave of the engagement (:data:`~hosedrogue.interop.fmu_engagement.ENGAGEMENT_FMU`),
    on :class:`~hosedrogue.interop.fmu_engagement.EngagementCore`.

    Outputs are those of the state at the communication point (no direct feedthrough); before
    initialization ends they are those of the start for the current parameters (and, with the
    position input, the position inputs as the tip's start).

    Parameters
    ----------
    **kwargs
        Passed by pythonfmu: ``instance_name``, ``resources`` (the unpacked FMU's resources
        folder, which holds the frozen scenario), ``visible``.
    """

    interface = ENGAGEMENT_FMU
    author = "hosedrogue"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        check_interface(self.resources, self.interface)
        self._scenario, starts = load_exported_scenario(self.resources)
        self.details = frozen_summary(self._scenario)
        self.version = __version__
        self.default_experiment = DefaultExperiment(start_time=0.0, stop_time=self._scenario.duration_s,
                                                    step_size=starts["sample_time_s"])
        self._core: EngagementCore | None = None
        self._core_key = None
        self._equilibria: dict = {}  # balance positions by flight condition, for rebuilds before the start
        self._start_s = 0.0
        self._started = False
        self._failure: StepFailure | None = None
        self._steps = 0
        self._values: dict = {}
        self._values_key = None
        self.register_interface(self._output, starts)

    def _settings(self) -> tuple:
        """What the simulation is built from: parameters and, with the position input, the tip's
        start (and with the velocity feed its start velocity)."""
        position = bool(self.probe_position_input)
        feed = position and bool(self.probe_velocity_feed)
        start = tuple(float(getattr(self, f"probe_cmd_{a}_m")) for a in "xyz")
        start_v = tuple(float(getattr(self, f"probe_cmd_v{a}_m_s")) for a in "xyz")
        return (float(self.altitude_m), float(self.airspeed_m_s), bool(self.wake_enabled), float(self.sample_time_s),
                position, feed, start if position else None, start_v if feed else None)

    def _model(self) -> EngagementCore:
        """The simulation: fixed once initialization ends, rebuilt for new settings before."""
        key = self._settings()
        if not self._started and self._core_key != key:
            altitude, airspeed, wake, sample, position, feed, start, start_v = key
            self._core = EngagementCore(self._scenario, altitude_m=altitude, airspeed_m_s=airspeed,
                                        wake_enabled=wake, sample_time_s=sample, position_input=position,
                                        velocity_feed=feed, probe_start_m=start, probe_start_velocity_m_s=start_v,
                                        equilibria=self._equilibria)
            self._core.t0_s = self._start_s
            self._core_key = key
        return self._core

    def _output(self, name: str):
        key = self._steps if self._started else self._settings()
        if key != self._values_key:
            self._values = self._model().outputs()
            self._values_key = key
        return self._values[name]

    def setup_experiment(self, start_time: float, stop_time, tolerance):
        """Take the experiment's start time as the run's t = 0; warn if its stop time is past the run's end.

        Parameters
        ----------
        start_time : float
            [s]
        stop_time : float or None
            [s]
        tolerance : float or None
            Unused (fixed steps: RK4, or the SDIRK of an elastic hose).
        """
        self._start_s = float(start_time)
        if self._core is not None:
            self._core.t0_s = self._start_s
        end = self._start_s + self._scenario.duration_s
        if stop_time is not None and stop_time > end * (1.0 + 1e-12):
            self.log(f"hosedrogue: the run ends at t = {end:g} s (the frozen scenario's duration_s = "
                     f"{self._scenario.duration_s:g} s); the experiment's stop time {stop_time:g} s is past it: "
                     "steps beyond it will fail", Fmi2Status.warning, "logStatusWarning")

    def exit_initialization_mode(self):
        """Build the simulation for the parameters (and start) the importer set."""
        try:
            self._model()
        except Exception as exc:  # a parameter the model cannot take: say which, then fail the call
            self.log(f"hosedrogue: {exc}", Fmi2Status.error, "logStatusError")
            raise
        self._started = True

    def do_step(self, current_time: float, step_size: float) -> bool:
        """Advance by ``step_size`` [s] with the inputs held; False (fmi2Discard) if the step was not taken.

        The reason goes to the FMI logger with status fmi2Discard, category ``logStatusDiscard``;
        after a failure that ends the run every later step fails the same way, a refused step
        (wrong time or step size, a non-finite input) leaves the FMU where it was.

        Parameters
        ----------
        current_time : float
            Communication point at the start of the step [s].
        step_size : float
            Communication step [s].

        Returns
        -------
        bool
            True if the step was taken.
        """
        if self._failure is None:
            inputs = {v.name: float(getattr(self, v.name)) for v in self.interface.of("input")}
            try:
                self._model().step(current_time, step_size, inputs)
            except StepFailure as exc:
                if exc.final:
                    self._failure = exc
                self.log_failure(exc)
                return False
            self._steps += 1
            return True
        self.log_failure(self._failure)
        return False
