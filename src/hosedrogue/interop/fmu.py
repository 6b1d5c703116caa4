"""FMI 2.0 co-simulation export of the hose-drogue model, and a check of an exported FMU.

The FMU is built with `pythonfmu <https://github.com/NTNU-IHB/PythonFMU>`_: its platform binary
implements the FMI 2.0 C API and forwards every call to a Python class
(:class:`hosedrogue.interop.fmu_slave.HoseDrogue`, the engagement's
:class:`~hosedrogue.interop.fmu_slave.HoseDrogueEngagement`), which runs the very same model code
as ``hosedrogue simulate`` (no second implementation that could drift from it). The FMU therefore
needs a Python with ``hosedrogue`` installed at run time (in-process for Python hosts such as
fmpy); its model description and ``documentation/index.html`` say so
(:func:`hosedrogue.interop.fmu_core.host_requirements`), and :func:`check_fmu` checks an FMU on
its host. The interfaces are the tables of :data:`hosedrogue.interop.fmu_core.INTERFACES`; see
``docs/interop.md``.
"""

from __future__ import annotations

import dataclasses
import json
import platform
import shutil
import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from ..simulation.budget import check_duration
from ..spec.params import PAPER, Params, params_from_dict
from ..units import NO_UNIT, unit_of
from ..version import __version__
from .fmu_core import INTERFACES, PARAMS_RESOURCE, HoseDrogueCore, fmu_params, parameter_starts
from .fmu_description import documentation_html
from .fmu_engagement import ENGAGEMENT_FMU, EngagementCore, fmu_starts
from .fmu_frozen import SCENARIO_RESOURCE, default_sample_time, fmu_scenario, frozen_summary, scenario_record
from .fmu_interface import INTERFACE_RESOURCE, interface_record

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


def _payload(model, kind: str | None):
    """The interface, resources (file name -> text), starts and details of an FMU of ``model``."""
    from ..scenarios import Scenario

    if isinstance(model, Scenario):
        interface = _interface(ENGAGEMENT_FMU.kind if kind is None else kind)
        if interface is not ENGAGEMENT_FMU:
            raise ParameterError(f"kind = {kind!r}: a scenario exports the {ENGAGEMENT_FMU.kind!r} FMU (the "
                                 "fixed-length FMU takes a Params)")
        scenario = fmu_scenario(model)
        starts = fmu_starts(scenario, default_sample_time(model))  # builds the run once: a bad value fails here
        record = scenario_record(scenario, starts)
        return interface, {SCENARIO_RESOURCE: json.dumps(record, indent=1)}, starts, frozen_summary(scenario)
    interface = _interface("fixed-length" if kind is None else kind)
    if interface is ENGAGEMENT_FMU or not isinstance(model, Params):
        raise ParameterError(f"params = {type(model).__name__}: the fixed-length FMU takes a Params, the engagement "
                             "FMU a Scenario with an engagement (load_scenario)")
    if model.hose.elastic:
        raise ParameterError(f"hose.axial_stiffness_n = {model.hose.axial_stiffness_n!r}: the fixed-length FMU carries "
                             "the rigid chain (axial_stiffness_n = inf); an elastic hose is simulated by hosedrogue simulate")
    fmu_params(model, model.flight.altitude_m, model.flight.airspeed_m_s, model.wake.enabled)  # validate
    starts = parameter_starts(interface, model) | {v.name: v.start for v in interface.of("input")}
    return interface, {PARAMS_RESOURCE: json.dumps(model.to_dict(), indent=1)}, starts, ""


def _write_sources(folder: Path, interface, files: dict, starts: dict, details: str) -> tuple[Path, list[Path], Path]:
    """The entry-point script, resources and documentation folder of an FMU, written in ``folder``."""
    script = folder / f"{interface.script_name}.py"
    script.write_text(_SCRIPT.format(version=__version__, module=interface.slave_module, model=interface.model_name))
    files = {**files, INTERFACE_RESOURCE: json.dumps(interface_record(interface), indent=1),
             "requirements.txt": f"hosedrogue[fmu]=={__version__}"}  # for `pythonfmu deploy -f FILE.fmu`
    resources = []
    for name, text in files.items():
        resources.append(folder / name)
        resources[-1].write_text(text + "\n")
    docs = folder / "documentation"
    docs.mkdir()
    (docs / "index.html").write_text(documentation_html(interface, starts, details))
    return script, resources, docs


def export_fmu(out: str | Path, params=PAPER, kind: str | None = None) -> Path:
    """Write an FMI 2.0 co-simulation FMU of the hose-drogue model: the hose of fixed length (of
    a :class:`~hosedrogue.spec.params.Params`) or the engagement (of a scenario).

    Parameters
    ----------
    out : str or Path
        The ``.fmu`` file to write (its folder is created).
    params : Params or Scenario
        A Params: the fixed-length FMU of those parameters (link count, hose, drogue, default
        flight condition and wake switch, integration step ``numerics.step_s`` [s]; the flight
        condition and wake switch stay adjustable as FMU parameters). A
        :class:`~hosedrogue.scenarios.Scenario` with an engagement: the engagement FMU of that
        scenario, frozen (:func:`hosedrogue.interop.fmu_frozen.fmu_scenario`; docs/interop.md).
    kind : str, optional
        Which FMU, a key of :data:`hosedrogue.interop.fmu_core.INTERFACES`; default the one of ``params``.

    Returns
    -------
    Path
        The written FMU.

    Raises
    ------
    ParameterError
        If ``out`` is not a ``.fmu`` file name, ``kind`` is unknown or not that of ``params``, a
        parameter is invalid, the scenario is one the engagement FMU cannot run, or pythonfmu is
        not installed; nothing is written then.
    """
    path = check_out_path(out)
    try:
        from pythonfmu import FmuBuilder
    except ImportError:
        raise ParameterError("export_fmu: needs pythonfmu (pip install 'hosedrogue[fmu]')") from None
    interface, files, starts, details = _payload(params, kind)
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="hosedrogue_fmu_") as tmp:
        script, resources, docs = _write_sources(Path(tmp), interface, files, starts, details)
        partial = path.with_name(path.name + ".partial.fmu")
        try:
            FmuBuilder.build_FMU(script, dest=partial, project_files=resources, documentation_folder=docs,
                                 needsExecutionTool=False, canHandleVariableCommunicationStepSize=True)
            shutil.move(partial, path)
        finally:
            partial.unlink(missing_ok=True)
    return path


def prepare_python_host(links: int = 2) -> None:
    """Import and compile everything the FMUs run, in this Python process, before a Python host
    (fmpy) loads an exported FMU here.

    pythonfmu's binary runs the FMU's Python code inside the host's interpreter when the host is
    Python itself. Modules first imported and kernels first compiled during a call into the FMU
    have damaged the interpreter: ``scipy.optimize`` emptied ("module has no attribute 'root'")
    and crashes in later garbage collections were seen in fresh fmpy sessions before
    :func:`hosedrogue.interop.fmu_slave.hold_entry_point_globals`; with it, 1 of 5 fresh sessions
    without this call still aborted at exit ("corrupted double-linked list"), 0 of 5 with it (3
    runs each). Importing the slaves' code and running tiny models of both FMUs first (the
    engagement's with both probe inputs, a commanded reel and drogue, and an LQR design) means
    the FMU's calls import and compile nothing. Simulink, OpenModelica and other non-Python hosts
    start their own interpreter and do not need this.

    Parameters
    ----------
    links : int
        Links of the throw-away models that compile the kernels [-].
    """
    from ..scenarios import Scenario
    from ..scenarios.runner import drogue_controller
    from ..spec.sections import Controller, Engagement, Loop, Probe, Reel
    from . import fmu_slave  # noqa: F401  the slave classes and pythonfmu

    params = PAPER.replace(hose={"links": links})
    core = HoseDrogueCore(fmu_params(params, PAPER.flight.altitude_m, PAPER.flight.airspeed_m_s, PAPER.wake.enabled))
    core.set_gust((0.0, 0.0, 0.0))
    core.step(0.0, PAPER.numerics.step_s, (0.0, 0.0))
    core.outputs()
    h = PAPER.numerics.step_s
    scenario = fmu_scenario(Scenario("prepare", params, 4 * h, engagement=Engagement(reel=Reel(law="python"),
                                                                                       probe=Probe())))
    for position, feed in ((True, False), (True, True), (False, False)):
        starts = fmu_starts(scenario, h)
        engagement = EngagementCore(scenario, altitude_m=starts["altitude_m"], airspeed_m_s=starts["airspeed_m_s"],
                                    wake_enabled=starts["wake_enabled"], sample_time_s=h, position_input=position,
                                    velocity_feed=feed)
        engagement.step(0.0, 2 * h, starts)
        engagement.outputs()
    drogue_controller(dataclasses.replace(scenario, loop=Loop(controller=Controller("lqr"))))


def exported_params(fmu: str | Path) -> Params:
    """The parameter set a fixed-length FMU was exported with (read from its ``resources`` in the zip).

    Parameters
    ----------
    fmu : str or Path
        A fixed-length FMU written by :func:`export_fmu`.

    Returns
    -------
    Params
    """
    with zipfile.ZipFile(fmu) as zf:
        data = json.loads(zf.read(f"resources/{PARAMS_RESOURCE}"))
    return params_from_dict(data, base=PAPER)


def exported_kind(fmu: str | Path) -> str:
    """Which FMU of :data:`~hosedrogue.interop.fmu_core.INTERFACES` a file is (its interface record).

    Parameters
    ----------
    fmu : str or Path
        An FMU written by :func:`export_fmu`.

    Returns
    -------
    str
        ``"fixed-length"`` or ``"engagement"``; "" for an FMU without the record.
    """
    with zipfile.ZipFile(fmu) as zf:
        try:
            return json.loads(zf.read(f"resources/{INTERFACE_RESOURCE}")).get("kind", "")
        except KeyError:
            return ""


def exported_scenario(fmu: str | Path):
    """The frozen scenario and the starts of an engagement FMU (read from its ``resources``).

    Parameters
    ----------
    fmu : str or Path
        An engagement FMU written by :func:`export_fmu`.

    Returns
    -------
    scenario : hosedrogue.scenarios.Scenario
    starts : dict
        Start values of the parameters and inputs, by name.
    """
    from .fmu_frozen import load_exported_scenario

    with tempfile.TemporaryDirectory(prefix="hosedrogue_fmu_") as tmp:
        with zipfile.ZipFile(fmu) as zf:
            zf.extract(f"resources/{SCENARIO_RESOURCE}", tmp)
        return load_exported_scenario(Path(tmp) / "resources")


def _unit_problems(md) -> list[str]:
    """Variables whose unit in the model description is not the one their name's suffix gives."""
    problems = []
    for v in md.modelVariables:
        expected = unit_of(v.name) if v.type == "Real" else NO_UNIT
        if (v.unit or NO_UNIT) != expected:
            problems.append(f"{v.name}: unit {v.unit!r}, its name says {expected!r}")
    return problems


def _run_from_balance(fmu: Path, md, duration_s: float) -> dict:
    """Run the FMU in fmpy with its start inputs (zero forces, the probe closing at its closure
    speed) and compare its start with the balance position (``hosedrogue steady``'s solve)."""
    import fmpy

    from ..analysis.equilibrium import solve_equilibrium

    kind = exported_kind(fmu)
    if kind == ENGAGEMENT_FMU.kind:
        scenario, starts = exported_scenario(fmu)
        params, step = scenario.params, starts["sample_time_s"]
        duration_s = min(duration_s, scenario.duration_s)
    else:
        params = exported_params(fmu)
        params = fmu_params(params, params.flight.altitude_m, params.flight.airspeed_m_s, params.wake.enabled)
        step = params.numerics.step_s
    balance = solve_equilibrium(params).drogue_position_m
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    messages = []
    start = time.perf_counter()
    rows = fmpy.simulate_fmu(str(fmu), stop_time=duration_s, step_size=step, output_interval=step, output=outputs,
                             debug_logging=True, logger=lambda *m: messages.append(m[-1]))
    wall = time.perf_counter() - start
    pos = np.column_stack([rows[f"drogue_{a}_m"] for a in "xyz"])
    stopped = [m.decode(errors="replace") for m in messages if m.startswith(b"hosedrogue:")]
    return {"kind": kind, "duration_s": float(rows["time"][-1]), "stop_time_s": float(duration_s), "step_s": step,
            "links": params.hose.links, "start_offset_m": float(np.max(np.abs(pos[0] - balance))),
            "drift_m": float(np.max(np.abs(pos - pos[0]))), "wall_s": round(wall, 3),
            "message": stopped[-1] if stopped else ""}


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
        ``problems`` (fmpy's :func:`fmpy.validation.validate_fmu`, unit mismatches and a run that
        stopped early, one line each), ``platforms`` (binaries in the FMU), ``host`` (this
        platform and the versions of Python, hosedrogue, fmpy, pythonfmu), ``variables`` and
        ``units`` (by name), and ``simulation`` (``kind``, ``start_offset_m`` and ``drift_m`` [m]
        over ``duration_s`` [s], at most the engagement's own duration; None if the FMU did not
        run, which is then one of the problems).

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
    check_duration(duration_s)
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
    if sim is not None and sim["duration_s"] < sim["stop_time_s"] * (1.0 - 1e-9):
        problems.append(f"the run in fmpy stopped at t = {sim['duration_s']:g} s of {sim['stop_time_s']:g} s: "
                        f"{sim['message'] or 'no reason logged'}")
    units = {v.name: v.unit for v in md.modelVariables if v.unit}
    return {
        "fmu": str(fmu), "ok": not problems and sim["start_offset_m"] < START_TOLERANCE_M,
        "problems": problems, "fmi_version": md.fmiVersion, "platforms": fmpy.supported_platforms(str(fmu)),
        "host": {"platform": fmpy.platform, "machine": platform.machine(), "python": platform.python_version(),
                 "hosedrogue": __version__, "fmpy": fmpy.__version__, "pythonfmu": pythonfmu.__version__},
        "variables": len(md.modelVariables), "units": units, "simulation": sim,
        "start_tolerance_m": START_TOLERANCE_M,
    }
