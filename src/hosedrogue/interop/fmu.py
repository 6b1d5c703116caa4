"""FMI 2.0 co-simulation export of the hose-drogue model, and a check of an exported FMU.

The FMU is built with `pythonfmu <https://github.com/NTNU-IHB/PythonFMU>`_: its platform binary
implements the FMI 2.0 C API and forwards every call to a Python class
(:class:`hosedrogue.interop.fmu_slave.HoseDrogue`), which runs the very same model code as
``hosedrogue simulate`` (no second implementation that could drift from it). The FMU therefore
needs a Python with ``hosedrogue`` installed at run time (in-process for Python hosts such as
fmpy); its model description and ``documentation/index.html`` say so
(:func:`hosedrogue.interop.fmu_core.host_requirements`), and :func:`check_fmu` checks an FMU on
its host. The interface is the table :data:`hosedrogue.interop.fmu_core.HOSE_FMU`; see
``docs/interop.md``.
"""

from __future__ import annotations

import json
import math
import platform
import shutil
import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from ..params import PAPER, Params, params_from_dict
from ..units import NO_UNIT, unit_of
from ..version import __version__
from .fmu_core import (
    INTERFACE_RESOURCE,
    INTERFACES,
    PARAMS_RESOURCE,
    HoseDrogueCore,
    fmu_params,
    interface_record,
    parameter_starts,
)
from .fmu_description import documentation_html

#: The check's bound on the FMU's start against the balance position [m]: the equilibrium
#: solver converges to a weight-moment residual of 1e-12, far below a micrometre.
START_TOLERANCE_M = 1e-6

_SCRIPT = '''"""Entry point of a hosedrogue FMU (written by `hosedrogue export-fmu`, hosedrogue {version}).

The model runs in the Python that loads this FMU; it needs hosedrogue {version} installed.
"""
from {module} import {model}, hold_entry_point_globals  # noqa: F401  (pythonfmu finds the class here)

hold_entry_point_globals(globals())  # pythonfmu's binary releases a reference to these globals it does not own
'''


def check_out_path(out: str | Path, name: str = "out") -> Path:
    """Refuse an output path that is not a ``.fmu`` file name (before anything is built).

    Parameters
    ----------
    out : str or Path
        The FMU file to write.
    name : str
        How the caller calls it, for the message (the command line passes ``--out``).

    Returns
    -------
    Path

    Raises
    ------
    ParameterError
        If ``out`` does not end in ``.fmu`` or is a directory.
    """
    path = Path(out)
    if path.suffix != ".fmu":
        raise ParameterError(f"{name} = {str(out)!r}: must be a file name ending in .fmu")
    if path.is_dir():
        raise ParameterError(f"{name} = {str(out)!r}: is a directory, expected a .fmu file name")
    return path


def _interface(kind: str):
    if kind not in INTERFACES:
        raise ParameterError(f"kind = {kind!r}: must be one of {', '.join(INTERFACES)}")
    return INTERFACES[kind]


def _write_sources(folder: Path, interface, params: Params) -> tuple[Path, list[Path], Path]:
    """The entry-point script, resources and documentation folder of an FMU, written in ``folder``."""
    script = folder / f"{interface.script_name}.py"
    script.write_text(_SCRIPT.format(version=__version__, module=interface.slave_module, model=interface.model_name))
    resources = [folder / PARAMS_RESOURCE, folder / INTERFACE_RESOURCE, folder / "requirements.txt"]
    resources[0].write_text(json.dumps(params.to_dict(), indent=1) + "\n")
    resources[1].write_text(json.dumps(interface_record(interface), indent=1) + "\n")
    resources[2].write_text(f"hosedrogue[fmu]=={__version__}\n")  # for `pythonfmu deploy -f FILE.fmu`
    docs = folder / "documentation"
    docs.mkdir()
    starts = parameter_starts(interface, params) | {v.name: v.start for v in interface.of("input")}
    (docs / "index.html").write_text(documentation_html(interface, starts))
    return script, resources, docs


def export_fmu(out: str | Path, params: Params = PAPER, kind: str = "fixed-length") -> Path:
    """Write an FMI 2.0 co-simulation FMU of the hose-drogue model.

    Parameters
    ----------
    out : str or Path
        The ``.fmu`` file to write (its folder is created).
    params : Params
        Parameters of the model (link count, hose, drogue, default flight condition and wake
        switch, integration step ``numerics.step_s`` [s]); the flight condition and wake switch
        stay adjustable as FMU parameters.
    kind : str
        Which FMU, a key of :data:`hosedrogue.interop.fmu_core.INTERFACES` (``"fixed-length"``).

    Returns
    -------
    Path
        The written FMU.

    Raises
    ------
    ParameterError
        If ``out`` is not a ``.fmu`` file name, ``kind`` is unknown, a parameter is invalid (an
        elastic hose among them), or pythonfmu is not installed; nothing is written then.
    """
    path = check_out_path(out)
    interface = _interface(kind)
    if params.hose.elastic:
        raise ParameterError(f"hose.axial_stiffness_n = {params.hose.axial_stiffness_n!r}: the FMU carries the rigid "
                             "chain (axial_stiffness_n = inf); an elastic hose is simulated by hosedrogue simulate")
    try:
        from pythonfmu import FmuBuilder
    except ImportError:
        raise ParameterError("export_fmu: needs pythonfmu (pip install 'hosedrogue[fmu]')") from None
    fmu_params(params, params.flight.altitude_m, params.flight.airspeed_m_s, params.wake.enabled)  # validate
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="hosedrogue_fmu_") as tmp:
        script, resources, docs = _write_sources(Path(tmp), interface, params)
        partial = path.with_name(path.name + ".partial.fmu")
        try:
            FmuBuilder.build_FMU(script, dest=partial, project_files=resources, documentation_folder=docs,
                                 needsExecutionTool=False, canHandleVariableCommunicationStepSize=True)
            shutil.move(partial, path)
        finally:
            partial.unlink(missing_ok=True)
    return path


def prepare_python_host(links: int = 2) -> None:
    """Import and compile everything the FMU runs, in this Python process, before a Python host
    (fmpy) loads an exported FMU here.

    pythonfmu's binary runs the FMU's Python code inside the host's interpreter when the host is
    Python itself. Modules first imported and kernels first compiled during a call into the FMU
    have damaged the interpreter: ``scipy.optimize`` emptied ("module has no attribute 'root'")
    and crashes in later garbage collections were seen in fresh fmpy sessions before
    :func:`hosedrogue.interop.fmu_slave.hold_entry_point_globals`; with it, 1 of 5 fresh sessions
    without this call still aborted at exit ("corrupted double-linked list"), 0 of 5 with it (3
    runs each). Importing the slave's code and running one tiny model first means the FMU's calls
    import and compile nothing. Simulink, OpenModelica and other
    non-Python hosts start their own interpreter and do not need this.

    Parameters
    ----------
    links : int
        Links of the throw-away model that compiles the kernels [-].
    """
    from . import fmu_slave  # noqa: F401  the slave class and pythonfmu

    core = HoseDrogueCore(fmu_params(PAPER.replace(hose={"links": links}), PAPER.flight.altitude_m,
                                     PAPER.flight.airspeed_m_s, PAPER.wake.enabled))
    core.set_gust((0.0, 0.0, 0.0))
    core.step(0.0, PAPER.numerics.step_s, (0.0, 0.0))
    core.outputs()


def exported_params(fmu: str | Path) -> Params:
    """The parameter set an FMU was exported with (read from its ``resources`` in the zip).

    Parameters
    ----------
    fmu : str or Path
        An FMU written by :func:`export_fmu`.

    Returns
    -------
    Params
    """
    with zipfile.ZipFile(fmu) as zf:
        data = json.loads(zf.read(f"resources/{PARAMS_RESOURCE}"))
    return params_from_dict(data, base=PAPER)


def _unit_problems(md) -> list[str]:
    """Variables whose unit in the model description is not the one their name's suffix gives."""
    problems = []
    for v in md.modelVariables:
        expected = unit_of(v.name) if v.type == "Real" else NO_UNIT
        if (v.unit or NO_UNIT) != expected:
            problems.append(f"{v.name}: unit {v.unit!r}, its name says {expected!r}")
    return problems


def _run_from_balance(fmu: Path, md, duration_s: float) -> dict:
    """Run the FMU in fmpy with zero inputs and compare it with the balance position."""
    import fmpy

    from ..analysis.equilibrium import solve_equilibrium

    params = exported_params(fmu)
    balance = solve_equilibrium(fmu_params(params, params.flight.altitude_m, params.flight.airspeed_m_s,
                                           params.wake.enabled)).drogue_position_m
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    start = time.perf_counter()
    rows = fmpy.simulate_fmu(str(fmu), stop_time=duration_s, step_size=params.numerics.step_s,
                             output_interval=params.numerics.step_s, output=outputs)
    wall = time.perf_counter() - start
    pos = np.column_stack([rows[f"drogue_{a}_m"] for a in "xyz"])
    return {"duration_s": float(rows["time"][-1]), "step_s": params.numerics.step_s, "links": params.hose.links,
            "start_offset_m": float(np.max(np.abs(pos[0] - balance))),
            "drift_m": float(np.max(np.abs(pos - pos[0]))), "wall_s": round(wall, 3)}


def check_fmu(fmu: str | Path, duration_s: float = 1.0) -> dict:
    """Check an exported FMU on this host: fmpy's validator, the units, and a short run at rest.

    Runs in this Python process (it calls :func:`prepare_python_host` first).

    Parameters
    ----------
    fmu : str or Path
        The ``.fmu`` file.
    duration_s : float
        Length of the run from the balance position with zero inputs [s], > 0.

    Returns
    -------
    dict
        ``ok`` (no problem and a start within :data:`START_TOLERANCE_M` of the balance position),
        ``problems`` (fmpy's :func:`fmpy.validation.validate_fmu` and unit mismatches, one line
        each), ``platforms`` (binaries in the FMU), ``host`` (this platform and the versions of
        Python, hosedrogue, fmpy, pythonfmu), ``variables`` and ``units`` (by name), and
        ``simulation`` (``start_offset_m`` and ``drift_m`` [m] over ``duration_s`` [s]; None if
        the FMU did not run, which is then one of the problems).

    Raises
    ------
    ParameterError
        If fmpy is not installed, ``fmu`` is not a file, or ``duration_s`` is not positive.
    """
    try:
        import fmpy
        from fmpy.validation import validate_fmu
    except ImportError:
        raise ParameterError("check_fmu: needs fmpy (pip install fmpy)") from None
    fmu = Path(fmu)
    if not fmu.is_file():
        raise ParameterError(f"fmu = {str(fmu)!r}: no such file")
    if isinstance(duration_s, bool) or not isinstance(duration_s, (int, float)) or not 0 < duration_s < math.inf:
        raise ParameterError(f"duration_s = {duration_s!r}: must be a finite number > 0 s")
    import pythonfmu

    problems = list(validate_fmu(str(fmu)))
    md = fmpy.read_model_description(str(fmu))
    problems += _unit_problems(md)
    prepare_python_host()
    try:
        sim = _run_from_balance(fmu, md, float(duration_s))
    except Exception as exc:  # the FMU did not run here: that is the check's finding, not a crash
        sim = None
        problems.append(f"running it in fmpy failed: {type(exc).__name__}: {exc}")
    units = {v.name: v.unit for v in md.modelVariables if v.unit}
    return {
        "fmu": str(fmu), "ok": not problems and sim["start_offset_m"] < START_TOLERANCE_M,
        "problems": problems, "fmi_version": md.fmiVersion, "platforms": fmpy.supported_platforms(str(fmu)),
        "host": {"platform": fmpy.platform, "machine": platform.machine(), "python": platform.python_version(),
                 "hosedrogue": __version__, "fmpy": fmpy.__version__, "pythonfmu": pythonfmu.__version__},
        "variables": len(md.modelVariables), "units": units, "simulation": sim,
        "start_tolerance_m": START_TOLERANCE_M,
    }
