"""The reproduction report (``hosedrogue reproduce``) and the figure functions behind it.

One end-to-end test (marked ``e2e``; ``-m "not e2e"`` leaves it out) builds the whole fast report
(about a minute and a half) and checks that every figure and table of the paper's Sec. 2.3 and 3
is on the page and on disk, that the page is self-contained (opens offline), that it says it is
the fast version, that ``report.json`` holds the headline numbers as finite values and that the
sections link to each other. The other tests build one section alone (the engagement, Table 3)
or none: the docking studies' counts are checked on the studies themselves
(tests/studies/test_studies_docking.py). The plotting smoke tests use small synthetic data and check
units on every axis and that no pyplot figure is ever created.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import matplotlib.pyplot as plt
from matplotlib.figure import Figure

from hosedrogue.plotting import figures as F

#: Every figure of the report: HTML id -> PNG file.
FIGURES = {
    "fig-convergence": "fig_convergence.png",
    "fig03": "fig03_sweep.png",
    "fig04": "fig04_turbulence_speeds.png",
    "fig05": "fig05_linear_steps.png",
    "fig06": "fig06_pole_zero.png",
    "fig07": "fig07_bode.png",
    "fig08": "fig08_step_compare.png",
    "fig10": "fig10_closed_loop_steps.png",
    "fig11": "fig11_pid_orders.png",
    "fig12": "fig12_controller_on_off.png",
    "fig13": "fig13_control_forces.png",
    "fig-hose3d": "fig_hose3d.png",
    "fig-pid-tuning": "pid_tuning_steps.png",
    "fig-accuracy": "fig_accuracy.png",
    "fig-long-runs": "fig_long_runs.png",
    "fig-engagement-history": "fig_engagement_history.png",
    "fig-engagement-snapshots": "fig_engagement_snapshots.png",
    "fig-docking-bow-wave": "fig_docking_bow_wave.png",
    "fig-docking-capture": "fig_docking_capture.png",
    "fig-docking-miss": "fig_docking_miss_cdf.png",
    "fig-docking-approach": "fig_docking_approach.png",
    "fig-docking-closure-speed": "fig_docking_closure_speed.png",
    "fig-docking-force-limit": "fig_docking_force_limit.png",
    "fig-docking-env": "fig_docking_env.png",
    "fig-manoeuvres-steady": "fig_manoeuvres_steady.png",
    "fig-manoeuvres-entry": "fig_manoeuvres_turn_entry.png",
    "fig-manoeuvres-capture": "fig_manoeuvres_capture.png",
    "fig-actuated-run": "fig_actuated_paper_case.png",
    "fig-actuated-claims": "fig_actuated_claims.png",
    "fig-actuated-capture": "fig_actuated_capture.png",
}

#: Every table of the report: HTML id -> CSV file.
TABLES = {
    "table-parameters": "table1_parameters.csv",
    "table-differences": "differences.csv",
    "table-step-convergence": "convergence_steps.csv",
    "table-link-convergence": "convergence_links.csv",
    "table-fig4": "fig04_turbulence_speeds.csv",
    "table-2": "table2.csv",
    "table-2-characteristics": "table2_characteristics.csv",
    "table-2-coefficients": "table2.csv",
    "table-linearization-conditions": "linearization_conditions.csv",
    "table-reduction-error": "reduction_error.csv",
    "table-3": "table3.csv",
    "table-3-lqr-integral": "table3_lqr_integral.csv",
    "table-closed-loop": "closed_loop_peaks.csv",
    "table-pid-tuning": "pid_tuning.csv",
    "table-realization-spread": "realization_spread.csv",
    "table-comparison": "comparison.csv",
    "table-accuracy-position": "accuracy_links.csv",
    "table-accuracy-modes": "accuracy_links.csv",
    "table-accuracy-rms": "accuracy_links.csv",
    "table-accuracy-continuum": "accuracy_continuum.csv",
    "table-accuracy-step": "accuracy_step.csv",
    "table-accuracy-cost": "accuracy_time_to_accuracy.csv",
    "table-long-runs-blowup": "long_runs_blowup.csv",
    "table-long-runs-modes": "long_runs_modes.csv",
    "table-long-runs-stable": "long_runs_stable_run.csv",
    "table-engagement": "engagement_outcomes.csv",
    "table-engagement-doubling": "engagement_outcomes.csv",
    "table-docking-capture": "docking_capture.csv",
    "table-docking-radii": "docking_bow_wave_radii.csv",
    "table-docking-closure-speed": "docking_closure_speed.csv",
    "table-docking-force-limit": "docking_force_limit.csv",
    "table-docking-env": "docking_env.csv",
    "table-manoeuvres-breakdown": "manoeuvres_turn_breakdown.csv",
    "table-manoeuvres-capture": "manoeuvres_capture.csv",
    "table-servo-margins": "actuated_servo_margins.csv",
    "table-actuator-convergence": "actuated_convergence.csv",
    "table-actuator-claims": "actuated_claims.csv",
    "table-actuator-capture": "actuated_capture.csv",
}

#: The data behind each figure.
FIGURE_DATA = [
    "convergence_steps.csv", "convergence_links.csv", "fig03_sweep.csv", "fig04_turbulence_speeds.csv",
    "fig05_linear_steps.csv", "fig06_pole_zero.csv", "fig07_bode.csv", "fig08_step_compare.csv",
    "fig10_closed_loop_steps.csv", "fig11_pid_orders.csv", "fig12_controller_on_off.csv",
    "fig13_control_forces.csv", "fig_hose3d.csv", "anim_turbulence.csv", "pid_tuning.csv",
    "accuracy_links.csv", "accuracy_continuum.csv", "long_runs_blowup.csv", "long_runs_modes.csv",
    "long_runs_stable_run.csv",
    "engagement_timeseries.csv", "engagement_snapshots.csv", "anim_engagement.csv",
    "docking_bow_wave_field.csv", "docking_bow_wave_displacement.csv", "docking_runs.csv", "docking_approach.csv",
    "docking_closure_speed.csv", "docking_closure_speed_runs.csv", "docking_force_limit.csv",
    "docking_force_limit_runs.csv", "docking_env_episode.csv",
    "manoeuvres_bank.csv", "manoeuvres_flight_path.csv", "manoeuvres_turn_entry.csv",
    "actuated_paper_case.csv", "actuated_claims_runs.csv",
]

#: Sections of the page (the paper's Sec. 2.3 and 3 and the report's own).
SECTIONS = ["summary", "comparison", "table1", "differences", "convergence", "fig3", "fig4", "table2",
            "fig5-8", "table3", "fig10-11", "fig12-13", "pid-tuning", "hose3d", "animation", "accuracy", "long-runs",
            "engagement", "docking", "docking-env", "manoeuvres", "actuated-drogue"]


# --- the whole fast report, once -------------------------------------------------------------------
def _check_files(out: Path, page: str) -> None:
    """Every figure and table is on the page and on disk, the GIFs are small GIFs."""
    for fig_id, png in FIGURES.items():
        assert f'id="{fig_id}"' in page, fig_id
        assert f'src="{png}"' in page, png
        assert (out / png).stat().st_size > 10_000, png
    for table_id, csv in TABLES.items():
        assert f'id="{table_id}"' in page, table_id
        assert (out / csv).stat().st_size > 0, csv
    for csv in FIGURE_DATA:
        assert (out / csv).stat().st_size > 0, csv
    for section in SECTIONS:
        assert f'<section id="{section}"' in page, section
    assert 'id="anim"' in page and 'src="anim_turbulence.gif"' in page
    assert 'id="anim-engagement"' in page and 'src="anim_engagement.gif"' in page
    for name in ("anim_turbulence.gif", "anim_engagement.gif"):
        gif = out / name
        assert gif.read_bytes()[:6] in (b"GIF87a", b"GIF89a"), name
        assert gif.stat().st_size < 3e6, name
    # the 3D viewer pages of the engagement and the docking approach, framed in their sections
    # (each self-contained: its libraries and data inside; docs/viewer.md gives their sizes)
    for fig_id, name in (("view-engagement", "view_engagement.html"), ("view-docking-approach", "view_docking_approach.html")):
        assert f'id="{fig_id}"' in page and f'<iframe src="{name}"' in page, name
        assert 0.6e6 < (out / name).stat().st_size < 8e6, name


def _check_self_contained(out: Path, page: str) -> None:
    for src in re.findall(r'<(?:img|iframe)[^>]+src="([^"]+)"', page):
        assert "://" not in src and not src.startswith("/"), src
        assert (out / src).is_file(), src
    for href in re.findall(r'href="([^"]+)"', page):
        if not href.startswith("#"):
            assert "://" not in href and (out / href).is_file(), href
    assert "<script" not in page.lower()
    assert "<link" not in page.lower()
    assert not re.search(r"https?://", page), "no web addresses: the page must open offline"
    assert "@import" not in page and "url(" not in page


def _numbers(obj, path="report"):
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _numbers(v, f"{path}.{k}")
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _numbers(v, f"{path}[{i}]")
    else:
        yield path, obj


def _check_headline(out: Path, headline: dict) -> None:
    """report.json holds the headline numbers as finite values; the stage labels name no issue."""
    data = json.loads((out / "report.json").read_text())
    assert data == headline
    for path, v in _numbers(data):
        assert v is not None, f"{path} is not finite"
        if isinstance(v, float):
            assert math.isfinite(v), path
    assert not [k for k in data["build"]["stage_times_s"] if "issue" in k]
    cl = data["closed_loop"]
    for k in ("off", "PID", "LQR"):
        assert cl[k]["peak_lateral_m"] > 0 and cl[k]["peak_vertical_m"] > 0
    for k in ("PID", "LQR"):
        assert cl[k]["peak_force_hor_n"] > 0 and cl[k]["reduction_lateral"] > 1
    conv = data["convergence"]
    assert conv["default_step_s"] == 0.005
    assert set(conv["max_drogue_error_at_default_step_m"]) == {"swing", "turbulence", "turbulence+pid"}
    assert {"lateral", "vertical"} <= set(data["table2"])
    assert "PID_lateral_rise_time_s" in data["table3"]
    assert data["steady"]["balance_ratio"] > 0
    acc = data["accuracy"]
    assert acc["split"]["position_error_m"][-1] < acc["aft"]["position_error_m"][-1]
    assert acc["split"]["position_orders"][-1] == pytest.approx(2.0, abs=0.1)  # split lumping: 2nd order
    assert acc["aft"]["position_orders"][-1] == pytest.approx(1.0, abs=0.1)  # the paper's aft lumping: 1st
    assert acc["step"]["reference_step_s"] < min(acc["step"]["steps_s"])
    lr = data["long_runs"]
    assert {"paper", "converged"} <= set(lr["modes"]) and lr["damping_gain"] > 10
    assert lr["blowup"] and lr["stable_run"]["completed"] is True


def _section(page: str, anchor: str) -> str:
    return re.search(rf'<section id="{anchor}".*?</section>', page, re.S).group(0)


def _check_cross_links(page: str) -> None:
    """The accuracy section points to the convergence section and back (no duplicated content);
    the fast variants of the accuracy and long-runs sections are labelled; the time-to-accuracy
    figures are quoted with their source, never rerun."""
    conv, acc, lr = (_section(page, a) for a in ("convergence", "accuracy", "long-runs"))
    assert 'href="#accuracy"' in conv and 'href="#convergence"' in acc
    assert 'id="accuracy-fast"' in acc and 'id="long-runs-fast"' in lr
    assert "docs/benchmarks.md" in acc
    assert "--config converged" in lr and 'preset = "converged"' in lr


def _check_docking(out: Path, headline: dict, page: str) -> None:
    """The docking section as the report runs it (the counts themselves: test_studies_docking.py):
    every cell of the full grid and of the fast studies is in report.json and its CSVs, each
    counted once; the cells the studies share are the grid's campaigns themselves; the page
    says it is the fast version and reads its numbers."""
    import pandas as pd

    from hosedrogue.report.settings import FAST
    from hosedrogue.studies.docking_grid import CONTROLLERS, LEVELS, PILOT, SPEED_CONTROLLERS

    dock = headline["docking"]
    runs = dock["runs_per_cell"]
    assert dock["fast"] is True and runs == FAST.docking_runs
    assert len(dock["capture"]) == len(LEVELS) * len(CONTROLLERS) * 2 + len(LEVELS)
    assert dock["pilot_cells"] == [f"{lev}-{PILOT}-bow-on" for lev in LEVELS]
    for name, cap in dock["capture"].items():
        assert cap["runs"] == runs and sum(cap["by_result"].values()) == runs, name
        assert (out / "docking" / "campaigns" / name / "campaign.json").is_file(), name
    per_cell = pd.read_csv(out / "docking_runs.csv").groupby(["level", "controller", "pilot", "bow_wave"]).size()
    assert len(per_cell) == len(dock["capture"]) and (per_cell == runs).all()
    spd, fl = dock["closure_speed"], dock["force_limit"]
    assert spd["speeds_m_s"] == sorted(FAST.docking_closure_speeds_m_s)
    assert len(spd["cells"]) == len(FAST.docking_closure_speeds_m_s) * len(SPEED_CONTROLLERS)
    assert fl["limits_n"] == sorted(FAST.docking_force_limits_n) and fl["levels"] == list(FAST.docking_force_levels)
    keys = ("rate", "ci95", "runs", "by_result")
    for c in SPEED_CONTROLLERS:  # the shipped speed's cell is the grid's campaign, not a rerun that agrees
        ref = spd["cells"][f"{c}-v1"]
        assert ref["campaign"] == f"moderate-{c}-bow-on" and ref["duration_s"] == 4.5
        assert {k: ref[k] for k in keys} == {k: dock["capture"][ref["campaign"]][k] for k in keys}
    for lev in FAST.docking_force_levels:
        for c in FAST.docking_force_controllers:
            free = fl["cells"][f"{lev}-{c}-unlimited"]
            assert free["campaign"] == f"{lev}-{c}-bow-on" and not free["limited"]
            assert {k: free[k] for k in keys} == {k: dock["capture"][free["campaign"]][k] for k in keys}
    n_speed = len(pd.read_csv(out / "docking_closure_speed_runs.csv"))
    assert n_speed == len(spd["cells"]) * runs
    assert len(pd.read_csv(out / "docking_force_limit.csv")) == len(fl["cells"])
    section = _section(page, "docking")
    assert 'id="docking-fast"' in section and f"{runs} runs per cell" in section
    assert f"run_seed({dock['campaign_seed']}, i)" in section  # read, not the f-string's braces
    assert "significant" in section and "Wilson" in section
    assert "<b>Closure speed.</b>" in section and "latch minimum" in section and "<b>Pilot.</b>" in section
    assert "<b>Force limit.</b>" in section and 'id="fig-docking-force-limit"' in section


@pytest.mark.e2e
def test_fast_report_end_to_end(fast_report):
    """The smoke test of the whole fast report: files, page, headline numbers, cross-links, docking.
    (The build is ``build_report(fast=True)`` of every section, once: tests/conftest.py.)"""
    tmp_path, headline = fast_report.dir, fast_report.headline
    page = (tmp_path / "index.html").read_text(encoding="utf-8")
    _check_files(tmp_path, page)
    _check_self_contained(tmp_path, page)
    assert 'id="fast-banner"' in page and "FAST VERSION" in page  # says so prominently
    assert "FAST VERSION" in re.search(r"<title>(.*?)</title>", page).group(1)
    assert headline["build"]["fast"] is True
    _check_headline(tmp_path, headline)
    _check_cross_links(page)
    _check_docking(tmp_path, headline, page)


# --- sections alone --------------------------------------------------------------------------------
@pytest.mark.subprocess
def test_sections_on_two_processes_write_the_report_one_process_writes(tmp_path):
    """Three independent sections built on two processes (spawned, each writing its files and
    returning what it added) give the files, the page and report.json that one process gives,
    byte for byte, but for the build's wall times, its worker count and the page's time stamp.
    (Not the PID tuning: its tuned gains were seen to differ in the 10th digit between a fresh
    process and one that had run other tests before, a defect of its own, reported.)"""
    from hosedrogue.report import build_report
    from hosedrogue.report.parallel import section_groups
    from hosedrogue.report.build import sections_for

    only = ["parameters", "sweep", "turbulence_speeds"]
    assert section_groups(sections_for(only)) == [("parameters",), ("sweep",), ("turbulence_speeds",)]
    heads = {w: build_report(tmp_path / str(w), fast=True, progress=False, only=only, workers=w) for w in (1, 2)}
    one, two = (sorted(p.name for p in (tmp_path / str(w)).iterdir()) for w in (1, 2))
    assert one == two and {"fig03_sweep.png", "fig04_turbulence_speeds.csv"} <= set(one)
    for name in one:
        a, b = ((tmp_path / str(w) / name).read_bytes() for w in (1, 2))
        if name == "report.json":
            a, b = (json.loads(x) for x in (a, b))
            for x in (a, b):
                for key in ("elapsed_s", "workers", "stage_times_s", "cpu_s", "stage_cpu_s"):
                    x["build"].pop(key)
        elif name == "index.html":
            a, b = (re.sub(rb"build, \d+ s, [\d: -]+\)", b"", x) for x in (a, b))
        assert a == b, name
    assert list(heads[2]["build"]["stage_times_s"]) == list(heads[1]["build"]["stage_times_s"])


def test_only_builds_the_sections_named_and_those_they_need():
    """``--only``: the sections named and, transitively, those they need, in build order; a name of
    no section is refused with the list."""
    from hosedrogue.errors import ParameterError
    from hosedrogue.report.build import SECTIONS, sections_for

    assert [s.key for s in sections_for(["closed_loop"])] == ["sweep", "linear", "controllers", "closed_loop"]
    assert [s.key for s in sections_for(["docking_env", "parameters"])] == ["parameters", "docking", "docking_env"]
    assert sections_for(None) == SECTIONS
    from hosedrogue.report.plan import COST_HINT_S
    assert set(COST_HINT_S) <= {s.key for s in SECTIONS}  # an ordering hint of sections that exist
    with pytest.raises(ParameterError, match=r"^only = 'dockin': no such report section; sections: parameters, "):
        sections_for(["dockin"])


def test_reproduce_only_writes_a_partial_report(tmp_path, capsys):
    """``hosedrogue reproduce --only parameters``: that section's page and report.json, both
    saying the report is partial; the closing 'differences' section, which needs the convergence
    section, is left out; a wrong name writes nothing (exit 2)."""
    from hosedrogue.cli import main

    out = tmp_path / "r"
    assert main(["reproduce", "--fast", "--only", "parameters", "--out", str(out)]) == 0
    build = json.loads((out / "report.json").read_text())["build"]
    assert build["sections"] == ["parameters"] and list(build["stage_times_s"]) == ["parameters"]
    # its CPU seconds (the section's process) are some of the whole build's (every process)
    assert list(build["stage_cpu_s"]) == ["parameters"] and 0.0 < build["stage_cpu_s"]["parameters"] <= build["cpu_s"]
    page = (out / "index.html").read_text(encoding="utf-8")
    assert 'id="partial-banner"' in page and 'id="table1"' in page and 'id="differences"' not in page
    assert main(["reproduce", "--only", "nope", "--out", str(tmp_path / "bad")]) == 2
    assert not (tmp_path / "bad").exists()


def test_engagement_section_alone_marks_the_fast_runs(fast_report):
    """The fast version's engagement runs are not the shipped mesh: the section says so; every
    reel captures; every peak's flag is measured by its doubling (the run verified, never
    "unverified"); the tension wave is drawn and written. (The section as the shared fast build
    built it: it needs no other section, tests/conftest.py.)"""
    from hosedrogue.report.settings import FAST

    out, tmp_path = fast_report.folder, fast_report.dir
    result = fast_report.results["engagement"]
    eng = out.headline["engagement"]
    assert result.fast is True and eng["fast"] is True and eng["links"] == FAST.engagement_links
    assert eng["doubling_links"] == 2 * eng["links"] and eng["duration_s"] == FAST.engagement_duration_s
    assert set(eng["runs"]) == {"locked", "constant-tension", "response"}
    for law, run in eng["runs"].items():
        assert run["captured"] is True, law
        assert run["peak_probe_load_n"] > 0 and run["peak_slack_m"] > 0, law
    # every flag is the doubling's measurement (the run verified), none "unverified"
    assert all(isinstance(v, bool) for run in eng["runs"].values() for v in run["converged"].values())
    (section,) = [s.html for s in out.sections if s.anchor == "engagement"]
    assert 'id="engagement-fast"' in section and f"{eng['links']} links" in section
    assert "not converged" in section
    # the elastic hose's tension wave: a figure and its data around each run's peak exit tension
    assert 'id="fig-engagement-wave"' in section and (tmp_path / "fig_engagement_wave.png").exists()
    wave = np.genfromtxt(tmp_path / "engagement_wave.csv", delimiter=",", names=True, dtype=None, encoding=None)
    assert set(wave["scenario"]) == {"engage-locked", "engage-constant-tension", "engage-response"}
    assert np.max(wave["tension_n"]) > 1000.0 and np.max(wave["s_m"]) > 15.0


def test_manoeuvres_section_alone(fast_report):
    """The fast manoeuvres section: its files, the fast note, and numbers that hang together -
    the turn lowers the drogue (apparent gravity), the PID holds it far closer than the open-loop
    swing, the capture campaigns ran every run in both cases. (The section as the shared fast
    build built it: it needs no other section, tests/conftest.py.)"""
    from hosedrogue.report.settings import FAST

    out, tmp_path = fast_report.folder, fast_report.dir
    result = fast_report.results["manoeuvres"]
    m = out.headline["manoeuvres"]
    (section,) = [s.html for s in out.sections if s.anchor == "manoeuvres"]
    assert 'id="manoeuvres-fast"' in section
    for name in ("fig_manoeuvres_steady.png", "fig_manoeuvres_turn_entry.png", "fig_manoeuvres_capture.png",
                 "manoeuvres_bank.csv", "manoeuvres_turn_breakdown.csv", "manoeuvres_capture.csv"):
        assert (tmp_path / name).stat().st_size > 0, name
    z = np.array(m["bank_drogue_position_m"])[:, 2]
    assert np.all(np.diff(z) > 0)  # deeper with every step of bank
    entry = m["turn_entry"]
    assert entry["pid_peak_offset_m"] < 0.1 * max(entry["peak_offset_m"])
    assert all(c["runs"] == FAST.manoeuvre_runs for c in m["capture"].values())
    assert result.beyond_apparent_gravity_m[1] > 0  # toward the inside of the right turn


def test_plot_manoeuvres():
    from types import SimpleNamespace

    from hosedrogue.analysis.steady_flight import SteadySweep
    from hosedrogue.studies.manoeuvres_figures import plot_steady_flight, plot_turn_capture, plot_turn_entry

    a = np.array([0.0, 15.0, 30.0])
    pos = np.c_[-15.0 + 0.01 * a, 0.4 + 0.002 * a, 5.5 + 0.01 * a]
    sw = SteadySweep("bank_deg", a, pos, 1500.0 + a, np.zeros((3, 3)))
    _check_figure(plot_steady_flight(sw, SteadySweep("flight_path_deg", a - 15.0, pos, 1500.0 - a, np.zeros((3, 3)))))
    t = np.linspace(0.0, 10.0, 50)
    traj = np.c_[-15.0 + 0 * t, 0.4 + 0.1 * np.sin(t), 5.5 + 0.05 * t]
    entry = SimpleNamespace(t_s=t, bank_deg=np.minimum(5.0 * t, 30.0), open_loop_m=traj, pid_m=traj * 0.999,
                            pid_force_n=np.c_[np.sin(t), -10.0 * t], level_m=traj[0], turn_m=traj[-1],
                            roll_start_s=2.0, roll_end_s=8.0)
    _check_figure(plot_turn_entry(entry))
    cap = SimpleNamespace(labels=("level flight", "25-degree turn"),
                          capture=({"rate": 0.8, "ci95": [0.7, 0.9], "runs": 50}, {"rate": 0.6, "ci95": [0.5, 0.7], "runs": 50}))
    _check_figure(plot_turn_capture(cap))


@pytest.fixture(scope="module")
def table3(fast_report):
    """The Table 3 section, on the linear-model section's models of the paper's balance position
    (the steady sweep section's ``solve_equilibrium(PAPER)``), as the shared fast build built them
    (tests/conftest.py); the page: what the linear and controllers sections added."""
    page = "".join(fast_report.html["linear"] + fast_report.html["controllers"])
    return fast_report.folder.headline, page


def test_paper_pid_reproduces_table3_on_the_papers_models(table3):
    """Same gains on the same (paper's) models must give the paper's numbers: a check of the
    report's plumbing. 6 %: the 2 % settling time of the vertical channel reads 1.379 s from the
    printed transfer function against the paper's 1.31 s (the paper rounds its coefficients)."""
    headline, _ = table3
    from hosedrogue.spec.paper import TABLE3

    for ch in ("lateral", "vertical"):
        for key in ("rise_time_s", "settling_time_s", "overshoot_pct"):
            ours = headline["table3"][f"PID_{ch}_{key}"]["on_paper_model"]
            assert ours == pytest.approx(TABLE3[("PID", ch)][key], rel=0.06), (ch, key)


def test_table3_section_shows_the_loop_margins(table3):
    """Beside Table 3: each loop's margins (the numbers of hosedrogue.controllers.margins, checked
    there) in report.json and a table, and the PID's Bode and Nyquist figure. Sampling the PID at
    10 ms adds half a sample of lag at its crossover, so it must lower its delay margin."""
    headline, page = table3
    m = headline["margins"]
    assert set(m) == {"PID", "PID sampled 10 ms", "LQR"}
    for ch in ("lateral", "vertical"):
        assert m["PID"][ch]["stable"] and m["PID"][ch]["delay_margin_s"] > m["PID sampled 10 ms"][ch]["delay_margin_s"]
    assert 'id="table-3-margins"' in page and "table3_pid_loops.png" in page


def test_papers_lqr_reproduces_table3_lateral_row_on_the_papers_models(table3):
    """The report's "LQR" is the paper's LQR read on the balanced states: on the paper's models
    its lateral rise and settling times are the paper's (0.836 / 1.485 s vs 0.839 / 1.49 s). 3 %:
    the paper prints three digits and the 2 % settling time depends on where the tail crosses
    the band. The overshoot is not reproduced (every closed-loop pole is real, so the step cannot
    overshoot): it must read 0 within the interpolation of the metrics, as the page explains."""
    headline, page = table3
    from hosedrogue.spec.paper import TABLE3

    t3 = headline["table3"]
    for key in ("rise_time_s", "settling_time_s"):
        ours = t3[f"LQR_lateral_{key}"]["on_paper_model"]
        assert ours == pytest.approx(TABLE3[("LQR", "lateral")][key], rel=0.03), key
    assert t3["LQR_lateral_overshoot_pct"]["on_paper_model"] < 0.01
    assert headline["lqr"]["reading"] == "balanced"
    assert 'id="table-3-lqr-integral"' in page
    assert "literal" not in page.lower()


def test_settings_hold_every_fast_full_difference():
    """The sections read the version from the settings' fields: the fast version's docking cells
    are the full studies' cells' subsets, and only the fast version coarsens the engagement."""
    from hosedrogue.report.settings import FAST, FULL

    assert FAST.fast and not FULL.fast
    assert set(FAST.docking_closure_speeds_m_s) <= set(FULL.docking_closure_speeds_m_s)
    assert set(FAST.docking_force_limits_n) <= set(FULL.docking_force_limits_n)
    assert set(FAST.docking_force_levels) <= set(FULL.docking_force_levels)
    assert set(FAST.docking_force_controllers) <= set(FULL.docking_force_controllers)
    assert FULL.engagement_links is None and FULL.engagement_duration_s is None
    assert FAST.engagement_links and FAST.engagement_step_s and FAST.engagement_output_every
    assert set(FAST.actuator_levels) <= set(FULL.actuator_levels)
    assert set(FAST.actuator_deflections_deg) <= set(FULL.actuator_deflections_deg)
    assert set(FAST.actuator_bandwidths_hz) <= set(FULL.actuator_bandwidths_hz)
    assert set(FAST.actuator_capture_levels) <= set(FULL.actuator_capture_levels)
    assert FAST.actuator_runs < FULL.actuator_runs and FAST.actuator_seeds <= FULL.actuator_seeds


def test_sections_receive_exactly_the_results_they_declare():
    """Each section's build takes (out, settings) plus, as keyword-only arguments, the results of
    the earlier sections it names in ``needs``: adding a section is one module and one line."""
    import inspect

    from hosedrogue.report.build import CLOSING, SECTIONS

    seen = set()
    for section in SECTIONS + CLOSING:
        params = inspect.signature(section.build).parameters
        positional = [n for n, p in params.items() if p.kind is p.POSITIONAL_OR_KEYWORD]
        keyword = {n for n, p in params.items() if p.kind is p.KEYWORD_ONLY}
        assert positional == ["out", "settings"], section.key
        assert keyword == set(section.needs), section.key
        assert set(section.needs) <= seen, f"{section.key} needs a later section"
        assert section.key not in seen, section.key
        seen.add(section.key)
    assert len({s.label for s in SECTIONS}) == len(SECTIONS)


# --- plotting smoke tests -------------------------------------------------------------------------
UNIT = re.compile(r"\[[^\]]+\]")


def _check_figure(fig):
    assert isinstance(fig, Figure)
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert axes
    for ax in axes:
        assert UNIT.search(ax.get_xlabel()), f"x label without unit: {ax.get_xlabel()!r}"
        assert UNIT.search(ax.get_ylabel()), f"y label without unit: {ax.get_ylabel()!r}"
        if hasattr(ax, "get_zlabel"):
            assert UNIT.search(ax.get_zlabel()), f"z label without unit: {ax.get_zlabel()!r}"
    assert plt.get_fignums() == [], "a pyplot figure was created"


def _fake_result(n_links=3, n=200, seed=0, on=False):
    """A SimulationResult of a short swinging chain (no physics: shapes and units only)."""
    from hosedrogue.results.run import SimulationResult

    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 4.0, n)
    s = np.linspace(0.0, 1.0, n_links + 1)
    amp = 0.01 if on else 0.5
    joints = np.zeros((n, n_links + 1, 3))
    joints[:, :, 0] = -15.0 * s
    joints[:, :, 1] = amp * np.sin(2 * t)[:, None] * s + 0.4 * s
    joints[:, :, 2] = 5.5 * s + amp * np.cos(3 * t)[:, None] * s
    return SimulationResult(
        t_s=t, states=np.zeros((n, 4 * n_links)), joints_m=joints, drogue_velocity_m_s=np.zeros((n, 3)),
        drogue_drag_n=np.zeros((n, 3)), tow_force_n=np.zeros((n, 3)), exit_tension_n=np.zeros(n),
        drogue_position_m=joints[:, -1, :], control_force_n=rng.normal(size=(n, 2)) * (30.0 if on else 0.0), completed=True, message="",
        equilibrium_m=joints[0, -1].copy())


def _curves(n, labels):
    return {lab: {"lateral": np.sin(np.linspace(0, 3, n)) + k, "vertical": np.cos(np.linspace(0, 3, n)) + k}
            for k, lab in enumerate(labels)}


@pytest.fixture(autouse=True)
def _no_pyplot_figures():
    plt.close("all")
    yield
    assert plt.get_fignums() == []


def test_plot_sweep():
    from hosedrogue.analysis.sweep import COLUMNS, SweepResult

    rows = []
    for h in (2000.0, 8000.0):
        for v in (100.0, 150.0, 200.0):
            rows.append(dict(zip(COLUMNS, (h, v, -15.0, 0.4, 5.0, 10 * v / (1 + h / 1e4), 0, 0, 0, 50 / v, True))))
    _check_figure(F.plot_sweep(SweepResult(np.array([2000.0, 8000.0]), np.array([100.0, 150.0, 200.0]), rows)))


def test_plot_turbulence_speeds():
    _check_figure(F.plot_turbulence_speeds([_fake_result(seed=1), _fake_result(seed=2)], [100, 150], window_s=(1, 3)))


def test_plot_linear_steps():
    t = np.linspace(0, 10, 50)
    _check_figure(F.plot_linear_steps(t, np.random.default_rng(0).normal(size=(2, 2, 50))))


def test_plot_pole_zero():
    p = np.array([-0.1 + 1.5j, -0.1 - 1.5j])
    z = np.array([-50.0 + 0j])
    pz = {"full": {"lateral": (p, z), "vertical": (p, z)}, "2nd order": {"lateral": (p, z), "vertical": (p, z)}}
    _check_figure(F.plot_pole_zero(pz, reference={"2nd order": pz["2nd order"]}))
    _check_figure(F.plot_pole_zero({"full": {"lateral": (p, p[:0]), "vertical": (p, p[:0])}}))


def test_plot_bode_compare():
    w = np.logspace(-2, 2, 40)
    g = {"full": {"lateral": 1 / (1j * w + 1), "vertical": 1 / (1j * w + 2)}}
    _check_figure(F.plot_bode_compare(w, g, reference={"paper": g["full"]}))


def test_plot_step_compare():
    _check_figure(F.plot_step_compare(np.linspace(0, 5, 30), _curves(30, ["full", "2nd"]),
                                      reference=_curves(30, ["paper 2nd"])))


def test_plot_closed_loop_steps():
    t = np.linspace(0, 5, 30)
    rows = {"paper models": _curves(30, ["PID", "LQR"]), "ours": _curves(30, ["PID", "LQR"])}
    _check_figure(F.plot_closed_loop_steps(t, rows, log_time=True))
    _check_figure(F.plot_closed_loop_steps(t, {"ours": _curves(30, ["full", "6th"])},
                                           reference_rows={"ours": _curves(30, ["paper 6th"])}))


def test_plot_controller_on_off_and_forces():
    off = _fake_result()
    on = {"PID": _fake_result(on=True, seed=3), "LQR": _fake_result(on=True, seed=4)}
    _check_figure(F.plot_controller_on_off(off, on, window_s=(1.0, 3.0)))
    _check_figure(F.plot_control_forces(on, window_s=(1.0, 3.0)))


def test_plot_hose_3d():
    r = _fake_result()
    _check_figure(F.plot_hose_3d([r.joints_m[0], r.joints_m[50]], ["equilibrium", "t = 1 s"]))


def test_plot_convergence():
    from hosedrogue.studies.convergence import LinkStudy, StepStudy
    from hosedrogue.studies.convergence_figures import plot_convergence

    steps = np.array([0.02, 0.01, 0.005])
    studies = [StepStudy(c, steps, 1e-3 * (steps / 0.02) ** 4 * (k + 1), 0.000625, 10.0)
               for k, c in enumerate(("swing", "turbulence"))]
    links = np.array([10, 20, 40])
    ls = LinkStudy(links, np.column_stack([-15 * np.ones(3), 0.4 * np.ones(3), [5.6, 5.53, 5.5]]),
                   np.array([1.51, 1.53, 1.535]), np.array([2.01, 2.03, 2.032]))
    _check_figure(plot_convergence(studies, ls))
    _check_figure(plot_convergence(studies, {"off": ls, "moment": ls}))


def test_animate_hose_writes_a_small_gif(tmp_path):
    path = F.animate_hose(_fake_result(), _fake_result(on=True), tmp_path / "a.gif", fps=5, window_s=(0.0, 2.0))
    data = Path(path).read_bytes()
    assert data[:6] in (b"GIF87a", b"GIF89a")
    from PIL import Image

    with Image.open(path) as im:
        assert im.n_frames == 11  # 0, 0.2, ..., 2.0 s
    assert plt.get_fignums() == []


def test_figure_helpers_draw_and_save(tmp_path):
    fig = F.plot_displacement(_fake_result(), labels=["a", "b"], others=[_fake_result(seed=5)])
    _check_figure(fig)
    assert F.save_figure(fig, tmp_path / "d.png").is_file()


def test_plot_accuracy():
    from hosedrogue.studies.accuracy_figures import plot_accuracy
    from hosedrogue.studies.accuracy import FrequencyStudy, LumpingStudy

    links = np.array([5, 10, 20])
    cont = np.array([-15.02, 0.41, 5.46])
    studies = []
    for lumping, order in (("split", 2), ("aft", 1)):
        pos = cont + np.outer(0.1 * (links / 5.0) ** -order, [0.0, 0.0, 1.0])
        freqs = FrequencyStudy(links, 1.55 - 0.05 / links, 2.04 - 0.05 / links)
        studies.append(LumpingStudy(lumping, links, pos, cont, freqs, np.full((3, 2), 0.15), np.full(3, 0.3)))
    _check_figure(plot_accuracy(studies))


def test_plot_docking_figures():
    import pandas as pd

    from hosedrogue.studies.docking_figures import (plot_approach_from_behind, plot_capture_rates, plot_closure_speed,
                                             plot_miss_cdfs)

    rows = [dict(level=lev, sigma_m_s=s, controller=c, bow_wave=b, rate=r, ci95_low=max(r - 0.2, 0.0),
                 ci95_high=min(r + 0.2, 1.0))
            for lev, s, r in (("light", 0.74, 0.9), ("severe", 5.9, 0.3)) for c in ("none", "pid") for b in (True, False)]
    _check_figure(plot_capture_rates(pd.DataFrame(rows), ("none", "pid"), ("light", "severe")))
    rows = [{**r, "pilot": False} for r in rows] + [dict(level=lev, sigma_m_s=s, controller="none", bow_wave=True,
                                                         rate=0.5, ci95_low=0.3, ci95_high=0.7, pilot=True)
                                                    for lev, s in (("light", 0.74), ("severe", 5.9))]
    fig = plot_capture_rates(pd.DataFrame(rows), ("none", "pid"), ("light", "severe"))
    _check_figure(fig)
    assert any("pilot" in t.get_text() for t in fig.axes[0].get_legend().get_texts())
    speeds = pd.DataFrame([dict(controller=c, probe_speed_m_s=v, rate=r, ci95_low=r / 2, ci95_high=(1 + r) / 2,
                                failed_latch_fraction=1.0 - r, coupler_speed_p05_m_s=0.9 * v,
                                coupler_speed_median_m_s=0.95 * v, coupler_speed_p95_m_s=v)
                           for c in ("none", "pid") for v, r in ((0.5, 0.1), (1.0, 0.6), (2.0, 0.8))])
    _check_figure(plot_closure_speed(speeds, ("none", "pid"), 0.5))
    rng = np.random.default_rng(1)
    _check_figure(plot_miss_cdfs({"light": {"none": rng.uniform(0, 0.4, 20), "pid": np.r_[rng.uniform(0, 0.3, 19), np.nan]}},
                                 0.305))
    t = np.linspace(0.0, 3.0, 50)
    path = {"probe_yz_m": np.tile([0.4, 5.5], (50, 1)), "drogue_yz_m": np.c_[0.4 + 0.1 * np.sin(t), 5.5 + 0.05 * t],
            "contact_probe_yz_m": np.array([0.4, 5.5]), "contact_drogue_yz_m": np.array([0.41, 5.65])}
    from hosedrogue.studies.bow_wave_figures import plot_bow_wave

    x, z = np.linspace(-4.0, 2.0, 13), np.linspace(-1.0, 1.0, 7)
    vel = np.ones((7, 13, 3)) * np.linspace(0.1, 2.0, 13)[None, :, None]
    d = np.geomspace(0.3, 20.0, 6)
    disp = np.c_[0.3 * d**-2, 0.0 * d, d**-2] * 0.05
    fig = (plot_bow_wave(x, z, vel, d, disp, outline_m=np.c_[np.linspace(-4, -2.4, 9), np.linspace(-0.7, 0.7, 9)],
                                stagnation_m=(-2.5, 0.0), source_distance_m=d + 2.9, level_m=1e-3,
                                radii_m=np.array([0.3, 0.6, 1.0]), far_displacement_m=np.array([4e-4, 1.7e-3, 4.6e-3]),
                                radius_limit_m=0.46))
    panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    assert len(panels) == 3 and all(UNIT.search(ax.get_xlabel()) and UNIT.search(ax.get_ylabel()) for ax in panels)
    _check_figure(plot_approach_from_behind({"none": path, "pid": {k: v for k, v in path.items() if "contact" not in k}},
                                            0.305))


def test_plot_actuated_drogue_figures():
    import pandas as pd

    from hosedrogue.studies.drogue_actuator_figures import plot_actuated_run, plot_capture_vs_surfaces, plot_claims
    from hosedrogue.results.run import SimulationResult
    import dataclasses

    ideal = _fake_result(on=True)
    n = ideal.t_s.size
    from hosedrogue.results.surfaces import SurfaceSeries

    act = dataclasses.replace(ideal, surfaces=SurfaceSeries(np.zeros((n, 4)) + 0.01, np.zeros((n, 4)), np.full(n, 5900.0),
                                                            0.35, 1.7))
    assert isinstance(act, SimulationResult)
    _check_figure(plot_actuated_run(ideal, act, (1.0, 3.0), 20.0))
    rows = [dict(level=lev, controller=c, force=f, completed_fraction=1.0 if f != "b" else 0.5, peak_dy_m_max=p,
                 peak_dz_m_max=p / 2) for lev, p in (("paper", 0.004), ("severe", 0.03)) for c in ("pid", "lqr")
            for f in ("ideal", "a", "b")]
    _check_figure(plot_claims(pd.DataFrame(rows)))
    inf = float("inf")
    cells = [dict(level="moderate", max_deflection_deg=d, bandwidth_hz=b, rate=r, ci95_low=r / 2, ci95_high=(1 + r) / 2)
             for d, b, r in ((inf, inf, 1.0), (2.0, 30.0, 0.7), (20.0, 30.0, 1.0), (20.0, 10.0, 0.4))]
    _check_figure(plot_capture_vs_surfaces(pd.DataFrame(cells), 27.1))
