"""Interoperability: the FMU (run in fmpy) against ``hosedrogue steady`` / ``simulate``, and the
MATLAB files against the arrays they were written from (the FMU's model description, units and
checks: tests/interop/test_fmu_description.py)."""

import json
import time

import numpy as np
import pytest

from hosedrogue.cli import main
from hosedrogue.spec.params import PAPER

fmpy = pytest.importorskip("fmpy")
pytest.importorskip("pythonfmu")

LINKS = 8
STEP_S = 0.005  # numerics.step_s, the paper's step: the FMU's communication step equals it
DURATION_S = 10.0
POSITIONS = ["drogue_x_m", "drogue_y_m", "drogue_z_m"]
VELOCITIES = ["drogue_vx_m_s", "drogue_vy_m_s", "drogue_vz_m_s"]
OUTPUTS = POSITIONS + VELOCITIES + ["tow_tension_n"]
INPUTS = ["u_y_n", "u_z_n", "gust_u_m_s", "gust_v_m_s", "gust_w_m_s"]


def cli(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


@pytest.fixture(scope="module")
def fmu_path(tmp_path_factory):
    from hosedrogue.interop.fmu import prepare_python_host

    # fmpy runs the FMU in this interpreter: everything the FMU imports must be imported before
    # (a module first imported inside an FMU call is left unusable by pythonfmu's binary)
    prepare_python_host(LINKS)
    path = tmp_path_factory.mktemp("fmu") / "hose.fmu"
    assert main(["export-fmu", "--links", str(LINKS), "--out", str(path)]) == 0
    return path


def run_fmu(path, inputs=None, start_values=None, duration=DURATION_S):
    kwargs = {}
    if inputs is not None:
        names = list(inputs)
        rows = [(0.0, *inputs.values()), (duration, *inputs.values())]
        kwargs["input"] = np.array(rows, dtype=[("time", np.float64)] + [(n, np.float64) for n in names])
    return fmpy.simulate_fmu(str(path), stop_time=duration, step_size=STEP_S, output_interval=STEP_S,
                             output=OUTPUTS, start_values=start_values or {}, **kwargs)


def drogue(rows, names=POSITIONS):
    return np.column_stack([rows[n] for n in names])


@pytest.mark.fmu
def test_fmu_model_description(fmu_path):
    md = fmpy.read_model_description(str(fmu_path))
    causality = {v.name: v.causality for v in md.modelVariables}
    for name in INPUTS:
        assert causality[name] == "input"
    for name in OUTPUTS:
        assert causality[name] == "output"
    for name in ("altitude_m", "airspeed_m_s", "wake_enabled"):
        assert causality[name] == "parameter"
    assert md.fmiVersion == "2.0" and md.coSimulation is not None
    assert "u_hor_n" not in causality and "u_ver_n" not in causality  # renamed to u_y_n, u_z_n


@pytest.mark.fmu
def test_fmu_at_rest_starts_and_stays_at_the_balance_position(fmu_path, capsys, tmp_path):
    """Zero inputs: the FMU starts at ``hosedrogue steady`` and follows ``hosedrogue simulate`` of a
    scenario that starts at the balance position, sample for sample."""
    steady = json.loads(cli(capsys, "steady", "--links", str(LINKS), "--json"))
    rows = run_fmu(fmu_path)
    pos = drogue(rows)
    # 1e-6 m: the equilibrium solver's convergence (residual 1e-12 of the weight moment) is far finer
    start_diff = np.max(np.abs(pos[0] - steady["drogue_position_m"]))
    assert start_diff < 1e-6
    assert np.max(np.abs(pos - steady["drogue_position_m"])) < 1e-6
    assert rows["tow_tension_n"][0] == pytest.approx(np.linalg.norm(steady["tow_force_n"]), rel=1e-9)
    # the balance state has zero rates, so the drogue starts exactly at rest
    assert np.all(drogue(rows, VELOCITIES)[0] == 0.0)

    scenario = tmp_path / "rest.toml"
    scenario.write_text(f'[scenario]\nduration_s = {DURATION_S}\ninitial = "equilibrium"\n'
                        f"[hose]\nlinks = {LINKS}\n[numerics]\nstep_s = {STEP_S}\noutput_every = 1\n")
    cli(capsys, "simulate", str(scenario), "--format", "mat", "--out", str(tmp_path / "sim"))
    from scipy.io import loadmat

    mat = loadmat(tmp_path / "sim" / "timeseries.mat", simplify_cells=True)
    ref = np.column_stack([mat["signals"][c] for c in POSITIONS])
    assert ref.shape == pos.shape
    # 1e-9 m: same RK4 arithmetic on the same compiled right-hand side; only rounding differs
    diff = np.max(np.abs(pos - ref))
    print(f"at rest: FMU vs hosedrogue steady at the start max |dP| = {start_diff:.3g} m, "
          f"FMU vs simulate max |dP| = {diff:.3g} m over {DURATION_S} s")
    assert diff < 1e-9


@pytest.mark.fmu
def test_fmu_with_inputs_matches_simulate(fmu_path):
    """Constant force and gust inputs (held from t = 0): the FMU follows :func:`hosedrogue.simulate`
    with the same force and a constant gust record, to 1e-9 m over 10 s."""
    from hosedrogue import simulate, solve_equilibrium
    from hosedrogue.interop.fmu_core import constant_gusts, fmu_params
    from hosedrogue.model.system import HoseModel

    inputs = {"u_y_n": 300.0, "u_z_n": -200.0, "gust_u_m_s": 0.5, "gust_v_m_s": 2.0, "gust_w_m_s": -1.0}
    start = time.perf_counter()
    rows = run_fmu(fmu_path, inputs)
    fmu_wall = time.perf_counter() - start
    pos = drogue(rows)

    p = fmu_params(PAPER.replace(hose={"links": LINKS}, numerics={"output_every": 1}), 8000.0, 150.0, True)
    model = HoseModel(p, gusts=constant_gusts([0.5, 2.0, -1.0]))
    eq = solve_equilibrium(p, model=model)
    u = np.array([300.0, -200.0])
    start = time.perf_counter()
    res = simulate(p, DURATION_S, control=lambda t, x: u, equilibrium=eq, model=model)
    sim_wall = time.perf_counter() - start
    print(f"FMU in fmpy {fmu_wall:.2f} s, simulate() {sim_wall:.2f} s for {DURATION_S} s")
    ref = res.drogue_position_m
    assert res.completed and ref.shape == pos.shape
    assert np.max(np.abs(ref - ref[0])) > 0.05  # the inputs do move the drogue
    # 1e-9 m: identical arithmetic (RK4 on HoseModel.derivative); only rounding differs
    diff = np.max(np.abs(pos - ref))
    vel = drogue(rows, VELOCITIES)
    vdiff = np.max(np.abs(vel - res.drogue_velocity_m_s))
    print(f"with inputs: FMU vs simulate max |dP| = {diff:.3g} m, max |dV| = {vdiff:.3g} m/s over {DURATION_S} s")
    assert diff < 1e-9
    assert np.max(np.abs(res.drogue_velocity_m_s)) > 0.05  # the drogue does move
    # 1e-9 m/s: as for the positions, the same arithmetic on the same state; only rounding differs
    assert vdiff < 1e-9
    tension = np.linalg.norm(res.tow_force_n, axis=1)
    assert np.max(np.abs(rows["tow_tension_n"] - tension)) < 1e-6 * tension.max()


@pytest.mark.fmu
def test_fmu_parameters_select_the_flight_condition(fmu_path, capsys):
    steady = json.loads(cli(capsys, "steady", "--links", str(LINKS), "--airspeed", "120",
                            "--altitude", "3000", "--no-wake", "--json"))
    rows = run_fmu(fmu_path, start_values={"airspeed_m_s": 120.0, "altitude_m": 3000.0, "wake_enabled": False},
                   duration=0.1)
    assert np.max(np.abs(drogue(rows)[0] - steady["drogue_position_m"])) < 1e-6


def test_export_fmu_bad_output_name(tmp_path, capsys):
    from hosedrogue.errors import ParameterError
    from hosedrogue.interop.fmu import export_fmu

    assert main(["export-fmu", "--out", str(tmp_path / "hose.zip")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--out = " in err
    assert main(["export-fmu"]) == 2  # neither --out nor --check
    assert "--out" in capsys.readouterr().err
    # the library names its own argument, not the command line's flag
    with pytest.raises(ParameterError, match=r"^out = '.*hose\.zip': must be a file name ending in \.fmu$"):
        export_fmu(tmp_path / "hose.zip")
    assert not list(tmp_path.iterdir())  # nothing written


def test_simulation_mat_round_trip(tmp_path, capsys):
    from scipy.io import loadmat

    from hosedrogue.scenarios.runner import run as run_scenario
    from hosedrogue.scenarios import load_scenario

    scenario = tmp_path / "swing.toml"
    scenario.write_text('[scenario]\nduration_s = 0.5\ninitial = "displaced"\ninitial_pitch_offset_deg = 5.0\n'
                        "[hose]\nlinks = 4\n")
    cli(capsys, "simulate", str(scenario), "--format", "mat", "--out", str(tmp_path / "o"))
    mat = loadmat(tmp_path / "o" / "timeseries.mat", simplify_cells=True)
    res = run_scenario(load_scenario(str(scenario)))
    df = res.to_dataframe()
    assert list(mat["signal_names"]) == list(df.columns)
    units = dict(zip(mat["signal_names"], mat["signal_units"]))
    assert units["drogue_y_m"] == "m" and units["drogue_vy_m_s"] == "m/s" and units["t_s"] == "s"
    forces = [c for c in df.columns if c.startswith("u_")]  # the control force (u_y_n, u_z_n)
    assert len(forces) == 2 and all(units[c] == "N" for c in forces)
    for c in df.columns:  # full double precision: exactly the arrays written
        np.testing.assert_array_equal(mat["signals"][c], df[c].to_numpy())
    np.testing.assert_array_equal(mat["data"], df.to_numpy())
    np.testing.assert_array_equal(mat["states"], res.states)
    assert len(mat["state_names"]) == res.states.shape[1]
    assert mat["completed"] and mat["message"] == "completed"


def test_linear_mat_round_trip(tmp_path, capsys):
    from scipy.io import loadmat

    from hosedrogue.analysis.linearize import linearize

    out = tmp_path / "lm.mat"
    cli(capsys, "linearize", "--links", "4", "--no-wake", "--format", "mat", "--out", str(out))
    mat = loadmat(out, simplify_cells=True)
    lm = linearize(PAPER.replace(hose={"links": 4}, wake={"enabled": False}))
    for name in "ABCD":
        np.testing.assert_array_equal(mat[name], getattr(lm, name))
    assert list(mat["input_names"]) == ["u_y_n", "u_z_n"]
    assert list(mat["output_names"]) == ["P_ny_m", "P_nz_m"]
    data = json.loads(cli(capsys, "linearize", "--links", "4", "--no-wake", "--json"))
    for ch in ("lateral", "vertical"):
        np.testing.assert_array_equal(np.atleast_1d(mat[ch]["num"]), data[ch]["num"])
        np.testing.assert_array_equal(np.atleast_1d(mat[ch]["den"]), data[ch]["den"])
        assert mat[ch]["A"].shape == (2, 2)
    assert mat["order"] == 2 and mat["flight"]["links"] == 4


def test_linearize_mat_needs_a_mat_name(tmp_path, capsys):
    assert main(["linearize", "--links", "2", "--format", "mat", "--out", str(tmp_path / "x.txt")]) == 2
    assert "--out" in capsys.readouterr().err
