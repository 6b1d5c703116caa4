"""The docking studies on their own (hosedrogue.studies.docking, docking_grid, docking_statistics,
bow_wave): each cell's scenario is the shipped approach scenario but for the cell's changes, a
tiny grid counts every run once with its rate inside its Wilson interval, cells of the same
scenario share one campaign, the closure-speed duration rule, the force-limit cell's actuator, and
the rows do not depend on where the runs execute (docs/engagement.md, "Docking statistics")."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pandas as pd
import pytest

from hosedrogue.errors import ParameterError
from hosedrogue.scenarios import load_scenario, scenario_from_dict
from hosedrogue.studies.docking import APPROACH_RUNS, approach_paths, run_grid
from hosedrogue.studies.docking_grid import (CLOSURE_SPEEDS_M_S, CellSpec, approach_duration_s, cell_scenario,
                                             force_specs, grid_specs, same_scenario, speed_specs)
from hosedrogue.studies.docking_statistics import (PEAK_FORCE, PEAK_FORCE_Y, PEAK_FORCE_Z, capture_table, compare,
                                                   comparisons, force_findings, force_table, saturated, speed_findings,
                                                   speed_table)
from hosedrogue.studies.seeds import run_seed
from hosedrogue.studies.statistics import intervals_overlap, wilson_interval

RUNS = 3  # runs per cell of the tiny grid: enough for every count to be checked, about 0.2 s each
LIMIT_N = 25.0  # a force limit every moderate-turbulence PID run reaches (its unlimited median peak is 92 N)


def _undo(sc, ref, **fields):
    """``sc`` with its name, description and source, and the given fields, set back to ``ref``'s."""
    return dataclasses.replace(sc, name=ref.name, description=ref.description, source=ref.source, **fields)


# --- the cells' scenarios ------------------------------------------------------------------------
def test_a_grid_cell_is_the_shipped_scenario_with_its_controller_and_bow_wave():
    sc, ref = cell_scenario(CellSpec("severe", "lqr", False)), load_scenario("approach-severe")
    assert sc.controller == "lqr" and sc.loop.controller.options == {} and sc.engagement.bow_wave.enabled is False
    assert sc.name == "approach-severe-lqr-bow-off"
    back = _undo(sc, ref, loop=ref.loop,
                 engagement=dataclasses.replace(sc.engagement, bow_wave=ref.engagement.bow_wave))
    assert back == ref  # nothing else changed
    assert same_scenario(cell_scenario(CellSpec("moderate", "none", True)), load_scenario("approach-moderate"))


def test_the_pilot_cell_enables_the_pilot_models_defaults_and_nothing_else():
    from hosedrogue.spec.sections import Pilot

    sc, ref = cell_scenario(CellSpec("light", "none", True, pilot=True)), load_scenario("approach-light")
    assert sc.engagement.pilot == Pilot(enabled=True)
    assert _undo(sc, ref, engagement=ref.engagement) == ref


def test_a_closure_speed_cell_changes_the_speed_and_the_duration_only():
    """0.5 m/s: 6 s to the balance position, then the 1 m push: 1.5 s cruising 0.75 m and the 1 s
    half-cosine stop covering 0.25 m; 8.5 s is a whole number of 0.1 s, so no rounding."""
    sc, ref = cell_scenario(CellSpec("moderate", "pid", True, closure_speed_m_s=0.5)), load_scenario("approach-moderate")
    assert sc.engagement.probe == dataclasses.replace(ref.engagement.probe, closure_speed_m_s=0.5)
    assert sc.duration_s == 8.5 and sc.params.turbulence.duration_s == 8.5  # gusts to the end of the run
    back = _undo(sc, ref, duration_s=ref.duration_s, loop=ref.loop, engagement=ref.engagement,
                 params=sc.params.replace(turbulence={"duration_s": ref.params.turbulence.duration_s}))
    assert back == ref
    # at the shipped 1 m/s the cell is the shipped scenario: run_grid runs it once
    assert same_scenario(cell_scenario(CellSpec("moderate", "pid", True, closure_speed_m_s=1.0)),
                         cell_scenario(CellSpec("moderate", "pid", True)))
    assert not same_scenario(sc, cell_scenario(CellSpec("moderate", "pid", True)))


def test_a_users_approach_in_a_levels_turbulence_is_the_shipped_level():
    """The shipped approach-light is approach-moderate in light turbulence: approach-moderate taken
    as the user's base gives, in every light cell, the shipped cell's scenario (names aside)."""
    from hosedrogue.studies.docking_grid import level_scenario

    base = load_scenario("approach-moderate")
    for spec in (CellSpec("light", "pid", True), CellSpec("light", "none", False, pilot=True),
                 CellSpec("light", "lqr", True, closure_speed_m_s=0.5)):
        mine = cell_scenario(spec, base)
        assert mine.name == f"approach-moderate-{spec.name}"
        assert same_scenario(mine, cell_scenario(spec))
    with pytest.raises(ParameterError, match="'swing-release' is a fixed-length scenario; a docking cell runs"):
        level_scenario(load_scenario("swing-release"), "light")


def test_cli_runs_the_grid_on_the_users_approach(tmp_path, capsys):
    """``study docking --scenario FILE``: the cells fly the file's hose (3.6 kg/m, recorded in each
    campaign's settings) and are named after it."""
    from hosedrogue.cli import main

    mine = tmp_path / "wing-pod.toml"
    mine.write_text('[scenario]\nextends = "approach-moderate"\nname = "wing-pod"\n[hose]\nmass_per_length_kg_m = 3.6\n')
    out = tmp_path / "grid"
    assert main(["study", "docking", "--runs", "1", "--levels", "light", "--controllers", "none", "--no-pilot",
                 "--scenario", str(mine), "--out", str(out), "--json", "--quiet"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["scenario"] == "wing-pod" and [c["cell"] for c in record["cells"]] == ["light-none-bow-on",
                                                                                         "light-none-bow-off"]
    settings = json.loads((out / "light-none-bow-on" / "campaign.json").read_text())
    assert settings["scenario"]["scenario"]["name"] == "wing-pod-light-none-bow-on"
    assert settings["scenario"]["hose"]["mass_per_length_kg_m"] == 3.6


def test_a_force_limit_cell_limits_the_actuator_and_nothing_else():
    sc, ref = cell_scenario(CellSpec("moderate", "pid", True, max_force_n=50.0)), load_scenario("approach-moderate")
    assert sc.actuator.max_force_n == 50.0
    assert sc.actuator == dataclasses.replace(ref.actuator, max_force_n=50.0)  # rate limit, lag as shipped
    assert _undo(sc, ref, loop=ref.loop) == ref


@pytest.mark.parametrize("spec", grid_specs() + speed_specs() + force_specs(), ids=lambda s: s.name)
def test_every_cell_sets_its_turbulence_window_to_its_run(spec):
    """The cells give the window explicitly (a [turbulence] without one means something else in
    other versions of the scenario format): from the shipped start to the end of the run."""
    sc = cell_scenario(spec)
    ref = load_scenario(f"approach-{spec.level}")
    assert sc.params.turbulence.start_s == ref.params.turbulence.start_s
    assert sc.params.turbulence.duration_s == sc.duration_s
    assert sc.name == f"approach-{spec.name}"


def test_closure_speed_duration_rule():
    """3 m of standoff at v, then the 1 m push (cruise, then the 1 s half-cosine stop covering
    v / 2), rounded up to 0.1 s: the durations of docs/engagement.md, and the shipped 4.5 s at 1 m/s."""
    probe = load_scenario("approach-moderate").engagement.probe
    durations = [approach_duration_s(probe, v) for v in CLOSURE_SPEEDS_M_S]
    assert durations == [8.5, 5.9, 4.5, 3.2, 2.5]
    for v, d in zip(CLOSURE_SPEEDS_M_S, durations):
        exact = 3.0 / v + max(1.0 - 0.5 * v, 0.0) / v + 1.0
        assert exact <= d + 1e-9 < exact + 0.1, v  # 1e-9 s: the rounding of the exact path time
    with pytest.raises(ParameterError, match="closure_speed_m_s"):
        approach_duration_s(probe, 0.0)


@pytest.mark.parametrize("fields, name", [(dict(level="windy"), "level"), (dict(controller="mpc"), "controller"),
                                          (dict(closure_speed_m_s=0.0), "closure_speed_m_s"),
                                          (dict(max_force_n=-1.0), "max_force_n")])
def test_bad_cells_are_one_line_errors_naming_the_field(fields, name):
    with pytest.raises(ParameterError, match=name) as exc:
        CellSpec(**{"level": "moderate", **fields})
    assert "\n" not in str(exc.value)


def test_cell_lists():
    grid = grid_specs()
    assert len(grid) == 3 * 3 * 2 + 3 and len({s.name for s in grid}) == len(grid)
    assert [s.name for s in grid[:4]] == ["light-none-bow-on", "light-pid-bow-on", "light-lqr-bow-on",
                                          "light-pilot-bow-on"]
    assert [s.name for s in speed_specs((0.5, 1.0), controllers=("pid",))] == ["moderate-pid-bow-on-v0.5",
                                                                               "moderate-pid-bow-on-v1"]
    assert [s.name for s in force_specs((25.0,), ("severe",), ("lqr",))] == [
        "severe-none-bow-on", "severe-lqr-bow-on-f25", "severe-lqr-bow-on"]


# --- a tiny grid, run ----------------------------------------------------------------------------
def _tiny_specs():
    grid = grid_specs(levels=("moderate",), controllers=("none", "pid"), pilot_levels=())
    speeds = speed_specs((0.5, 1.0), controllers=("none",))
    forces = force_specs((LIMIT_N,), ("moderate",), ("pid",))
    return grid, speeds, forces


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    grid, speeds, forces = _tiny_specs()
    out = tmp_path_factory.mktemp("dock")
    return out, grid, speeds, forces, run_grid(grid + speeds + forces, RUNS, out)


def test_every_run_is_counted_once_and_every_rate_lies_in_its_wilson_interval(tiny):
    out, grid, speeds, forces, cells = tiny
    assert len(cells) == len(grid) + len(speeds) + len(forces)
    for spec, cell in zip(grid + speeds + forces, cells):
        cap = cell.capture
        assert cap["runs"] == RUNS and sum(cap["by_result"].values()) == RUNS, spec.name
        assert cap["ci95"] == list(wilson_interval(cap["by_result"]["captured"], RUNS)), spec.name
        assert cap["ci95"][0] <= cap["rate"] <= cap["ci95"][1], spec.name
        rows = pd.read_csv(cell.folder / "runs.csv")
        assert sorted(rows["run"]) == list(range(RUNS))  # each run once
        assert sorted(rows["seed"]) == sorted(run_seed(0, i) for i in range(RUNS))  # the same seeds in every cell
    table = capture_table(cells[:len(grid)])
    counts = table[[c for c in table.columns if c.startswith("n_")]].sum(axis=1)
    assert (counts == table["runs"]).all() and (table["runs"] == RUNS).all()


def test_cells_of_the_same_scenario_share_one_campaign(tiny):
    out, grid, speeds, forces, cells = tiny
    by_name = dict(zip((s.name for s in grid + speeds + forces), cells))
    assert by_name["moderate-none-bow-on-v1"] is by_name["moderate-none-bow-on"]
    assert cells[len(grid) + len(speeds)] is by_name["moderate-none-bow-on"]  # the force study's "none"
    assert cells[-1] is by_name["moderate-pid-bow-on"]  # and its unlimited PID
    folders = sorted(p.name for p in out.iterdir())
    assert folders == sorted({"moderate-none-bow-on", "moderate-pid-bow-on", "moderate-none-bow-off",
                              "moderate-pid-bow-off", "moderate-none-bow-on-v0.5", f"moderate-pid-bow-on-f{LIMIT_N:g}"})


def test_each_campaign_records_the_scenario_it_ran(tiny):
    """campaign.json holds the cell's scenario, which rebuilds it (the description aside)."""
    _, grid, speeds, forces, cells = tiny
    for spec, cell in zip(grid + speeds + forces, cells):
        settings = json.loads((cell.folder / "campaign.json").read_text())
        rebuilt = scenario_from_dict(settings["scenario"])
        assert same_scenario(rebuilt, cell.scenario) and same_scenario(rebuilt, cell_scenario(spec)), spec.name
        assert settings["scenario_name"] == f"approach-{cell.name}"


def test_the_closure_speed_cell_runs_as_long_as_the_probe_path(tiny):
    _, grid, speeds, _, cells = tiny
    slow = cells[len(grid)]
    assert slow.name == "moderate-none-bow-on-v0.5" and slow.closure_speed_m_s == 0.5 and slow.duration_s == 8.5
    settings = json.loads((slow.folder / "campaign.json").read_text())
    assert settings["duration_s"] == 8.5 and settings["statistics_window_s"] == [0.0, 8.5]
    table = speed_table(speeds, cells[len(grid):len(grid) + len(speeds)])
    assert list(table["duration_s"]) == [8.5, 4.5] and list(table["probe_speed_m_s"]) == [0.5, 1.0]
    found = speed_findings(table, 0.5)["none"]
    assert found["slowest_m_s"] == 0.5 and found["reference_m_s"] == 1.0 and found["runs"] == RUNS


def test_the_force_limit_cell_clips_its_actuator(tiny):
    """In every run of the limited cell the per-axis peak force is at most the limit and the
    magnitude at most sqrt(2) times it, while the unlimited cell's exceed it; moderate turbulence
    saturates the PID at 25 N in every run. The clip returns the limit itself and runs.csv writes
    floats with repr, so the per-axis peak is exactly <= the limit; 1e-12 relative only absorbs a
    rounding in hypot for the magnitude."""
    _, grid, speeds, forces, cells = tiny
    fcells = cells[len(grid) + len(speeds):]
    limited = fcells[1]
    assert limited.scenario.actuator.max_force_n == LIMIT_N
    settings = json.loads((limited.folder / "campaign.json").read_text())
    assert settings["scenario"]["actuator"]["max_force_n"] == LIMIT_N
    r = limited.runs
    assert (r[[PEAK_FORCE_Y, PEAK_FORCE_Z]].max(axis=1) <= LIMIT_N).all()
    assert (r[PEAK_FORCE] <= math.sqrt(2.0) * LIMIT_N * (1 + 1e-12)).all()
    assert saturated(r, LIMIT_N).all()
    assert (fcells[-1].runs[[PEAK_FORCE_Y, PEAK_FORCE_Z]].max(axis=1) > LIMIT_N).any()
    table = force_table(forces, fcells)
    assert list(table["max_force_n"]) == [math.inf, LIMIT_N, math.inf]
    assert table.loc[1, "saturated_fraction"] == 1.0 and np.isnan(table.loc[2, "saturated_fraction"])
    f = force_findings(table)["moderate-pid"]
    assert f["smallest_n"] == LIMIT_N and f["smallest_saturated_fraction"] == 1.0


def test_a_second_run_into_the_same_folder_resumes_and_other_settings_are_refused(tiny):
    out, grid, _, _, cells = tiny
    again = run_grid(grid[:1], RUNS, out)
    assert again[0].capture == cells[0].capture
    assert (again[0].runs.drop(columns="message") == cells[0].runs.drop(columns="message")).all().all()
    with pytest.raises(ParameterError, match="different settings"):
        run_grid(grid[:1], RUNS + 1, out)


def test_the_reports_grid_leaves_out_the_cells_figures_and_keeps_their_data(tiny, tmp_path):
    """plots=False (the report's sections): the same capture and runs, no campaign figure; the
    default (the study command) draws them."""
    out, grid, _, _, cells = tiny
    bare = run_grid(grid[:1], RUNS, tmp_path / "bare", plots=False)
    assert bare[0].capture == cells[0].capture
    assert (bare[0].runs.drop(columns="message") == cells[0].runs.drop(columns="message")).all().all()
    figures = ("histograms.png", "cdf.png", "miss_cdf.png")
    assert not any((tmp_path / "bare" / grid[0].name / f).exists() for f in figures)
    assert all((out / grid[0].name / f).stat().st_size > 0 for f in figures)
    with pytest.raises(ParameterError, match=r"^plots = 1: must be True or False$"):
        run_grid(grid[:1], RUNS, tmp_path / "bad", plots=1)
    assert not (tmp_path / "bad").exists()


def test_comparisons_and_significance(tiny):
    _, grid, _, _, cells = tiny
    table = capture_table(cells[:len(grid)])
    cmp = comparisons(table)
    assert set(cmp) == {"pid_vs_none_moderate", "bow_off_vs_on_moderate"}  # one level, no LQR, no pilot cells
    c = cmp["pid_vs_none_moderate"]
    assert c == compare(table, dict(controller="pid", bow_wave=True), dict(controller="none", bow_wave=True))
    assert c["significant"] is (not intervals_overlap(c["ci95_a"], c["ci95_b"]))
    with pytest.raises(ParameterError, match="a = "):
        compare(table, dict(controller="lqr"), dict(controller="none"))


def test_intervals_overlap():
    assert intervals_overlap((0.1, 0.4), (0.4, 0.9))  # touching: overlapping
    assert intervals_overlap((0.2, 0.8), (0.3, 0.4))
    assert not intervals_overlap((0.1, 0.39), (0.4, 0.9)) and not intervals_overlap((0.5, 0.9), (0.1, 0.45))


def test_a_campaign_two_grids_of_one_job_hold_runs_once(tmp_path, monkeypatch):
    """With a register (``share``), a grid's cell whose campaign another grid ran is that campaign,
    copied: no run simulated again, the same runs.csv rows, and its own folder; a cell of other
    runs or another scenario is not taken for it."""
    import hosedrogue.studies.campaign as campaign

    share = tmp_path / "share"
    share.mkdir()
    grid = grid_specs(levels=("moderate",), controllers=("pid",), pilot_levels=())[:1]
    first = run_grid(grid, RUNS, tmp_path / "a", share=share)[0]

    def no_run(task):
        raise AssertionError(f"run {task.index} of {task.scenario.name} simulated again")

    monkeypatch.setattr(campaign, "run_task", no_run)
    again = run_grid(grid, RUNS, tmp_path / "b", share=share)[0]
    assert again.folder == tmp_path / "b" / grid[0].name and again.capture == first.capture
    assert (again.folder / "runs.csv").read_bytes() == (first.folder / "runs.csv").read_bytes()
    with pytest.raises(AssertionError, match="simulated again"):  # other runs: another campaign
        run_grid(grid, RUNS + 1, tmp_path / "c", share=share)
    with pytest.raises(AssertionError, match="simulated again"):  # the bow wave on: another scenario
        run_grid(grid_specs(levels=("moderate",), controllers=("pid",), pilot_levels=())[1:2], RUNS, tmp_path / "d",
                 share=share)


@pytest.mark.dask
def test_rows_do_not_depend_on_the_workers(tiny, tmp_path):
    """The same two cells on two dask workers give the same runs.csv rows, sorted by run (the
    order runs finish in differs), as in this process."""
    pytest.importorskip("distributed")
    _, grid, _, _, cells = tiny
    twice = run_grid(grid[:2], RUNS, tmp_path, workers=2)
    for here, there in zip(cells[:2], twice):
        a = pd.read_csv(here.folder / "runs.csv").sort_values("run").reset_index(drop=True)
        b = pd.read_csv(there.folder / "runs.csv").sort_values("run").reset_index(drop=True)
        pd.testing.assert_frame_equal(a, b, check_exact=True)


def test_run_grid_refuses_bad_input_before_writing(tmp_path):
    specs = grid_specs(levels=("moderate",), controllers=("none",), pilot_levels=())
    for kwargs, name in ((dict(runs=0), "runs"), (dict(runs=2, seed=-1), "seed"), (dict(runs=2, workers=0), "workers"),
                         (dict(runs=2, workers=2, client=object()), "workers, client")):
        with pytest.raises(ParameterError, match=name):
            run_grid(specs, out_dir=tmp_path / "x", **kwargs)
    assert not (tmp_path / "x").exists()


# --- the approach paths and the bow wave ---------------------------------------------------------
def test_approach_paths_stop_at_contact():
    paths = approach_paths(runs=tuple(APPROACH_RUNS))
    assert set(paths) == set(APPROACH_RUNS)
    for label, p in paths.items():
        tc = p["outcome"].get("contact_time_s")
        assert p["probe_yz_m"].shape == p["drogue_yz_m"].shape == (p["t_s"].size, 2), label
        if tc is not None:
            assert p["t_s"][-1] <= tc and "contact_probe_yz_m" in p, label
    with pytest.raises(ParameterError, match="runs"):
        approach_paths(runs=("mpc",))


def test_bow_wave_study_numbers():
    """The study reads the steady displacement of the scenario's bow wave (the same numbers as
    bow_wave_displacement), which is docs/engagement.md's 49.6 mm at 0.5 m and 2.6 mm at 10 m (to
    the 0.05 mm of their last digit) and its "R < 0.46 m" for 1 mm at 10 m (to 0.005 m); the field
    is blanked inside the forebody only."""
    from hosedrogue.engagement.bow_wave import bow_wave_displacement
    from hosedrogue.studies.bow_wave import FAR_M, LEVEL_M, NEAR_M, bow_wave_study, radius_for_displacement

    bw = bow_wave_study()
    sc = load_scenario("approach-moderate")
    direct = np.linalg.norm(bow_wave_displacement(sc.params, sc.engagement.bow_wave, [NEAR_M, FAR_M]), axis=1)
    assert (bw.near_m, bw.far_m) == tuple(direct)
    assert bw.near_m == pytest.approx(49.6e-3, abs=0.05e-3) and bw.far_m == pytest.approx(2.6e-3, abs=0.05e-3)
    assert bw.radius_limit_m == pytest.approx(0.46, abs=0.005)
    assert bw.radius_limit_m == radius_for_displacement(LEVEL_M, FAR_M)
    nan = np.isnan(bw.velocity_m_s[..., 0])
    assert nan.any() and not nan.all()
    assert not np.isnan(bw.velocity_m_s[:, bw.x_m > 0.0]).any()  # ahead of the tip is outside the body
    with pytest.raises(ParameterError, match="bounds_m"):
        radius_for_displacement(LEVEL_M, FAR_M, bounds_m=(0.6, 1.0))


# --- the command line ----------------------------------------------------------------------------
def _help_blocks(text: str) -> dict:
    import re

    blocks, current = {}, None
    for line in text.splitlines():
        m = re.match(r"^\s{2}(--[\w-]+)", line)
        if m:
            current = m.group(1)
            blocks[current] = line
        elif current and line.startswith("    "):
            blocks[current] += " " + line.strip()
        else:
            current = None
    return blocks


def test_cli_help_states_each_options_unit(capsys):
    from hosedrogue.cli import main

    with pytest.raises(SystemExit) as exc:
        main(["study", "docking", "--help"])
    assert exc.value.code == 0
    blocks = _help_blocks(capsys.readouterr().out)
    for option, unit in {"--runs": "[-]", "--closure-speeds": "[m/s]", "--force-limits": "[N]", "--workers": "[-]",
                         "--seed": "[-]"}.items():
        assert unit in " ".join(blocks[option].split()), option


@pytest.mark.parametrize("argv, name", [(["--runs", "0"], "--runs"), (["--runs", "2", "--levels", "windy"], "--levels"),
                                        (["--runs", "2", "--closure-speeds", "0"], "--closure-speeds"),
                                        (["--runs", "2", "--workers", "0"], "--workers"),
                                        (["--runs", "2", "--seed", "-1"], "--seed")])
def test_cli_bad_arguments_are_one_line_errors_exit_2(capsys, tmp_path, argv, name):
    from hosedrogue.cli import main

    out = tmp_path / "dock"
    with pytest.raises(SystemExit) as exc:
        main(["study", "docking", *argv, "--out", str(out)])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert name in err and len(err.splitlines()) == 1
    assert not out.exists()


def test_cli_out_that_is_a_file_is_refused(capsys, tmp_path):
    from hosedrogue.cli import main

    path = tmp_path / "file"
    path.write_text("")
    assert main(["study", "docking", "--runs", "2", "--out", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "--out" in err and len(err.splitlines()) == 1


def test_cli_runs_a_small_grid_and_prints_json(capsys, tmp_path):
    from hosedrogue.cli import main

    code = main(["study", "docking", "--runs", "2", "--levels", "moderate", "--controllers", "none", "pid",
                 "--no-pilot", "--closure-speeds", "1", "--json", "--quiet", "--out", str(tmp_path)])
    assert code == 0
    record = json.loads(capsys.readouterr().out)
    names = [c["cell"] for c in record["cells"]]
    assert names == ["moderate-none-bow-on", "moderate-pid-bow-on", "moderate-none-bow-off", "moderate-pid-bow-off",
                     "moderate-none-bow-on-v1", "moderate-pid-bow-on-v1"]
    assert [c["campaign"] for c in record["cells"][-2:]] == ["moderate-none-bow-on", "moderate-pid-bow-on"]
    for c in record["cells"]:
        assert c["runs"] == 2 and sum(c["by_result"].values()) == 2, c["cell"]
    assert set(record["comparisons"]) == {"pid_vs_none_moderate", "bow_off_vs_on_moderate"}
    assert set(record["closure_speed"]["moderate"]) == {"none", "pid"}
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(names[:4])
