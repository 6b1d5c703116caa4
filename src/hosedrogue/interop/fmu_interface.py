"""What every FMU the package exports shares, independent of pythonfmu and of the model: the
interface table (:class:`FmuInterface` of :class:`FmuVariable`), the record of an exported
interface that the slave checks (:func:`check_interface`), what a host needs
(:func:`host_requirements`) and a failed step (:class:`StepFailure`).

An FMU's interface is one :class:`FmuInterface`: its variables in value-reference order, each with
its causality, description, start (inputs) or parameter field (parameters), and, for outputs,
which inputs act on it at the same instant and which variables its initial value depends on. The
slave (:mod:`hosedrogue.interop.fmu_slave`) registers the variables from the table and
:func:`hosedrogue.interop.fmu_description.complete_model_description` writes the units and the
model structure from it. The tables: :data:`hosedrogue.interop.fmu_core.HOSE_FMU` (the hose of
fixed length) and :data:`hosedrogue.interop.fmu_engagement.ENGAGEMENT_FMU` (the engagement);
:data:`hosedrogue.interop.fmu_core.INTERFACES` lists them by kind.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path

from ..errors import ParameterError
from ..units import NO_UNIT, unit_of
from ..version import __version__

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
    #: parameters: the ``section.name`` of :class:`~hosedrogue.spec.params.Params` it sets (None: the
    #: FMU's own setting, its start from the exported case)
    field: str | None = None
    start: float = 0.0  #: inputs: value until the importer sets one [unit of the name] (unless the FMU's starts say)
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


@dataclass
class StepFailure(Exception):
    """A communication step that could not be taken: the run failed or ended during it (``final``:
    every later step fails the same way), or the FMU refused it before advancing (a step size or
    time it cannot take, an input it cannot hold; the state is unchanged)."""

    t_s: float  #: time at which it was detected [s]
    reason: str  #: why the step was not taken
    final: bool = True  #: whether the run is over (False: refused, nothing advanced)

    def __str__(self) -> str:
        return f"{'stopped' if self.final else 'refused a step'} at t = {self.t_s:.6g} s: {self.reason}"


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
