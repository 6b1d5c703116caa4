"""Runs refused before they start: one that cannot reach its duration on its step grid, one that
would save nothing after its start, one whose statistics window misses it, and one (or a
campaign) whose kept output would exceed the stated share of the machine's memory; each in one
line naming the fields, with nothing allocated or written.

"Nothing allocated" is measured: the refused command's peak memory (``ru_maxrss`` of a child
process) stays below a bound far under what the run would keep.
"""

import dataclasses
import resource
import subprocess
import sys

import pytest

from hosedrogue import cli
from hosedrogue.errors import ParameterError
from hosedrogue.simulation import budget
from hosedrogue.spec.params import PAPER

DAY = '[scenario]\nname = "day"\nduration_s = 86400.0\n[hose]\nlinks = 20\n[numerics]\nstep_s = 1e-5\noutput_every = 1\n'
GRID = '[scenario]\nname = "grid"\nduration_s = 0.1\n[numerics]\nstep_s = 0.03\n'
OUTPUT = '[scenario]\nname = "output"\nduration_s = 0.1\n[numerics]\nstep_s = 0.01\noutput_every = 3\n'
EVERY = '[scenario]\nname = "every"\nduration_s = 0.1\n[numerics]\noutput_every = 1000000\n'
LATE = ('[scenario]\nname = "late"\nduration_s = 1.0\n[turbulence]\nenabled = true\nstart_s = 5.0\n'
        'duration_s = 2.0\n')

CASES = {
    "24 hours at every step": (DAY, ["scenario.duration_s = 86400.0", "numerics.step_s = 1e-05", "numerics.output_every = 1",
                                     "GB"]),
    "duration off the step grid": (GRID, ["scenario.duration_s = 0.1", "numerics.step_s = 0.03", "0.09 or 0.12"]),
    "duration off the output grid": (OUTPUT, ["scenario.duration_s = 0.1", "numerics.step_s = 0.01",
                                              "numerics.output_every = 3", "0.09 or 0.12"]),
    "output_every past the end": (EVERY, ["numerics.output_every = 1000000", "output_every <= 20"]),
    "turbulence window after the run": (LATE, ["turbulence.start_s = 5.0", "[0, 1] s"]),
}

#: on_step_grid writes the duration to 12 significant digits: at most 5e-13 of it from the grid [-]
ROUNDED = 1e-12


@pytest.mark.parametrize("case", list(CASES))
def test_a_run_that_cannot_be_done_is_refused_in_one_line(tmp_path, capsys, case):
    text, words = CASES[case]
    path = tmp_path / "case.toml"
    path.write_text(text)
    out = tmp_path / "out"
    code = cli.main(["simulate", str(path), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err, err
    assert all(w in err for w in words), err
    assert not out.exists()


def test_the_grid_check_accepts_decimal_steps():
    """0.3 / 0.1 is 2.9999999999999996 in binary: whole to the stated tolerance."""
    params = PAPER.replace(numerics={"step_s": 0.1, "output_every": 1})
    assert budget.check_run(params, 0.3, command=True) == (0.1, 3)
    with pytest.raises(ParameterError, match="not a whole number of steps"):
        budget.check_run(params, 0.35, command=True)
    with pytest.raises(ParameterError, match="not a whole number of steps"):
        budget.check_run(params, 0.36)  # a library run: the same check as the commands'


def _library_run(entry, numerics=None):
    """Every way a run starts from Python: the scenario runner, the simulation API, the
    fixed-length stepper, the engagement; each given 0.1 s at a step of 0.03 s."""
    from hosedrogue.engagement.simulate import simulate_engagement
    from hosedrogue.scenarios import load_scenario
    from hosedrogue.scenarios.runner import run
    from hosedrogue.simulation import simulate
    from hosedrogue.simulation.stepper import FixedLengthStepper

    numerics = numerics or {"step_s": 0.03, "output_every": 1}
    params = PAPER.replace(numerics=numerics)
    if entry == "scenarios.runner.run":
        sc = load_scenario("paper-turbulence").with_overrides(duration_s=0.1)
        return run(dataclasses.replace(sc, params=sc.params.replace(numerics=numerics)))
    if entry == "FixedLengthStepper":
        return FixedLengthStepper(params, 0.1, control_step_s=numerics["step_s"])
    return {"simulate": simulate, "simulate_engagement": simulate_engagement}[entry](params, 0.1)


@pytest.mark.parametrize("entry", ["scenarios.runner.run", "simulate", "FixedLengthStepper", "simulate_engagement"])
def test_a_library_run_off_its_step_grid_is_refused_as_the_command_refuses_it(entry):
    """The run would end at 0.09 s (3 steps), short of its 0.1 s: refused, naming the step."""
    with pytest.raises(ParameterError, match=r"duration_s = 0.1: not a whole number of steps of numerics.step_s = 0.03"):
        _library_run(entry)


@pytest.mark.parametrize("entry", ["scenarios.runner.run", "simulate", "FixedLengthStepper", "simulate_engagement"])
def test_a_library_run_off_its_output_grid_is_refused(entry):
    """0.1 s is 20 steps of 0.005 s, 6 output intervals of 3 steps and 2 steps more: the saved
    series would end at 0.09 s, short of the run's 0.1 s."""
    with pytest.raises(ParameterError, match=r"duration_s = 0.1: not a whole number of output intervals"):
        _library_run(entry, {"step_s": 0.005, "output_every": 3})


@pytest.mark.parametrize("duration, step, every", [(4.5049, 0.005, 4), (0.36, 0.1, 2), (1e-4, 0.01, 3),
                                                   (8.123456789, 0.002, 5)])
def test_on_step_grid_with_an_output_interval_gives_whole_intervals_nearest_the_duration(duration, step, every):
    """Whole output intervals (every steps) to the grid's tolerance, within half an interval of the
    wish, at least one interval: check_run accepts the run at that output_every."""
    params = PAPER.replace(numerics={"step_s": step, "output_every": every})
    d = budget.on_step_grid(duration, step, every)
    h, steps = budget.check_run(params, d)
    assert steps % every == 0 and steps == every * max(1, round(duration / (step * every)))
    assert abs(d - steps * step) <= ROUNDED * d


@pytest.mark.parametrize("duration, step", [(4.5049, 0.005), (0.36, 0.1), (1e-4, 0.01), (8.123456789, 0.002)])
def test_on_step_grid_gives_a_whole_number_of_steps_nearest_the_duration(duration, step):
    """Whole to the grid's tolerance, within half a step of the wish, at least one step."""
    params = PAPER.replace(numerics={"step_s": step, "output_every": 1})
    d = budget.on_step_grid(duration, step)
    h, steps = budget.check_run(params, d)
    assert steps == max(1, round(duration / step)) and abs(d - steps * step) <= ROUNDED * d


def test_the_whip_load_study_runs_whole_steps_and_records_the_duration_run():
    """Its duration, (standoff + push) / closure speed + stop + settle, is rarely whole at 0.7 m/s."""
    from hosedrogue.studies.whip_loads import study_scenario

    for links, step in ((None, None), (20, 0.0025)):  # output every 2 steps as shipped; every 4 at 2.5 ms
        sc = study_scenario("engage-response", 2e5, 0.7, links=links, step_s=step)
        h, steps = budget.check_run(sc.params, sc.duration_s)
        assert abs(sc.duration_s - steps * h) <= ROUNDED * sc.duration_s
        assert steps % sc.params.numerics.output_every == 0


def test_the_memory_estimate_counts_state_joints_and_signals():
    """Independent count for 20 links: 8 per link of state + 6 per joint (21) + 64 signals = 350
    float64 per sample."""
    assert budget.output_bytes(20, 1000) == 1000 * 350 * 8
    params = PAPER.replace(hose={"links": 20}, numerics={"step_s": 1e-5, "output_every": 1})
    with pytest.raises(ParameterError, match="8.64e\\+09 samples of 20 links"):
        budget.check_run(params, 86400.0)


@pytest.mark.subprocess
def test_the_day_long_run_is_refused_before_allocating(tmp_path):
    """The refused command's peak resident memory stays under 4 GB, against the 24 TB it would
    keep (and the 64 GiB of one array that failed to allocate before): with an empty numba cache
    the process compiles the model before the check and peaks at 1.3 GB doing so (measured in a
    fresh clone), 0.3 GB with the cache warm."""
    path = tmp_path / "day.toml"
    path.write_text(DAY)
    code = ("import resource, sys\nfrom hosedrogue import cli\n"
            f"code = cli.main(['simulate', {str(path)!r}, '--out', {str(tmp_path / 'out')!r}])\n"
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, code)")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    peak_kb, status = (int(x) for x in proc.stdout.split())
    assert status == 2 and peak_kb < 4_000_000, (peak_kb, proc.stderr)
    assert resource  # ru_maxrss is in kB on Linux


def test_a_campaign_of_too_many_runs_is_refused_before_any_run(tmp_path, capsys):
    out = tmp_path / "out"
    code = cli.main(["montecarlo", "paper-turbulence", "--runs", "73786976294838206464", "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and "runs = 73786976294838206464" in err and "GB" in err, err
    assert not out.exists()


@pytest.mark.parametrize("limit", [1.0025, 1.005, 0.003])
def test_an_episode_s_time_limit_is_put_on_its_output_grid(limit):
    """An episode's limit is its run's duration: moved to the nearest whole output interval
    (approach-moderate saves every 2 steps of 5 ms: 10 ms), at least one, so the run's saved
    series reaches it."""
    from hosedrogue.envs.options import docking_scenario

    sc = docking_scenario(time_limit_s=limit)
    num = sc.params.numerics
    h, steps = budget.check_run(sc.params, sc.duration_s)
    interval = h * num.output_every
    assert steps % num.output_every == 0 and steps // num.output_every == max(1, round(limit / interval))
    assert abs(sc.duration_s - limit) <= max(0.5 * interval, interval - limit) + 1e-12  # at least one interval


#: (value given, what the message shows): a bool is no duration, nor NaN, infinity, zero or a negative
BAD_DURATIONS = [(True, "True"), (float("nan"), "nan"), (float("inf"), "inf"), (0.0, "0.0"), (-1.0, "-1.0"),
                 ("1", "'1'")]


@pytest.mark.parametrize("value, shown", BAD_DURATIONS)
@pytest.mark.parametrize("entry", ["simulate", "FixedLengthStepper", "simulate_engagement"])
def test_every_loop_refuses_a_duration_in_the_same_line(entry, value, shown):
    """One check (budget.check_duration) for every loop: the same line, naming the field, the value
    and what is allowed (before, a bool ran for 1 s in three of the four loops)."""
    from hosedrogue.engagement.simulate import simulate_engagement
    from hosedrogue.simulation import simulate
    from hosedrogue.simulation.stepper import FixedLengthStepper

    start = {"simulate": simulate, "simulate_engagement": simulate_engagement,
             "FixedLengthStepper": lambda p, d: FixedLengthStepper(p, d, control_step_s=p.numerics.step_s)}[entry]
    with pytest.raises(ParameterError) as err:
        start(PAPER, value)
    assert str(err.value) == f"duration_s = {shown}: must be a finite number > 0 s"


def test_a_scenario_duration_has_its_upper_bound_in_the_same_check():
    with pytest.raises(ParameterError, match=r"^duration_s = 86401.0: must be a finite number in \(0, 86400\] s$"):
        budget.check_duration(86401.0, "duration_s", 86400.0)
    assert budget.check_duration(86400, "duration_s", 86400.0) == 86400.0


@pytest.mark.parametrize("entry, integrator", [("simulate_engagement", "adaptive"), ("simulate_engagement", "sdirk2"),
                                               ("FixedLengthStepper", "adaptive"), ("simulate", "sdirk2"),
                                               ("scenario", "adaptive")])
def test_every_loop_refuses_an_integrator_it_does_not_run_from_one_table(entry, integrator):
    """budget.INTEGRATORS for every loop (before, each loop had its own check, and the engagement
    run from Python took 'adaptive' with rigid links and ran fixed RK4 steps without a word)."""
    from hosedrogue.engagement.simulate import simulate_engagement
    from hosedrogue.scenarios import load_scenario
    from hosedrogue.simulation import simulate
    from hosedrogue.simulation.stepper import FixedLengthStepper

    params = PAPER.replace(numerics={"integrator": integrator})
    loop = {"simulate_engagement": "engagement", "scenario": "engagement", "simulate": "fixed-length",
            "FixedLengthStepper": "fixed-length stepper"}[entry]
    allowed = " or ".join(repr(a) for a in budget.INTEGRATORS[loop][False])
    line = (rf"^numerics.integrator = '{integrator}': the {loop} run of rigid links \(hose.axial_stiffness_n = inf\) "
            rf"integrates with {allowed}$")
    with pytest.raises(ParameterError, match=line):
        if entry == "scenario":
            sc = load_scenario("approach-moderate")
            dataclasses.replace(sc, params=sc.params.replace(numerics={"integrator": integrator}))
        elif entry == "FixedLengthStepper":
            FixedLengthStepper(params, 0.1, control_step_s=params.numerics.step_s)
        else:
            {"simulate": simulate, "simulate_engagement": simulate_engagement}[entry](params, 0.1)
