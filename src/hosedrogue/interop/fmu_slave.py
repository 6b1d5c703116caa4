"""The pythonfmu slave class inside an exported FMU (see :mod:`hosedrogue.interop.fmu`).

Importing this module needs ``pythonfmu`` (the ``fmu`` extra). The FMU's generated entry-point
script imports :class:`HoseDrogue` from here, so the FMU always runs the installed model code.
"""

from __future__ import annotations

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Real
from pythonfmu.enums import Fmi2Status

from ..errors import EquilibriumError, ParameterError
from .fmu import (
    FMU_INPUTS,
    FMU_OUTPUTS,
    FMU_REAL_PARAMETERS,
    HoseDrogueCore,
    StepFailure,
    fmu_params,
    load_exported_params,
)


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


class HoseDrogue(Fmi2Slave):
    """FMI 2.0 co-simulation slave of the hose-drogue model (pythonfmu).

    Parameters
    ----------
    **kwargs
        Passed by pythonfmu: ``instance_name``, ``resources`` (the unpacked FMU's resources
        folder, which holds the exported parameter set), ``visible``.
    """

    author = "hosedrogue"
    description = ("Probe-and-drogue refuelling hose, rigid-link Kane model (after Wu et al., 2018); "
                   "frame S_p: x forward, y right, z down; SI units")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._base = load_exported_params(self.resources)
        self.altitude_m = float(self._base.flight.altitude_m)
        self.airspeed_m_s = float(self._base.flight.airspeed_m_s)
        self.wake_enabled = bool(self._base.wake.enabled)
        for name, _unit, _text in FMU_INPUTS:
            setattr(self, name, 0.0)
        for name, _unit, _text in FMU_OUTPUTS:
            setattr(self, name, 0.0)
        self._core: HoseDrogueCore | None = None
        for name, unit, text in FMU_REAL_PARAMETERS:
            self.register_variable(Real(name, causality=Fmi2Causality.parameter,
                                        variability=Fmi2Variability.fixed, description=f"{text} [{unit}]"))
        self.register_variable(Boolean("wake_enabled", causality=Fmi2Causality.parameter,
                                       variability=Fmi2Variability.fixed, description="tanker wake on/off"))
        for name, unit, text in FMU_INPUTS:
            self.register_variable(Real(name, causality=Fmi2Causality.input,
                                        variability=Fmi2Variability.continuous, description=f"{text} [{unit}]"))
        for name, unit, text in FMU_OUTPUTS:
            self.register_variable(Real(name, causality=Fmi2Causality.output,
                                        variability=Fmi2Variability.continuous, description=f"{text} [{unit}]"))
        self._seed_outputs()

    def _seed_outputs(self) -> None:
        """Outputs of the exported flight condition's balance position, if it can be solved cheaply
        (it is solved again at initialization with the parameters the importer set)."""
        try:
            core = HoseDrogueCore(fmu_params(self._base, self.altitude_m, self.airspeed_m_s, self.wake_enabled))
        except (ParameterError, EquilibriumError):
            return
        self._publish(core)

    def _publish(self, core: HoseDrogueCore) -> None:
        for name, value in core.outputs().items():
            setattr(self, name, value)

    def exit_initialization_mode(self):
        """Build the model for the parameters set by the importer and start at its balance position."""
        params = fmu_params(self._base, self.altitude_m, self.airspeed_m_s, self.wake_enabled)
        self._core = HoseDrogueCore(params)
        self._core.set_gust((self.gust_u_m_s, self.gust_v_m_s, self.gust_w_m_s))
        self._core.set_force((self.u_hor_n, self.u_ver_n))
        self._publish(self._core)

    def do_step(self, current_time: float, step_size: float) -> bool:
        """Advance by ``step_size`` [s] with the inputs held; False (fmi2Error) if the run diverged.

        Parameters
        ----------
        current_time : float
            Communication point at the start of the step [s].
        step_size : float
            Communication step [s].
        """
        core = self._core
        core.set_gust((self.gust_u_m_s, self.gust_v_m_s, self.gust_w_m_s))
        try:
            core.step(current_time, step_size, (self.u_hor_n, self.u_ver_n))
        except StepFailure as exc:
            self.log(f"hosedrogue: {exc}", Fmi2Status.error)
            return False
        self._publish(core)
        return True
