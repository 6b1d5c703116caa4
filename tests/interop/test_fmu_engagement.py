"""The engagement FMU (``hosedrogue export-fmu --engagement``) run in fmpy: fed the probe path of
``engage-response`` it follows ``hosedrogue simulate engage-response``; flown by velocity
commands through the receiver's response it holds the closure speed; a failed or refused step
logs its reason; bad input exits 2 with one line. (Its model description and the validator:
tests/interop/test_fmu_description.py.)"""

import math
import re

import numpy as np
import pytest

from hosedrogue.cli import main

fmpy = pytest.importorskip("fmpy")
pytest.importorskip("pythonfmu")

from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.fmi2 import FMU2Slave  # noqa: E402

pytestmark = pytest.mark.fmu

LINKS = 20
#: SDIRK step [s] of the coarse variant: engage-response's own 5 ms
STEP_S = 0.005
#: RK4 step [s] of the rigid variant: engage-response's former 0.625 ms scaled with the link
#: length would be 5 ms at 20 links; 1.25 ms keeps the probe path's first-order hold in the ramp
#: (below) at 3e-7 m, under the check's 1e-6 m
RIGID_STEP_S = 0.00125
DURATION_S = 4.0  # capture at 2.0004 s (3.0006 m at 1.5 m/s), the push's ramp 2.83-3.83 s
#: [m]: engage-response's 3 m would put the capture at 2.0 s, on the end of a step, a knife edge
#: where rounding (1e-13 m in the tip's position) decides in which step the tip crosses the
#: coupler plane (the elastic FMU flown by velocity commands coupled one step before simulate:
#: 3e-4 m apart); 0.6 mm more puts it 0.08 of a step past the grid at 5 ms (0.32 at 1.25 ms), 0.6 mm
#: of tip travel against rounding's 1e-13 m
STANDOFF_M = 3.0006
AXES = "xyz"


def coarse(rigid: bool) -> str:
    """engage-response on 20 links instead of 160, 4 s instead of 15 (the full case:
    docs/interop.md): its elastic hose (docs/model.md §11) and the SDIRK, or the rigid links
    (RK4) it had before its hose became elastic."""
    hose = "axial_stiffness_n = inf\naxial_damping_n_s = 0.0" if rigid else ""
    numerics = f'integrator = "rk4"\nstep_s = {RIGID_STEP_S}' if rigid else f"step_s = {STEP_S}"
    return f"""
[scenario]
extends = "engage-response"
name = "engage-response-coarse{'-rigid' if rigid else ''}"
duration_s = {DURATION_S}

[hose]
links = {LINKS}
{hose}

[probe]
standoff_m = {STANDOFF_M}

[numerics]
{numerics}
output_every = 1
"""


def build_case(tmp_path_factory, rigid: bool):
    """The coarse scenario file, its run by ``simulate`` and its engagement FMU."""
    from hosedrogue import load_scenario, run
    from hosedrogue.interop.fmu import prepare_python_host

    prepare_python_host()  # fmpy runs the FMU in this interpreter (docs/interop.md)
    folder = tmp_path_factory.mktemp("engagement_fmu_rigid" if rigid else "engagement_fmu")
    toml = folder / "coarse.toml"
    toml.write_text(coarse(rigid))
    fmu = folder / "engagement.fmu"
    assert main(["export-fmu", "--engagement", str(toml), "--out", str(fmu)]) == 0
    scenario = load_scenario(str(toml))
    assert scenario.params.hose.elastic != rigid
    return scenario, run(scenario), fmu


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    """The coarse engage-response with its elastic hose (the SDIRK at 5 ms)."""
    return build_case(tmp_path_factory, rigid=False)


@pytest.fixture(scope="module")
def rigid_case(tmp_path_factory):
    """The coarse engage-response with rigid links (RK4 at 1.25 ms)."""
    return build_case(tmp_path_factory, rigid=True)


def prescribed_path(t_s, start_m, probe, t_cap_s):
    """engage-response's probe path written out from docs/engagement.md: forward at the closure
    speed; from the capture on to ``push_m`` further, the last part a half-cosine speed ramp of
    ``stop_time_s`` to rest. The tip's position [m] and velocity [m/s]."""
    vc, t_stop = probe.closure_speed_m_s, probe.stop_time_s
    s, v = vc * t_s, vc
    if t_s > t_cap_s:
        cruise = max(probe.push_m - 0.5 * vc * t_stop, 0.0)
        t_ramp = t_cap_s + cruise / vc
        if t_s > t_ramp:
            tau = min(t_s - t_ramp, t_stop)
            w = math.pi / t_stop
            s = vc * t_cap_s + cruise + 0.5 * vc * (tau + math.sin(w * tau) / w)
            v = 0.5 * vc * (1.0 + math.cos(w * tau)) if tau < t_stop else 0.0
    return np.asarray(start_m) + (s, 0.0, 0.0), np.array([v, 0.0, 0.0])


def fly(fmu, steps, command, start=None, position_input=True, velocity_feed=False, step_s=STEP_S):
    """Drive the FMU like a script master: per communication step of ``step_s`` [s], set the inputs
    ``command(k, outputs) -> {name: value}`` and take the step; the outputs at every point."""
    md = fmpy.read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    outputs = [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
    slave = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(str(fmu)), instanceName="master",
                      modelIdentifier=md.coSimulation.modelIdentifier)
    slave.instantiate()
    rows, taken = [], 0
    try:
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        slave.setBoolean([vr["probe_position_input"], vr["probe_velocity_feed"]], [position_input, velocity_feed])
        slave.setReal([vr["sample_time_s"]], [step_s])
        if start is not None:
            slave.setReal([vr[f"probe_cmd_{a}_m"] for a in AXES], list(start))
        slave.exitInitializationMode()

        def read():
            values = dict(zip(outputs, slave.getReal([vr[n] for n in outputs])))
            values["coupled"] = slave.getBoolean([vr["coupled"]])[0]
            return values

        rows.append(read())
        for k in range(steps):
            inputs = command(k, rows[-1])
            slave.setReal([vr[n] for n in inputs], list(inputs.values()))
            try:
                slave.doStep(currentCommunicationPoint=k * step_s, communicationStepSize=step_s)
            except FMICallException:  # fmi2Discard: the step was not taken
                break
            taken += 1
            rows.append(read())
        slave.terminate()
    finally:
        slave.freeInstance()
    return rows, taken


def logged_run(fmu, steps, command, **kwargs):
    """:func:`fly` through fmpy's logger: the rows and the messages (status, category, text)."""
    messages = []
    inputs = command(0, {})
    table = np.array([(0.0, *inputs.values()), (steps * STEP_S, *inputs.values())],
                     dtype=[("time", np.float64)] + [(n, np.float64) for n in inputs])
    rows = fmpy.simulate_fmu(str(fmu), stop_time=steps * STEP_S, step_size=STEP_S, input=table,
                             debug_logging=True, logger=lambda *m: messages.append(m[-3:]), **kwargs)
    return rows, messages


def columns(rows, prefix):
    return np.array([[r[f"{prefix}_{a}_m"] for a in AXES] for r in rows])


@pytest.mark.parametrize("feed", [False, True], ids=["positions", "positions-and-velocities"])
@pytest.mark.parametrize("hose", ["elastic", "rigid"])
def test_fed_the_probe_path_it_matches_simulate(request, hose, feed):
    """The check of issue 20: the FMU in fmpy, fed the probe path of engage-response (positions at
    each communication step, with the velocity feed their velocities too; the capture time from
    the run), against ``simulate``: the shipped elastic hose and the rigid links."""
    scenario, result, fmu = request.getfixturevalue("rigid_case" if hose == "rigid" else "case")
    step_s = scenario.params.numerics.step_s
    probe = scenario.engagement.probe
    frame = result.to_dataframe()
    start = frame[[f"probe_{a}_m" for a in AXES]].to_numpy()[0]
    t_cap = result.outcome["contact_time_s"]
    assert result.completed and result.outcome["result"] == "captured"
    steps = round(DURATION_S / step_s)

    def command(k, _):
        p, v = prescribed_path((k + 1) * step_s, start, probe, t_cap)
        names = [f"probe_cmd_{a}_m" for a in AXES] + ([f"probe_cmd_v{a}_m_s" for a in AXES] if feed else [])
        return dict(zip(names, [*p, *v]))

    rows, taken = fly(fmu, steps, command, start=start, velocity_feed=feed, step_s=step_s)
    assert taken == steps and len(rows) == len(frame)
    t = frame["t_s"].to_numpy()
    drogue = np.abs(columns(rows, "drogue") - frame[[f"drogue_{a}_m" for a in AXES]].to_numpy()).max(axis=1)
    probe_tip = np.abs(columns(rows, "probe") - frame[[f"probe_{a}_m" for a in AXES]].to_numpy()).max()
    length = np.abs(np.array([r["hose_length_m"] for r in rows]) - frame["hose_length_m"].to_numpy()).max()
    ramp = t_cap + (probe.push_m - 0.5 * probe.closure_speed_m_s * probe.stop_time_s) / probe.closure_speed_m_s
    fed = "positions and velocities" if feed else "positions"
    print(f"FMU ({hose}, {fed}) vs simulate: drogue max |dP| = {drogue.max():.3g} m ({drogue[t <= ramp].max():.3g} m "
          f"before the push's ramp at {ramp:.3f} s), probe tip {probe_tip:.3g} m, hose length {length:.3g} m")
    # the probe tip at the communication points is the fed path to rounding (1e-12 m of 20 m)
    assert probe_tip < 1e-12
    if feed:  # the cubic through both ends' positions and velocities ends at the velocity fed:
        # rounding of positions of 20 m differenced over the step, 1e-9 m/s
        tip_v = np.array([[r[f"probe_v{a}_m_s"] for a in AXES] for r in rows[1:]])
        fed_v = np.array([prescribed_path((k + 1) * step_s, start, probe, t_cap)[1] for k in range(steps)])
        assert np.abs(tip_v - fed_v).max() < 1e-9
    # until the ramp the path is straight at constant speed, so the FMU's polynomials through it
    # are the path itself: the same run to rounding (1e-9 m)
    assert drogue[t <= ramp].max() < 1e-9
    # in the ramp the kernel evaluates the FMU's tip, as the run's prescribed path, at every
    # integrator stage's time (not as states through the stages: the SDIRK's first stage had it at
    # p + hg v + (hg)^2 a where the path is at p + hg v + (hg)^2 a / 2, 1.8e-6 m here at 5 ms,
    # O(h^2)), so what remains is how the FMU's polynomial over each step departs from the cosine
    if not feed:
        # the parabola leaving with the three-point parabola's slope: it meets the fed positions at
        # both ends, so its velocity error has zero mean over the step; RK4's Simpson weights
        # integrate that quadratic exactly (measured O(h^3): 4.3e-8, 5.4e-9, 6.7e-10 m at 5, 2.5,
        # 1.25 ms on the rigid links; bound 1e-8 m at 1.25 ms), the SDIRK's two stages (at hg and
        # h) only a linear one (O(h^2): 1.6e-7, 4.2e-8, 1.1e-8 m on the elastic hose): the check's
        # 1e-6 m
        bound = 1e-8 if hose == "rigid" else 1e-6
        assert drogue.max() < bound and length < bound
    else:
        # the cubic through both ends' positions and velocities: O(h^4) in position, O(h^3) in
        # velocity (measured 2.4e-9, 6.5e-10, 2.3e-11 m at 5, 2.5, 1.25 ms on the elastic hose, the
        # same with the stages corrected to 1e-9 m/s; 1.3e-9, 1.1e-11, 1.1e-13 m on the rigid
        # links): 1e-8 m, 4x the largest, 1 % of the check's
        assert drogue.max() < 1e-8 and length < 1e-8
    assert rows[-1]["coupled"] and not rows[0]["coupled"]
    assert max(r["probe_load_n"] for r in rows) == pytest.approx(result.outcome["peak_probe_load_n"], rel=1e-3)


def test_a_kink_in_the_position_path_is_one_parabola(case):
    """Positions only, the tip held still and then moved sideways at 1 m/s from t = 4 h on:
    the three-point parabolas are straight lines except in the step after the kink, where the
    parabola through (still, still, moved) leaves at dv / 2 and ends at v + dv / 2 (1.5 m/s), and
    every fed point is reached."""
    _, result, fmu = case
    start = result.to_dataframe()[[f"probe_{a}_m" for a in AXES]].to_numpy()[0]

    def path(k):  # the position fed for the end of step k
        return start + (0.0, max(k + 1 - 4, 0) * STEP_S * 1.0, 0.0)

    def command(k, _):
        return dict(zip((f"probe_cmd_{a}_m" for a in AXES), path(k)))

    rows, taken = fly(fmu, 8, command, start=start)
    vy = np.array([r["probe_vy_m_s"] for r in rows])
    # exact arithmetic but for rounding of positions ~20 m differenced over 1.25 ms: 1e-9 m/s
    np.testing.assert_allclose(vy, [0, 0, 0, 0, 0, 1.5, 1.0, 1.0, 1.0], atol=1e-9)
    tips = columns(rows, "probe")
    np.testing.assert_allclose(tips[1:], [path(k) for k in range(8)], rtol=0, atol=1e-12)


def test_velocity_commands_through_the_receiver_hold_the_closure_speed(case):
    """Velocity input at the closure speed: the receiver's response starts at that speed, so the tip
    flies the prescribed straight line and the run is simulate's until the push's ramp."""
    scenario, result, fmu = case
    probe = scenario.engagement.probe
    frame = result.to_dataframe()
    t_cap = result.outcome["contact_time_s"]
    steps = round(t_cap / STEP_S) + 40  # into the coupled cruise, before the ramp

    def command(k, _):
        return {"probe_cmd_vx_m_s": probe.closure_speed_m_s, "probe_cmd_vy_m_s": 0.0, "probe_cmd_vz_m_s": 0.0}

    rows, taken = fly(fmu, steps, command, position_input=False)
    assert taken == steps
    sim = frame[[f"drogue_{a}_m" for a in AXES]].to_numpy()[:steps + 1]
    assert np.abs(columns(rows, "drogue") - sim).max() < 1e-9  # the same run to rounding (1e-9 m)
    assert rows[-1]["coupled"] and rows[-1]["probe_vx_m_s"] == probe.closure_speed_m_s


@pytest.mark.parametrize("inputs, reason", [
    # 1600x the tow tension: the rigid links swing past the yaw limit, the elastic hose's responsive
    # reel pays out past its end stop (measured: at 0.061 s, L = 30.8 m of 30 m)
    ({"u_y_n": 1e7}, r"stopped at t = [0-9.e+-]+ s: .*(yaw passed the limit|non-finite|left the reel's range)"),
    ({"u_y_n": math.nan}, r"refused a step at t = 0 s: input u_y_n = nan: must be a finite number"),
])
def test_a_failed_step_logs_its_reason(case, inputs, reason):
    _, _, fmu = case

    def command(k, _):
        return inputs

    rows, messages = logged_run(fmu, 400, command)
    failures = [(status, category, text.decode()) for status, category, text in messages
                if text.startswith(b"hosedrogue:")]
    assert failures, messages
    status, category, text = failures[0]
    assert status == 2 and category == b"logStatusDiscard"  # fmi2Discard, as fmi2DoStep returns
    assert re.search(reason, text), text
    assert rows["time"][-1] < 400 * STEP_S  # fmpy ended the run at the last good point


def test_a_step_past_the_frozen_duration_says_so(case):
    scenario, _, fmu = case
    rows, messages = logged_run(fmu, round(DURATION_S / STEP_S) + 2, lambda k, _: {"u_y_n": 0.0})
    texts = [m[-1].decode() for m in messages if m[-1].startswith(b"hosedrogue:")]
    assert any("past it: steps beyond it will fail" in t for t in texts)  # the stop time, at setup
    assert any(f"the frozen scenario's duration_s = {DURATION_S:g} s" in t for t in texts)
    assert rows["time"][-1] == pytest.approx(DURATION_S, abs=1e-9)


@pytest.mark.parametrize("argv, message", [
    (["--engagement", "paper-turbulence"], "has no engagement"),
    (["--engagement", "approach-moderate-pilot"], "pilot.enabled = true"),
    (["--engagement", "engage-response", "--config", "paper"], "--config paper: not with --engagement"),
    (["--duration", "2"], "--duration: only with --engagement"),
    (["--engagement", "no-such-scenario"], "no-such-scenario"),
])
def test_bad_input_exits_2_with_one_line_and_writes_nothing(tmp_path, capsys, argv, message):
    out = tmp_path / "e.fmu"
    assert main(["export-fmu", *argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_check_validates_and_runs_the_engagement_fmu(case, capsys):
    import json

    scenario, _, _ = case
    toml = scenario.source
    assert main(["export-fmu", "--engagement", str(toml), "--duration", "0.5", "--check", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["ok"] and report["problems"] == []  # fmpy's validator and the units: 0 problems
    sim = report["simulation"]
    # the start inputs fly the probe straight at the drogue, which stays at its balance position
    # until the contact at 2 s: within the equilibrium solver's 1e-6 m, and still (1e-9 m) over 0.5 s
    assert sim["kind"] == "engagement" and sim["duration_s"] == pytest.approx(0.5)
    assert sim["start_offset_m"] < 1e-6 and sim["drift_m"] < 1e-9


@pytest.mark.parametrize("take_up_m_s", [0.0, 0.5])
def test_the_reel_command_sets_the_take_up(rigid_case, tmp_path, take_up_m_s):
    """A reel of law "python" commanded through reel_speed_cmd_m_s: the drive follows the held
    command through its first-order lag (tau = speed_time_constant_s) within its torque limit, so
    from rest L(t) = L0 - c (t - tau (1 - exp(-t / tau))); zero keeps the length (as locked). On
    the rigid links: their RK4 integrates the lag to the bounds below."""
    import dataclasses

    from hosedrogue.interop.fmu import export_fmu

    scenario, _, _ = rigid_case
    reel = dataclasses.replace(scenario.engagement.reel, law="python")
    commanded = dataclasses.replace(scenario, duration_s=1.0,
                                    engagement=dataclasses.replace(scenario.engagement, reel=reel))
    fmu = export_fmu(tmp_path / "reel.fmu", commanded)
    steps = round(1.0 / RIGID_STEP_S)
    rows, taken = fly(fmu, steps, lambda k, _: {"reel_speed_cmd_m_s": take_up_m_s}, position_input=False,
                      step_s=RIGID_STEP_S)
    assert taken == steps and not rows[-1]["coupled"]  # the probe is still closing (contact at 2 s)
    t = RIGID_STEP_S * np.arange(steps + 1)
    tau = reel.speed_time_constant_s
    expected = rows[0]["hose_length_m"] - take_up_m_s * (t - tau * (1.0 - np.exp(-t / tau)))
    length = np.array([r["hose_length_m"] for r in rows])
    error = np.abs(length - expected)
    # until the exit link is first merged (below 0.5 l_nom = 0.4 m, after 0.4 m taken up): RK4 on
    # the lag's exponential at h / tau = 0.025, ~(h/tau)^4 / 120 ~ 3e-9 relative of the 0.4 m: 1e-8 m
    merge = np.flatnonzero(np.abs(np.diff(length - expected)) > 1e-8)
    before = error[:merge[0] + 1] if merge.size else error
    print(f"take-up {take_up_m_s} m/s: max |L - L_exact| = {before.max():.3g} m before the merge at "
          f"{t[merge[0] + 1] if merge.size else '-'} s, {error.max():.3g} m over 1 s")
    assert before.max() < 1e-8 and (take_up_m_s == 0.0 or merge.size == 1)
    # a merge keeps the joints, so it loses a little free length and changes the reel speed a little
    # (docs/engagement.md, "Hose of varying length": 2 um lost over engage-response's take-up)
    assert error.max() < 1e-6
    # the reel speed at 1 s: the lag's, but for the merge's small speed jump (measured 3e-8 m/s)
    assert rows[-1]["reel_speed_m_s"] == pytest.approx(take_up_m_s * (1.0 - math.exp(-1.0 / tau)), abs=1e-6)


def test_the_stepper_pass_through_is_refused_where_it_means_nothing(case):
    from hosedrogue.engagement.stepper import EngagementStepper
    from hosedrogue.errors import ParameterError
    from hosedrogue.spec.sections import Receiver

    scenario, _, _ = case
    e = scenario.engagement
    kwargs = dict(control_step_s=STEP_S, reel=e.reel, probe=e.probe, record=False)
    with pytest.raises(ParameterError, match="only with a receiver"):
        EngagementStepper(scenario.params, 0.1, receiver_pass_through=True, **kwargs)
    with pytest.raises(ParameterError, match=r"probe_start_m = \[1, 2\]: must be 3 finite numbers \[m\]"):
        EngagementStepper(scenario.params, 0.1, receiver=Receiver(), probe_start_m=[1, 2], **kwargs)
    stepper = EngagementStepper(scenario.params, 0.1, receiver=Receiver(), **kwargs)
    stepper.reset()
    with pytest.raises(ParameterError, match="move_receiver: only with receiver_pass_through"):
        stepper.move_receiver((1.0, 0.0, 0.0), (0.0, 0.0, 0.0))


def test_the_drogue_surfaces_fly_in_the_fmu(tmp_path):
    """approach-moderate-pid-actuated (the paper's PID commanding the drogue's control surfaces, in
    moderate turbulence, the bow wave on), 2 s of it: the FMU flown at the closure speed through the
    receiver's response is the scenario's run (its straight probe) to rounding (1e-9 m), and not
    the run with the ideal force."""
    import dataclasses

    from hosedrogue import load_scenario, run

    scenario = load_scenario("approach-moderate-pid-actuated").with_overrides(duration_s=2.0)
    fmu = tmp_path / "actuated.fmu"
    assert main(["export-fmu", "--engagement", "approach-moderate-pid-actuated", "--duration", "2",
                 "--out", str(fmu)]) == 0
    step, every = scenario.params.numerics.step_s, scenario.params.numerics.output_every
    result = run(scenario)
    frame = result.to_dataframe()
    md = fmpy.read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    assert "control surfaces" in md.description
    slave = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(str(fmu)), instanceName="surfaces",
                      modelIdentifier=md.coSimulation.modelIdentifier)
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    out = [vr[f"drogue_{a}_m"] for a in AXES]
    rows = [slave.getReal(out)]
    for k in range(round(2.0 / step)):  # the start inputs: the closure speed forward
        slave.doStep(currentCommunicationPoint=k * step, communicationStepSize=step)
        rows.append(slave.getReal(out))
    slave.terminate()
    slave.freeInstance()
    sim = frame[[f"drogue_{a}_m" for a in AXES]].to_numpy()
    diff = np.abs(np.array(rows)[::every] - sim).max()
    ideal = run(dataclasses.replace(scenario, loop=dataclasses.replace(scenario.loop, drogue_actuator=None)))
    off = np.abs(np.array(rows)[::every] - ideal.drogue_position_m).max()
    print(f"surfaces: FMU vs simulate max |dP| = {diff:.3g} m; vs the ideal force's run {off:.3g} m")
    # the PID holds the drogue within millimetres either way; the surfaces' lag moves it by more than 1e-6 m
    assert result.completed and diff < 1e-9 and off > 1e-6


def test_surfaces_commanded_by_deflection_are_refused(tmp_path):
    import dataclasses

    from hosedrogue import load_scenario
    from hosedrogue.errors import ParameterError
    from hosedrogue.interop.fmu import export_fmu
    from hosedrogue.spec.sections import Controller

    scenario = load_scenario("approach-moderate-pid-actuated")
    loop = dataclasses.replace(scenario.loop, controller=Controller(
        type="python", entry="hosedrogue.examples.controllers:fixed_deflection", sample_time_s=0.01),
        drogue_actuator=dataclasses.replace(scenario.loop.drogue_actuator, command="deflection"))
    with pytest.raises(ParameterError, match=r"^drogue_actuator.command = 'deflection': the engagement FMU's drogue"):
        export_fmu(tmp_path / "e.fmu", dataclasses.replace(scenario, loop=loop))
    assert list(tmp_path.iterdir()) == []
