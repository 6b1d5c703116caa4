"""The exported FMUs as a strict importer reads them: fmpy's validator, units that match the names,
a model structure that matches what the FMU does, what the host needs, the reason of a failed
step in the FMI log, and ``hosedrogue export-fmu --check``. (The FMU's numbers against
``hosedrogue steady`` and ``simulate``: tests/interop/test_interop.py.)"""

import html
import json
import math
import re
import zipfile

import numpy as np
import pytest

from hosedrogue.cli import main
from hosedrogue.model import layout as LY
from hosedrogue.model.status import STATUS_TEXT
from hosedrogue.spec.params import PAPER
from hosedrogue.units import NO_UNIT, UNITS, unit_of

fmpy = pytest.importorskip("fmpy")
pytest.importorskip("pythonfmu")

from fmpy.validation import validate_fmu  # noqa: E402

from hosedrogue.interop.fmu_core import HOSE_FMU, INTERFACES  # noqa: E402
from hosedrogue.interop.fmu_engagement import ENGAGEMENT_FMU  # noqa: E402

pytestmark = pytest.mark.fmu

LINKS = 4
STEP_S = 0.005  # numerics.step_s of the exported parameters, the communication step here


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    """Every FMU the package exports, by kind."""
    from hosedrogue.interop.fmu import export_fmu, prepare_python_host

    prepare_python_host(LINKS)  # fmpy runs the FMUs in this interpreter (docs/interop.md)
    folder = tmp_path_factory.mktemp("fmus")
    params = PAPER.replace(hose={"links": LINKS})
    models = {HOSE_FMU.kind: params, ENGAGEMENT_FMU.kind: engagement_scenario()}
    return {kind: export_fmu(folder / f"{kind}.fmu", models[kind], kind=kind) for kind in INTERFACES}


def engagement_scenario():
    """``engage-response`` (its elastic hose, docs/model.md §11, on the SDIRK) on a coarse mesh,
    short: what the engagement FMU freezes."""
    import dataclasses

    from hosedrogue import load_scenario

    scenario = load_scenario("engage-response")
    return dataclasses.replace(scenario, duration_s=1.0, params=scenario.params.replace(
        hose={"links": LINKS}, numerics={"step_s": STEP_S, "output_every": 1}))


@pytest.fixture(scope="module")
def hose_fmu(fmus):
    return fmus[HOSE_FMU.kind]


def rewrite(src, dst, member, edit):
    """A copy of the FMU ``src`` at ``dst`` with ``member`` changed by ``edit(bytes) -> bytes``."""
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w") as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            zout.writestr(item, edit(data) if item.filename == member else data)
    return dst


def without_initial_unknowns(data: bytes) -> bytes:
    """The model description as pythonfmu writes it in this respect: no <InitialUnknowns>."""
    return re.sub(rb"\s*<InitialUnknowns>.*?</InitialUnknowns>", b"", data, flags=re.S)


def test_every_exported_fmu_passes_fmpys_validator(fmus):
    assert set(fmus) == set(INTERFACES)
    for kind, path in fmus.items():
        assert validate_fmu(str(path)) == [], kind


def test_the_validator_finds_the_missing_initial_unknowns(hose_fmu, tmp_path):
    # the finding, on pythonfmu's own model structure: the validator does look at it
    raw = rewrite(hose_fmu, tmp_path / "raw.fmu", "modelDescription.xml", without_initial_unknowns)
    problems = validate_fmu(str(raw))
    assert len(problems) == 1 and "InitialUnknowns does not contain the expected set" in problems[0]
    assert "drogue_x_m" in problems[0] and "tow_tension_n" in problems[0]


# --- units -----------------------------------------------------------------------------------

def test_every_variable_carries_the_unit_of_its_name(fmus):
    for kind, path in fmus.items():
        md = fmpy.read_model_description(str(path))
        defined = {u.name: u for u in md.unitDefinitions}
        for v in md.modelVariables:
            if v.type == "Boolean":
                assert v.unit is None and unit_of(v.name) == NO_UNIT, v.name
                continue
            assert v.unit == unit_of(v.name) != NO_UNIT, v.name
            base, unit = defined[v.unit].baseUnit, UNITS[v.unit]  # the table tests/package/test_fmu_units.py checks
            assert (base.kg, base.m, base.s, base.rad, base.factor) == (unit.kg, unit.m, unit.s, unit.rad, unit.factor)
        assert set(defined) == {v.unit for v in md.modelVariables if v.unit}, kind  # no unused definitions


def test_fmpy_dump_lists_every_unit(hose_fmu, capsys):
    fmpy.dump(str(hose_fmu))
    lines = {line.split()[0]: line.split() for line in capsys.readouterr().out.splitlines() if line.strip()}
    for v in HOSE_FMU.variables:
        if v.causality in ("input", "output"):  # the variables fmpy dump lists
            # name, causality, start (inputs only), unit, description...
            assert lines[v.name][3 if v.causality == "input" else 2] == unit_of(v.name), v.name


def test_outputs_are_the_time_series_columns():
    from hosedrogue import simulate

    columns = set(simulate(PAPER.replace(hose={"links": 2}), 0.01).to_dataframe().columns)
    names = {v.name for v in HOSE_FMU.of("output")}
    # tow_tension_n is the magnitude of the time series' tow_force_x/y/z_n (docs/interop.md)
    assert names - columns == {"tow_tension_n"}
    assert {"tow_force_x_n", "tow_force_y_n", "tow_force_z_n"} <= columns


# --- model structure against behaviour -------------------------------------------------------

#: A change of every parameter and input, large enough to move what depends on it.
CHANGES = {"altitude_m": 9000.0, "airspeed_m_s": 160.0, "wake_enabled": False, "u_y_n": 100.0, "u_z_n": 100.0,
           "gust_u_m_s": 1.0, "gust_v_m_s": 1.0, "gust_w_m_s": 1.0}


def affected(fmu, md, changes, outputs):
    """Per changed variable, the outputs it changes: exactly equal means independent (an output that
    does not depend on a variable comes from the same arithmetic), and a change must exceed 1e-9
    relative to count as dependence rather than rounding (none falls between)."""
    vr = {v.name: v.valueReference for v in md.modelVariables}
    kinds = {v.name: v.type for v in md.modelVariables}

    def put(name, value):
        (fmu.setBoolean if kinds[name] == "Boolean" else fmu.setReal)([vr[name]], [value])

    def read():
        return dict(zip(outputs, fmu.getReal([vr[n] for n in outputs])))

    base = read()
    found = {}
    for name, value in changes.items():
        start = (fmu.getBoolean if kinds[name] == "Boolean" else fmu.getReal)([vr[name]])[0]
        put(name, value)
        now = read()
        put(name, start)
        found[name] = {o for o in outputs if now[o] != base[o]}
        tiny = {o for o in found[name] if abs(now[o] - base[o]) <= 1e-9 * max(1.0, abs(base[o]))}
        assert not tiny, (name, tiny)
    return found


def declared(unknowns):
    return {u.variable.name: {d.name for d in u.dependencies} for u in unknowns}


def test_declared_dependencies_are_what_the_fmu_does(hose_fmu):
    from fmpy.fmi2 import FMU2Slave

    md = fmpy.read_model_description(str(hose_fmu))
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(str(hose_fmu)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="dependencies")
    fmu.instantiate()
    try:
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        at_start = affected(fmu, md, CHANGES, outputs)
        fmu.exitInitializationMode()
        vr = {v.name: v.valueReference for v in md.modelVariables}
        fmu.setReal([vr["u_y_n"], vr["gust_w_m_s"]], [300.0, -1.0])  # a moving state, not the balance
        for k in range(40):
            fmu.doStep(currentCommunicationPoint=k * STEP_S, communicationStepSize=STEP_S)
        inputs = {n: CHANGES[n] for n in CHANGES if n.startswith(("u_", "gust_"))}
        running = affected(fmu, md, inputs, outputs)
        fmu.terminate()
    finally:
        fmu.freeInstance()
    for unknowns, found in ((md.initialUnknowns, at_start), (md.outputs, running)):
        observed = {o: {name for name, outs in found.items() if o in outs} for o in outputs}
        assert declared(unknowns) == observed
    assert running["u_y_n"] == {"tow_tension_n"}  # the only direct feedthrough


# --- host, documentation, stale FMUs ---------------------------------------------------------

def test_the_fmu_says_what_its_host_needs(hose_fmu):
    from importlib.metadata import metadata

    from hosedrogue.version import __version__

    md = fmpy.read_model_description(str(hose_fmu))
    needs = [f"hosedrogue {__version__}", metadata("hosedrogue")["Requires-Python"],
             f"pip install 'hosedrogue[fmu]=={__version__}'", "hosedrogue export-fmu --check", "linux64"]
    with zipfile.ZipFile(hose_fmu) as zf:
        page = zf.read("documentation/index.html").decode()
        requirements = zf.read("resources/requirements.txt").decode()
    for text in needs:
        assert text in md.description, text
        assert html.escape(text) in page, text
    assert all(v.name in page for v in HOSE_FMU.variables)
    assert requirements.strip() == f"hosedrogue[fmu]=={__version__}"  # for `pythonfmu deploy`
    assert md.generationTool.startswith(f"hosedrogue {__version__} (PythonFMU ")
    assert float(md.defaultExperiment.stepSize) == STEP_S


def test_an_fmu_with_other_variables_is_refused(hose_fmu, tmp_path):
    def rename(data):
        record = json.loads(data)
        record["variables"][record["variables"].index("u_y_n")] = "u_hor_n"  # as exported before the rename
        return json.dumps(record).encode()

    stale = rewrite(hose_fmu, tmp_path / "stale.fmu", "resources/hosedrogue_interface.json", rename)
    messages = []
    with pytest.raises(Exception, match="instantiate"):
        fmpy.simulate_fmu(str(stale), stop_time=0.1, debug_logging=True, logger=lambda *m: messages.append(m))
    text = b" ".join(m[-1] for m in messages).decode()
    assert "its own: u_hor_n" in text and "u_y_n" in text and "export it again" in text


# --- a failed step ---------------------------------------------------------------------------

@pytest.mark.parametrize("force_n, reason", [
    (1e6, STATUS_TEXT[LY.YAW_LIMIT] + ": link "),  # 650x the tow tension: past the yaw limit within 0.1 s
    (math.nan, STATUS_TEXT[LY.NONFINITE] + ": "),  # a NaN force makes the state NaN in the first step
])
def test_a_failed_step_logs_time_and_reason(hose_fmu, force_n, reason):
    messages = []
    inputs = np.array([(0.0, force_n), (1.0, force_n)], dtype=[("time", np.float64), ("u_y_n", np.float64)])
    rows = fmpy.simulate_fmu(str(hose_fmu), stop_time=1.0, step_size=STEP_S, input=inputs, debug_logging=True,
                             logger=lambda *m: messages.append(m))
    failures = [m for m in messages if b"stopped at t" in m[-1]]
    assert len(failures) == 1
    _, _, status, category, text = failures[0]
    assert status == 2 and category == b"logStatusDiscard"  # fmi2Discard, as fmi2DoStep returns
    assert reason in text.decode()
    t_fail = float(re.search(rb"t = ([0-9.e+-]+) s", text).group(1))
    # fmpy stops at the last good communication point, one step before the failure (to its 6 digits)
    assert rows["time"][-1] < 1.0 and t_fail == pytest.approx(rows["time"][-1] + STEP_S, abs=1e-6)


# --- export-fmu --check ----------------------------------------------------------------------

def test_check_validates_and_runs_the_fmu(capsys):
    assert main(["export-fmu", "--links", str(LINKS), "--check", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["ok"] and report["problems"] == [] and report["fmi_version"] == "2.0"
    assert report["units"] == {v.name: unit_of(v.name) for v in HOSE_FMU.variables if v.kind == "Real"}
    sim = report["simulation"]
    # 1e-6 m: the equilibrium solver's convergence (weight-moment residual 1e-12) is far finer;
    # zero inputs at the balance position: the drogue stays within rounding (1e-9 m) of it
    assert sim["links"] == LINKS and sim["start_offset_m"] < 1e-6 and sim["drift_m"] < 1e-9
    assert report["host"]["platform"] in report["platforms"]


def test_check_of_an_invalid_fmu_exits_2_with_one_line(monkeypatch, tmp_path, capsys):
    from hosedrogue.interop import fmu as fmu_module

    export = fmu_module.export_fmu

    def export_raw(out, params=PAPER, kind="fixed-length"):  # what pythonfmu alone would write
        good = export(tmp_path / "good.fmu", params, kind)
        return rewrite(good, out, "modelDescription.xml", without_initial_unknowns)

    monkeypatch.setattr(fmu_module, "export_fmu", export_raw)
    assert main(["export-fmu", "--links", str(LINKS), "--check", "--out", str(tmp_path / "raw.fmu")]) == 2
    captured = capsys.readouterr()
    assert len(captured.err.strip().splitlines()) == 1 and "InitialUnknowns" in captured.err
    assert "FAILED" in captured.out


# --- import graph ----------------------------------------------------------------------------

def test_fmu_modules_import_downwards_only():
    grimp = pytest.importorskip("grimp")
    graph = grimp.build_graph("hosedrogue")
    modules = {m for m in graph.modules if m.startswith("hosedrogue.interop")} | {"hosedrogue.units"}
    state = {}

    def visit(module, path):  # depth-first search for a cycle among these modules
        state[module] = "open"
        for imported in graph.find_modules_directly_imported_by(module) & modules:
            assert state.get(imported) != "open", " -> ".join(path + [imported])
            if imported not in state:
                visit(imported, path + [imported])
        state[module] = "done"

    for module in sorted(modules):
        if module not in state:
            visit(module, [module])
    assert graph.find_shortest_chain(importer="hosedrogue.interop.fmu_slave", imported="hosedrogue.interop.fmu") is None
    assert graph.find_shortest_chain(importer="hosedrogue.interop.fmu_core", imported="hosedrogue.interop.fmu_slave") is None


#: A change of every parameter and input of the engagement FMU (from the position input with the
#: velocity feed, where every probe input acts on the start).
ENGAGEMENT_CHANGES = {"altitude_m": 9000.0, "airspeed_m_s": 160.0, "wake_enabled": False, "probe_cmd_x_m": -17.0,
                      "probe_cmd_y_m": 0.5, "probe_cmd_z_m": 5.0, "probe_cmd_vx_m_s": 0.5, "probe_cmd_vy_m_s": 0.2,
                      "probe_cmd_vz_m_s": 0.1, "reel_speed_cmd_m_s": 1.0, "u_y_n": 100.0, "u_z_n": 100.0,
                      "probe_velocity_feed": False, "probe_position_input": False}


def test_engagement_dependencies_cover_what_the_fmu_does(fmus):
    """Every dependence the engagement FMU shows is declared (at the start: in InitialUnknowns;
    running: none, the outputs have no direct feedthrough). Its start depends on the probe inputs
    only in some modes, so the declaration may be wider than one mode shows."""
    from fmpy.fmi2 import FMU2Slave

    path = fmus[ENGAGEMENT_FMU.kind]
    md = fmpy.read_model_description(str(path))
    outputs = [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="dependencies")
    fmu.instantiate()
    try:
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.setBoolean([vr["probe_position_input"], vr["probe_velocity_feed"]], [True, True])
        at_start = affected(fmu, md, ENGAGEMENT_CHANGES, outputs)
        fmu.exitInitializationMode()
        for k in range(40):  # the probe closing at its start speed, the drogue force on
            fmu.setReal([vr["probe_cmd_x_m"], vr["u_y_n"]], [-18.0 + 1.5 * (k + 1) * STEP_S, 300.0])
            fmu.doStep(currentCommunicationPoint=k * STEP_S, communicationStepSize=STEP_S)
        inputs = {n: v for n, v in ENGAGEMENT_CHANGES.items() if n in {v.name for v in ENGAGEMENT_FMU.of("input")}}
        running = affected(fmu, md, inputs, outputs)
        fmu.terminate()
    finally:
        fmu.freeInstance()
    initial = declared(md.initialUnknowns)
    for name, outs in at_start.items():
        assert all(name in initial[o] for o in outs), (name, outs)
    assert at_start["altitude_m"] >= {"drogue_x_m", "drogue_z_m"}  # the balance position moves
    assert at_start["probe_cmd_x_m"] == {"probe_x_m"} and at_start["probe_cmd_vx_m_s"] == {"probe_vx_m_s"}
    assert all(not outs for outs in running.values()), running  # no direct feedthrough, as declared
    assert all(not deps for deps in declared(md.outputs).values())
