"""What an exported FMU is, independent of pythonfmu: its interface table, the simulation it runs,
and the exported parameter set it reads (see :mod:`hosedrogue.interop.fmu` for the export).

An FMU's interface is one :class:`FmuInterface`: its variables in value-reference order, each with
its causality, description, start (inputs) or parameter field (parameters), and, for outputs,
which inputs act on it at the same instant and which variables its initial value depends on. The
slave (:mod:`hosedrogue.interop.fmu_slave`) registers the variables from the table and
:func:`hosedrogue.interop.fmu_description.complete_model_description` writes the units and the
model structure from it, so a second FMU is a second table.

The fixed-length FMU (:data:`HOSE_FMU`), SI units, frame S_p (x forward, y right, z down, origin
at the tow point):

===================================  ==========  ================================================
variable                             causality   meaning
===================================  ==========  ================================================
``altitude_m``, ``airspeed_m_s``     parameter   flight condition [m], [m/s]
``wake_enabled``                     parameter   tanker wake on/off
``u_y_n``, ``u_z_n``                 input       control force at the drogue, S_p y and z [N]
``gust_u_m_s`` .. ``gust_w_m_s``     input       gust velocity along S_p x, y, z [m/s], uniform
``drogue_x_m`` .. ``drogue_z_m``     output      drogue position [m]
``drogue_vx_m_s`` .. ``_vz_m_s``     output      drogue velocity [m/s]
``tow_tension_n``                    output      magnitude of the force at the tow point [N]
===================================  ==========  ================================================

Inputs are held over a communication step (zero-order hold); the step is split into sub-steps no
longer than ``numerics.step_s`` of :func:`hosedrogue.simulation.simulate.rk4_step_python` on
:meth:`hosedrogue.model.system.HoseModel.derivative`, the arithmetic of :func:`hosedrogue.simulate`
with a control function. The FMU starts at rest at the balance position of its flight condition in
still air.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from ..params import PAPER, Params, params_from_dict
from ..units import NO_UNIT, unit_of
from ..version import __version__

#: File in the FMU's ``resources`` folder holding the exported parameter set (JSON).
PARAMS_RESOURCE = "hosedrogue_params.json"

#: File in the FMU's ``resources`` folder naming the exporting package version, the FMU kind and
#: its variables (JSON); the slave refuses to run an FMU whose variables it does not have.
INTERFACE_RESOURCE = "hosedrogue_interface.json"

#: Where the exported FMUs were run, for the model description and the documentation.
TESTED_ON = ("Linux x86_64 (linux64) with CPython 3.11, FMU run in-process by fmpy 0.3.32 "
             "(pythonfmu 0.7.0); the win64 binary is pythonfmu's and was not run")

CAUSALITIES = ("parameter", "input", "output")


@dataclass(frozen=True)
class FmuVariable:
    """One variable of an FMU's interface; its unit is :func:`hosedrogue.units.unit_of` its name."""

    name: str  #: variable name, with the unit suffix of the project's names
    causality: str  #: ``"parameter"``, ``"input"`` or ``"output"``
    description: str  #: what it is (frame, sign), without the unit
    kind: str = "Real"  #: FMI type, ``"Real"`` or ``"Boolean"``
    field: str | None = None  #: parameters: the ``section.name`` of :class:`Params` it sets
    start: float = 0.0  #: inputs: value until the importer sets one [unit of the name]
    #: outputs: the inputs that act on it at the same instant (direct feedthrough)
    depends_on: tuple[str, ...] = ()
    #: outputs: the parameters and inputs its value at the end of initialization depends on
    initial_depends_on: tuple[str, ...] = ()

    @property
    def unit(self) -> str | None:
        """The variable's unit symbol, None for a Boolean or a name without a unit suffix."""
        unit = unit_of(self.name)
        return None if self.kind != "Real" or unit == NO_UNIT else unit


@dataclass(frozen=True)
class FmuInterface:
    """The variables of one FMU, in value-reference order (0, 1, ...; FMI index = reference + 1)."""

    kind: str  #: short name of the FMU, e.g. ``"fixed-length"``
    model_name: str  #: FMI ``modelName`` and ``modelIdentifier``: the slave class's name
    slave_module: str  #: the module defining the slave class (imported by the FMU's entry point)
    summary: str  #: one sentence: what the FMU simulates
    notes: str  #: how it starts, steps and fails (for its documentation page)
    variables: tuple[FmuVariable, ...]  #: parameters, inputs and outputs

    def __post_init__(self):
        names = [v.name for v in self.variables]
        if len(set(names)) != len(names):
            raise ValueError(f"{self.kind}: variable names repeat: {names}")
        inputs = {v.name for v in self.of("input")}
        known = inputs | {v.name for v in self.of("parameter")}
        for v in self.variables:
            if v.causality not in CAUSALITIES:
                raise ValueError(f"{v.name}: causality {v.causality!r} is not one of {CAUSALITIES}")
            if not set(v.depends_on) <= inputs or not set(v.initial_depends_on) <= known:
                raise ValueError(f"{v.name}: depends on variables that are not inputs or parameters")

    @property
    def script_name(self) -> str:
        """Name of the FMU's entry-point script, the Python module pythonfmu's binary imports.

        One per kind: the binary takes the slave class from the module of that name already
        imported in the process, if any, so two kinds must not share it.
        """
        return "hosedrogue_fmu_" + self.kind.replace("-", "_")

    def of(self, causality: str) -> tuple[FmuVariable, ...]:
        """The variables of one causality, in value-reference order.

        Parameters
        ----------
        causality : str
            ``"parameter"``, ``"input"`` or ``"output"``.

        Returns
        -------
        tuple of FmuVariable
        """
        return tuple(v for v in self.variables if v.causality == causality)

    def index(self, name: str) -> int:
        """The FMI 2.0 index of a variable (its value reference + 1, as ``<ModelStructure>`` counts).

        Parameters
        ----------
        name : str
            Variable name.

        Returns
        -------
        int
        """
        return 1 + [v.name for v in self.variables].index(name)


_FLIGHT = ("altitude_m", "airspeed_m_s", "wake_enabled")
_INPUTS = ("u_y_n", "u_z_n", "gust_u_m_s", "gust_v_m_s", "gust_w_m_s")

#: The fixed-length FMU: the hose at constant length behind the tanker.
HOSE_FMU = FmuInterface(
    kind="fixed-length",
    model_name="HoseDrogue",
    slave_module="hosedrogue.interop.fmu_slave",
    summary=("Probe-and-drogue refuelling hose of fixed length, rigid-link Kane model (after Wu et al., 2018); "
             "frame S_p: x forward, y right, z down, origin at the tow point; SI units"),
    notes=("The outputs start at rest at the balance position of the flight condition (the parameters) in still "
           "air, solved when initialization ends. Inputs are held over each communication step, which is split "
           "into RK4 sub-steps no longer than numerics.step_s (the DefaultExperiment's stepSize). A failed step "
           "(non-finite state, a link's yaw past numerics.max_yaw_deg) returns fmi2Discard with fmi2Terminated "
           "and logs its time and reason (status fmi2Discard, category logStatusDiscard; pythonfmu forwards "
           "log messages only with the importer's debug logging on)."),
    variables=(
        FmuVariable("altitude_m", "parameter", "flight altitude", field="flight.altitude_m"),
        FmuVariable("airspeed_m_s", "parameter", "true airspeed", field="flight.airspeed_m_s"),
        FmuVariable("wake_enabled", "parameter", "tanker wake on/off", kind="Boolean", field="wake.enabled"),
        FmuVariable("u_y_n", "input", "control force at the drogue along S_p y (lateral, right)"),
        FmuVariable("u_z_n", "input", "control force at the drogue along S_p z (vertical, down)"),
        FmuVariable("gust_u_m_s", "input", "gust velocity along S_p x (forward), uniform over the hose"),
        FmuVariable("gust_v_m_s", "input", "gust velocity along S_p y (right), uniform over the hose"),
        FmuVariable("gust_w_m_s", "input", "gust velocity along S_p z (down), uniform over the hose"),
        *(FmuVariable(f"drogue_{a}_m", "output", f"drogue position along S_p {a}", initial_depends_on=_FLIGHT)
          for a in "xyz"),
        # at rest at the start whatever the parameters: the velocity starts at exactly 0
        *(FmuVariable(f"drogue_v{a}_m_s", "output", f"drogue velocity along S_p {a}, relative to the tow point")
          for a in "xyz"),
        FmuVariable("tow_tension_n", "output",
                    "magnitude of the force the hose exerts at the tow point (|tow_force_x/y/z_n|)",
                    depends_on=_INPUTS, initial_depends_on=_FLIGHT + _INPUTS),
    ),
)

#: Every FMU the package exports, by kind.
INTERFACES = {HOSE_FMU.kind: HOSE_FMU}


def python_requirement() -> str:
    """The Python versions the installed hosedrogue supports (its ``Requires-Python``).

    Returns
    -------
    str
        E.g. ``">=3.11"``; ``"(unknown)"`` when running from a source tree without metadata.
    """
    try:
        return metadata.metadata("hosedrogue").get("Requires-Python") or "(unknown)"
    except metadata.PackageNotFoundError:  # pragma: no cover - source tree
        return "(unknown)"


def host_requirements() -> str:
    """What a host needs to run an FMU exported by this package: one paragraph.

    Returns
    -------
    str
        The Python versions, the package and its version, how to install it, where it was tested
        and how to check an FMU.
    """
    return (f"The FMU runs Python code: the host needs CPython {python_requirement()} with hosedrogue "
            f"{__version__} installed (pip install 'hosedrogue[fmu]=={__version__}', or pythonfmu deploy -f "
            f"FILE.fmu, which installs resources/requirements.txt into the current Python). Tested on "
            f"{TESTED_ON}. Check an FMU on its host with: hosedrogue export-fmu --check (or "
            f"python -c \"from hosedrogue.interop.fmu import check_fmu; print(check_fmu('FILE.fmu'))\").")


def fmu_params(params: Params, altitude_m: float, airspeed_m_s: float, wake_enabled: bool) -> Params:
    """The parameter set the FMU simulates: ``params`` at the given flight condition, with
    turbulence switched to the externally driven ``uniform`` gust field of the gust inputs.

    Parameters
    ----------
    params : Params
        Exported parameter set (hose, drogue, tanker, numerics, ...).
    altitude_m : float
        Flight altitude [m].
    airspeed_m_s : float
        True airspeed [m/s].
    wake_enabled : bool
        Tanker wake on or off.

    Returns
    -------
    Params
        Validated parameters (:class:`ParameterError` names a bad value).
    """
    return params.replace(
        flight={"altitude_m": altitude_m, "airspeed_m_s": airspeed_m_s},
        wake={"enabled": bool(wake_enabled)},
        turbulence={"enabled": True, "distribution": "uniform"},
    )


def parameter_starts(interface: FmuInterface, params: Params) -> dict[str, float | bool]:
    """The start values of an interface's parameters: the fields they set, read from ``params``.

    Parameters
    ----------
    interface : FmuInterface
        The FMU's interface.
    params : Params
        The exported parameter set.

    Returns
    -------
    dict
        Parameter name -> value (float in the unit of its name, or bool).
    """
    starts = {}
    for v in interface.of("parameter"):
        section, name = v.field.split(".")
        value = getattr(getattr(params, section), name)
        starts[v.name] = bool(value) if v.kind == "Boolean" else float(value)
    return starts


def constant_gusts(gust_m_s) -> "object":
    """A gust record that holds ``gust_m_s`` = (u, v, w) [m/s] at all times.

    Parameters
    ----------
    gust_m_s : sequence of 3 float
        Gust velocity along S_p x, y, z [m/s].

    Returns
    -------
    hosedrogue.environment.turbulence.GustRecord
        Two equal samples, acting for all times.
    """
    from ..environment.turbulence import GustRecord

    g = np.asarray(gust_m_s, dtype=np.float64).reshape(3)
    return GustRecord(t0_s=0.0, dt_s=1.0, values=np.vstack([g, g]), t_on_s=-math.inf, t_off_s=math.inf)


@dataclass
class StepFailure(Exception):
    """The state stopped being valid during a step (non-finite, or a yaw beyond the limit)."""

    t_s: float  #: time at which it was detected [s]
    reason: str  #: why the state is no longer valid

    def __str__(self) -> str:
        return f"stopped at t = {self.t_s:.6g} s: {self.reason}"


class HoseDrogueCore:
    """The fixed-length FMU's simulation, independent of pythonfmu (tested directly and through fmpy).

    Parameters
    ----------
    params : Params
        The parameters to simulate (see :func:`fmu_params`).
    """

    def __init__(self, params: Params):
        from ..analysis.equilibrium import solve_equilibrium
        from ..model.system import HoseModel
        from ..simulation.simulate import rk4_step_python

        self.params = params
        self._rk4 = rk4_step_python
        self._gust = (0.0, 0.0, 0.0)
        self.model = HoseModel(params, gusts=constant_gusts(self._gust))
        self.equilibrium = solve_equilibrium(params, model=self.model)  # in still air
        self.x = self.equilibrium.state.copy()
        self.t_s = 0.0
        self.u_n = np.zeros(2)
        self._max_yaw = math.radians(params.numerics.max_yaw_deg)

    def set_gust(self, gust_m_s) -> None:
        """Hold the uniform gust velocity ``gust_m_s`` = (u, v, w) [m/s] from now on.

        Parameters
        ----------
        gust_m_s : sequence of 3 float
            Gust velocity along S_p x, y, z [m/s].
        """
        g = tuple(float(v) for v in gust_m_s)
        if g != self._gust:
            self._gust = g
            self.model.gusts = constant_gusts(g)  # HoseModel reads its gust record at every call

    def set_force(self, u_n) -> None:
        """Hold the control force ``u_n`` = (u_y, u_z) [N] (also for the outputs until the next step).

        Parameters
        ----------
        u_n : sequence of 2 float
            Control force at the drogue along S_p y and z [N].
        """
        self.u_n = np.asarray(u_n, dtype=np.float64).reshape(2).copy()

    def step(self, t_s: float, h_s: float, u_n) -> None:
        """Advance from ``t_s`` by ``h_s`` [s] with the control force ``u_n`` [N] held constant.

        Parameters
        ----------
        t_s : float
            Time at the start of the step [s].
        h_s : float
            Communication step [s], > 0; split into equal RK4 sub-steps <= ``numerics.step_s``.
        u_n : sequence of 2 float
            Control force (u_y, u_z) [N].

        Raises
        ------
        StepFailure
            If the state becomes non-finite or a link yaw passes ``numerics.max_yaw_deg``; the
            state stays that of ``t_s``.
        """
        self.set_force(u_n)
        u = self.u_n
        count = max(1, int(math.ceil(h_s / self.params.numerics.step_s - 1e-9)))
        h = h_s / count
        n = self.model.n
        x = self.x

        def f(t, state):
            return self.model.derivative(t, state, u)

        for k in range(count):
            x = self._rk4(f, t_s + k * h, x, h)
            if not np.all(np.isfinite(x)):
                raise StepFailure(t_s + (k + 1) * h, "the state became non-finite (numerical divergence; "
                                                     "check the inputs for NaN or values far beyond the model's range)")
            yaw = np.abs(x[1: 2 * n: 2])
            if np.max(yaw) > self._max_yaw:
                link = int(np.argmax(yaw)) + 1
                raise StepFailure(t_s + (k + 1) * h, f"the yaw of link {link}, {math.degrees(yaw[link - 1]):.1f} deg, "
                                                     f"passed numerics.max_yaw_deg = {self.params.numerics.max_yaw_deg:g} "
                                                     "deg, where the angle coordinates become singular")
        self.x = x
        self.t_s = t_s + h_s

    def outputs(self) -> dict[str, float]:
        """The outputs of :data:`HOSE_FMU` at the current state, force and gust.

        Returns
        -------
        dict of str to float
            ``drogue_x_m`` .. ``drogue_z_m`` [m], ``drogue_vx_m_s`` .. ``drogue_vz_m_s`` [m/s],
            ``tow_tension_n`` [N].
        """
        out = self.model.outputs(self.x, self.t_s, self.u_n)
        pos, vel = out.joints_m[-1], out.joint_velocities_m_s[-1]
        values = {f"drogue_{a}_m": float(pos[i]) for i, a in enumerate("xyz")}
        values.update({f"drogue_v{a}_m_s": float(vel[i]) for i, a in enumerate("xyz")})
        values["tow_tension_n"] = float(np.linalg.norm(out.tow_force_n))
        return values


def load_exported_params(resources: str | Path) -> Params:
    """The parameter set stored in an FMU's ``resources`` folder by the export.

    Parameters
    ----------
    resources : str or Path
        The unpacked FMU's ``resources`` folder.

    Returns
    -------
    Params
    """
    data = json.loads((Path(resources) / PARAMS_RESOURCE).read_text())
    return params_from_dict(data, base=PAPER)


def interface_record(interface: FmuInterface) -> dict:
    """The content of :data:`INTERFACE_RESOURCE` for an FMU of ``interface``.

    Parameters
    ----------
    interface : FmuInterface
        The FMU's interface.

    Returns
    -------
    dict
        ``hosedrogue`` (the exporting version), ``kind`` and ``variables`` (names in value-reference order).
    """
    return {"hosedrogue": __version__, "kind": interface.kind, "variables": [v.name for v in interface.variables]}


def check_interface(resources: str | Path, interface: FmuInterface) -> None:
    """Refuse an FMU whose model description the installed package's slave does not match.

    The value references in the FMU's ``modelDescription.xml`` are positions in the exporting
    version's table; a hosedrogue with other variables would read and write the wrong ones.

    Parameters
    ----------
    resources : str or Path
        The unpacked FMU's ``resources`` folder.
    interface : FmuInterface
        The interface of the installed slave.

    Raises
    ------
    ParameterError
        If the FMU was exported with other variables (or another kind of FMU).
    """
    path = Path(resources) / INTERFACE_RESOURCE
    if not path.exists():
        raise ParameterError(f"{path.name}: missing from the FMU's resources; export the FMU again with "
                             f"hosedrogue {__version__}")
    record = json.loads(path.read_text())
    theirs, mine = record.get("variables") or [], interface_record(interface)["variables"]
    if record.get("kind") != interface.kind or theirs != mine:
        only_theirs = ", ".join(n for n in theirs if n not in mine) or "-"
        only_mine = ", ".join(n for n in mine if n not in theirs) or "-"
        raise ParameterError(f"this {record.get('kind')} FMU was exported by hosedrogue {record.get('hosedrogue')} "
                             f"with other variables (its own: {only_theirs}; the installed hosedrogue {__version__}'s "
                             f"{interface.kind} FMU: {only_mine}, or another order): export it again")
