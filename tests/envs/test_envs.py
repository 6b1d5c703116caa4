"""The Gymnasium docking environment (docs/gym.md): Gymnasium's own checker, reproducible
episodes, the baseline against the same law flown as a user's docking controller through the
scenario, every outcome with its reward, the options reaching the physics, the picture, the
registration and a clear error without Gymnasium. Each test runs a few episodes (seconds)."""

import json
import math
import subprocess
import sys
import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

from hosedrogue import load_scenario, run  # noqa: E402
from hosedrogue.envs import DOCKING_ID, OBSERVATION, DockingEnv, DockingReward, PDFeedForward, StraightLine  # noqa: E402
from hosedrogue.errors import ParameterError  # noqa: E402
from hosedrogue.spec.standards import standard_intensity  # noqa: E402


@pytest.fixture(scope="module")
def env():
    return DockingEnv(time_limit_s=15.0)


def episode(env, policy, seed=0, options=None):
    """Fly one episode; the infos of every step and the sum of the rewards."""
    obs, info = env.reset(seed=seed, options=options)
    infos, total = [info], 0.0
    while True:
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        infos.append(info)
        total += reward
        if terminated or truncated:
            return infos, total, obs, terminated, truncated


def test_gymnasium_env_checker_passes_without_a_warning():
    e = gymnasium.make(DOCKING_ID, render_mode="rgb_array").unwrapped  # with its spec: every render mode tried
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(e)
    assert [str(w.message) for w in caught] == []
    assert e.observation_space.shape == (len(OBSERVATION),)


def test_same_seed_same_actions_same_observations_and_different_seeds_differ(env):
    actions = np.random.default_rng(3).uniform(-1.0, 1.0, (40, 3))
    actions[:, 0] = np.abs(actions[:, 0]) / 3.0  # forward, at up to 1 m/s

    def observations(seed):
        obs, _ = env.reset(seed=seed)
        return np.array([obs] + [env.step(a)[0] for a in actions])

    a, b, c = observations(11), observations(11), observations(12)
    assert np.array_equal(a, b)
    # the drogue's velocity after 0.8 s of moderate turbulence: centimetres per second apart
    assert np.max(np.abs(a[-1, 9:12] - c[-1, 9:12])) > 1e-3


def test_baseline_flies_the_shipped_pd_docking_controller_run(env):
    """The baseline through the environment and ``pd_docking`` through the scenario
    (approach-moderate-docking, seed 2018) are one law on one stepper: the same drogue path up to
    contact and the same capture test. Tolerance 1e-9 m: the action is the command over the speed
    bound, so the command can differ by one rounding (2e-16 relative) from the controller's, and a
    damped approach of 3 s does not grow that to a nanometre."""
    sc = load_scenario("approach-moderate-docking")
    ref = run(sc)
    short = DockingEnv(time_limit_s=sc.duration_s)
    infos, _, _, terminated, _ = episode(short, PDFeedForward(short),
                                         options={"turbulence_seed": sc.params.turbulence.seed})
    assert terminated and infos[-1]["outcome"] == "captured" and ref.outcome["result"] == "captured"
    t = np.array([i["t_s"] for i in infos])
    rows = np.searchsorted(ref.t_s, t - 1e-9)
    assert np.array_equal(ref.t_s[rows], t)
    path = np.array([i["measurement"]["drogue_position_m"] for i in infos])
    before = t < ref.outcome["contact_time_s"]
    assert before.sum() > 100
    assert np.max(np.abs(path[before] - ref.drogue_position_m[rows[before]])) < 1e-9
    assert abs(infos[-1]["miss_distance_m"] - ref.outcome["miss_distance_m"]) < 1e-9
    assert abs(infos[-1]["contact_time_s"] - ref.outcome["contact_time_s"]) < 1e-9


def test_the_drogues_control_surfaces_fly_in_the_episode():
    """approach-moderate-pid-actuated flown by the straight-line policy is the scenario's run: the
    PID commands the drogue's surfaces in the stepper as in the engagement driver. Tolerance 1e-9 m
    as above (one rounding of the command, a damped 3 s approach)."""
    sc = load_scenario("approach-moderate-pid-actuated")
    ref = run(sc)
    e = DockingEnv(scenario=sc, time_limit_s=sc.duration_s)
    infos, _, _, terminated, _ = episode(e, StraightLine(e), options={"turbulence_seed": sc.params.turbulence.seed})
    assert terminated and infos[-1]["outcome"] == ref.outcome["result"]
    t = np.array([i["t_s"] for i in infos])
    rows = np.searchsorted(ref.t_s, t - 1e-9)
    assert np.array_equal(ref.t_s[rows], t)
    path = np.array([i["measurement"]["drogue_position_m"] for i in infos])
    before = t < ref.outcome["contact_time_s"]
    assert before.sum() > 100
    assert np.max(np.abs(path[before] - ref.drogue_position_m[rows[before]])) < 1e-9
    assert abs(infos[-1]["miss_distance_m"] - ref.outcome["miss_distance_m"]) < 1e-9


def test_a_capture_scores_the_distance_closed_less_the_effort_plus_the_bonus(env):
    """The reward's terms as docs/gym.md writes them: the progress terms add up to the distance
    closed (d_0 - d_end) and the control terms to the effort, to the round-off of 150 additions."""
    w = env.reward_weights
    policy = PDFeedForward(env)
    obs, info = env.reset(seed=4)
    d0, total, effort = info["distance_m"], 0.0, 0.0
    while True:
        a = policy(obs)
        effort += float(a @ a) * env.control_step_s
        obs, reward, terminated, truncated, info = env.step(a)
        total += reward
        if terminated or truncated:
            break
    assert info["outcome"] == "captured" and terminated and not truncated
    expected = w.progress_per_m * (d0 - info["distance_m"]) - w.control_penalty_1_s * effort + w.capture_bonus
    assert total == pytest.approx(expected, abs=1e-12)
    assert info["reward_terms"]["terminal"] == w.capture_bonus


@pytest.mark.parametrize("case", ["miss", "failed latch", "breakaway", "time-out"])
def test_every_outcome_ends_the_episode_with_its_reward(case):
    if case == "miss":  # steer 0.6 m to the left of the drogue, then fly straight on
        e = DockingEnv()
        policy = lambda o: np.array([1.0 / 3.0, 0.5 if o[1] > -0.6 else 0.0, 0.0])  # noqa: E731
    elif case == "failed latch":  # in steady air, dead centre, but at 0.3 m/s: below the 0.5 m/s latch
        e = DockingEnv(turbulence="none", time_limit_s=15.0)
        policy = PDFeedForward(e, closure_speed_m_s=0.3)
    elif case == "breakaway":  # back away at 3 m/s
        e = DockingEnv()
        policy = lambda o: np.array([-1.0, 0.0, 0.0])  # noqa: E731
    else:  # hold station 3 m behind the drogue for the whole second
        e = DockingEnv(time_limit_s=1.0)
        policy = lambda o: np.zeros(3)  # noqa: E731
    infos, _, obs, terminated, truncated = episode(e, policy)
    last = infos[-1]
    assert last["outcome"] == case
    assert (terminated, truncated) == ((False, True) if case == "time-out" else (True, False))
    assert last["reward_terms"]["terminal"] == e.reward_weights.terminal(case)
    assert obs in e.observation_space
    if case == "failed latch":
        assert last["closure_speed_m_s"] < 0.5 and last["miss_distance_m"] < 0.305
    if case == "breakaway":
        assert last["distance_m"] > e.breakaway_distance_m
    if case == "time-out":
        assert last["t_s"] == pytest.approx(1.0, abs=1e-12) and last["result"] == "no contact"
    with pytest.raises(RuntimeError, match="call reset"):
        e.step(np.zeros(3))


def test_options_reach_the_physics():
    # steady air, no bow wave, the probe held 3 m aft: the drogue stays at its balance position
    # (to 1e-9 m: the balance position's residual; measured 2e-15 m) ...
    calm = DockingEnv(turbulence="none", bow_wave=False, time_limit_s=1.0)
    _, _, obs, _, _ = episode(calm, lambda o: np.zeros(3))
    assert np.max(np.abs(obs[12:15])) < 1e-9
    # ... and the bow wave at 2.75 m pushes it by centimetres (docs/docking-results.md: 50 mm at 0.5 m)
    bow = DockingEnv(turbulence="none", bow_wave=True, time_limit_s=1.0)
    _, _, obs, _, _ = episode(bow, lambda o: np.zeros(3))
    assert np.max(np.abs(obs[12:15])) > 5e-3
    # the PID holds the drogue within millimetres where it swings tens of centimetres
    # (docs/docking-results.md: RMS lateral 0.43 m without, 3 mm with the PID)
    swing = {}
    for controller in ("none", "pid"):
        e = DockingEnv(drogue_controller=controller, time_limit_s=3.0)
        infos, *_ = episode(e, lambda o: np.zeros(3), options={"turbulence_seed": 5})
        swing[controller] = max(np.max(np.abs(i["measurement"]["drogue_position_m"][1:]
                                              - i["measurement"]["drogue_balance_m"][1:])) for i in infos)
    assert swing["pid"] < 0.01 < 0.1 < swing["none"]
    severe = DockingEnv(turbulence="severe", reel="locked", model="paper")
    p = severe.scenario.params
    assert p.turbulence.sigma_m_s == pytest.approx(standard_intensity("severe", p.flight.altitude_m))
    assert severe.scenario.engagement.reel.law == "locked"
    assert p.hose.link_inertia == "paper" and p.hose.bending == "paper"
    assert p.turbulence.start_s + p.turbulence.duration_s == pytest.approx(severe.scenario.duration_s)
    assert DockingEnv(turbulence=2.5).scenario.params.turbulence.sigma_m_s == (2.5, 2.5, 2.5)


@pytest.mark.parametrize("kwargs, names", [
    ({"turbulence": "extreme"}, "turbulence = 'extreme'"),
    ({"reel": "python"}, "reel = 'python'"),
    ({"drogue_controller": "python"}, "drogue_controller = 'python'"),
    ({"model": "fine"}, "model = 'fine'"),
    ({"scenario": "paper-turbulence"}, "enabled [probe]"),
    ({"scenario": "approach-moderate-pilot"}, "pilot.enabled = True"),
    ({"time_limit_s": -1.0}, "time_limit_s = -1.0"),
    ({"breakaway_distance_m": 30.0}, "breakaway_distance_m = 30.0"),
    ({"reward": {"capture_bonus": -1.0}}, "reward.capture_bonus = -1.0"),
    ({"control_step_s": 0.013}, "control_step_s = 0.013"),
])
def test_a_bad_option_is_one_line_naming_it(kwargs, names):
    with pytest.raises(ParameterError) as err:
        DockingEnv(**kwargs)
    assert names in str(err.value) and "\n" not in str(err.value)


def test_bad_actions_and_reset_options_are_refused(env):
    env.reset(seed=0)
    with pytest.raises(ParameterError, match="action"):
        env.step([0.1, math.nan, 0.0])
    with pytest.raises(ParameterError, match="action"):
        env.step([0.1, 0.2])
    with pytest.raises(ParameterError, match="'wind'"):
        env.reset(options={"wind": 3})


def test_rgb_array_draws_the_hose_and_probe_where_the_stepper_has_them():
    e = DockingEnv(render_mode="rgb_array")
    obs, _ = e.reset(seed=0)
    first = e.render()
    for _ in range(50):
        e.step(np.array([1.0 / 3.0, 0.0, 0.0]))
    later = e.render()
    assert first.shape == later.shape == (320, 720, 3) and first.dtype == np.uint8
    assert np.any(first != later)  # the probe moved 1 m
    # the picture's source: the state's hose, whose last joint is the drogue the sensor measures
    # (no noise, no delay here), whose links have the hose's length, and the probe tip
    joints, tip = e.stepper.hose_shape()
    m = e.stepper.measurement
    assert np.max(np.abs(joints[-1] - m.drogue_position_m)) < 1e-12
    assert np.max(np.abs(tip - m.probe_position_m)) < 1e-12
    assert np.sum(np.linalg.norm(np.diff(joints, axis=0), axis=1)) == pytest.approx(m.hose_length_m, rel=1e-12)
    assert np.max(np.abs(joints[0])) < 1e-12  # the exit at the tow point
    with pytest.warns(UserWarning, match="render_mode='rgb_array'"):
        assert DockingEnv().render() is None


def test_registered_and_vectorized_by_gymnasium():
    e = gymnasium.make(DOCKING_ID, turbulence="light")
    assert isinstance(e.unwrapped, DockingEnv) and e.spec.id == DOCKING_ID
    vec = gymnasium.make_vec(DOCKING_ID, num_envs=2, vectorization_mode="sync")
    obs, _ = vec.reset(seed=1)
    assert obs.shape == (2, len(OBSERVATION))
    obs, reward, terminated, truncated, info = vec.step(np.tile([1.0 / 3.0, 0.0, 0.0], (2, 1)))
    assert obs.shape == (2, len(OBSERVATION)) and reward.shape == (2,)
    vec.close()


@pytest.mark.subprocess
def test_without_gymnasium_the_import_says_how_to_install_it():
    code = "import sys; sys.modules['gymnasium'] = None; import hosedrogue.envs"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode != 0
    assert r.stderr.strip().splitlines()[-1] == (
        "ImportError: hosedrogue.envs needs Gymnasium: pip install 'hosedrogue[gym]'")


def test_reward_weights_are_a_validated_section():
    assert DockingReward().terminal("time-out") == 0.0
    assert DockingEnv(reward={"miss_penalty": 2.0}).reward_weights.miss_penalty == 2.0


def test_gym_command_json_is_the_episodes_flown_in_python(capsys):
    """``hosedrogue gym --json``: the episodes of :func:`fly` on the campaign's turbulence seeds
    (run i of campaign seed s has ``run_seed(s, i)``), the same outcomes and miss distances bit for bit."""
    from hosedrogue.cli import main
    from hosedrogue.envs import fly
    from hosedrogue.studies.seeds import run_seed
    from hosedrogue.studies.statistics import wilson_interval

    assert main(["gym", "--episodes", "3", "--seed", "7", "--turbulence", "light", "--time-limit", "4.5",
                 "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    e = DockingEnv(turbulence="light", time_limit_s=4.5)
    ends = fly(e, PDFeedForward(e), [run_seed(7, i) for i in range(3)])
    assert [d["turbulence_seed"] for d in doc["episodes_detail"]] == [run_seed(7, i) for i in range(3)]
    assert [d["outcome"] for d in doc["episodes_detail"]] == [x["outcome"] for x in ends]
    assert [d["miss_distance_m"] for d in doc["episodes_detail"]] == [x["miss_distance_m"] for x in ends]
    k = sum(x["outcome"] == "captured" for x in ends)
    assert doc["capture_rate"] == k / 3 and doc["ci95"] == list(wilson_interval(k, 3))
    assert doc["turbulence_sigma_m_s"] == pytest.approx(list(e.scenario.params.turbulence.sigma_m_s), rel=1e-15)


@pytest.mark.parametrize("argv, names", [
    (["--episodes", "0"], "--episodes"),
    (["--model", "fine"], "model = 'fine'"),
    (["paper-turbulence"], "enabled [probe]"),
    (["--time-limit", "700"], "--time-limit"),
])
def test_gym_command_bad_input_is_one_line_exit_2(capsys, argv, names):
    from hosedrogue.cli import main

    with pytest.raises(SystemExit) as exc:
        raise SystemExit(main(["gym", *argv]))
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert names in err and "\n" not in err and "Traceback" not in err


def test_gym_command_help_states_the_units(capsys):
    from hosedrogue.cli import main

    with pytest.raises(SystemExit):
        main(["gym", "--help"])
    text = " ".join(capsys.readouterr().out.split()).split("options:", 1)[1]  # past the usage line
    for option, unit in (("--episodes N", "[-]"), ("--seed SEED", "[-]"), ("--time-limit S", "[s]")):
        assert option in text and unit in text.split(option, 1)[1].split("--", 1)[0]


@pytest.mark.subprocess
def test_another_process_flies_the_same_bits():
    """The same seed and actions in a fresh process: the same observations to the bit (the compiled
    loop's floating-point options are fixed, docs/develop.md), compared through their hex digits."""
    code = ("import numpy as np, hosedrogue.envs as he\n"
            "e = he.DockingEnv(); o, _ = e.reset(seed=21); out = [o]\n"
            "for _ in range(30): out.append(e.step(np.array([1/3, 0.2, -0.1]))[0])\n"
            "print(' '.join(float(x).hex() for x in np.ravel(out)))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    e = DockingEnv()
    o, _ = e.reset(seed=21)
    here = [o] + [e.step(np.array([1 / 3, 0.2, -0.1]))[0] for _ in range(30)]
    assert r.stdout.split() == [float(x).hex() for x in np.ravel(here)]


def test_report_section_alone(tmp_path):
    """The report's "Docking environment" section (fast: 8 episodes per level and policy): its
    table, episode and picture on disk, one row per level x policy whose interval holds its rate,
    the drawn episode a capture of the baseline, and the campaigns' columns empty without the
    docking section."""
    import pandas as pd

    from hosedrogue.report import docking_env
    from hosedrogue.report.settings import FAST
    from hosedrogue.report.writer import ReportFolder

    out = ReportFolder(tmp_path)
    docking_env.build(out, FAST)
    (section,) = [s.html for s in out.sections if s.anchor == "docking-env"]
    assert 'id="table-docking-env"' in section and 'id="fig-docking-env"' in section
    assert (tmp_path / docking_env.FIGURE_PNG).stat().st_size > 10_000
    table = pd.read_csv(tmp_path / docking_env.TABLE_CSV)
    assert len(table) == 3 * len(docking_env.POLICIES) and set(table["episodes"]) == {FAST.docking_runs}
    assert np.all((table["ci95_lo"] <= table["rate"]) & (table["rate"] <= table["ci95_hi"]))
    episode = pd.read_csv(tmp_path / docking_env.EPISODE_CSV)
    assert episode["t_s"].iloc[0] == 0.0 and np.all(np.diff(episode["t_s"]) > 0)
    assert "captured, radial miss" in section and section.count("<td>-</td>") == 6
    rec = out.headline["docking_env"]
    assert rec["built"] is True and set(rec["cells"]) == {f"{lv}-{p}" for lv in ("light", "moderate", "severe")
                                                          for p in docking_env.POLICIES}


def test_report_section_without_gymnasium_says_so(tmp_path, monkeypatch):
    from hosedrogue.report import docking_env
    from hosedrogue.report.settings import FAST
    from hosedrogue.report.writer import ReportFolder

    monkeypatch.setitem(sys.modules, "gymnasium", None)
    out = ReportFolder(tmp_path)
    docking_env.build(out, FAST)
    (section,) = [s.html for s in out.sections if s.anchor == "docking-env"]
    assert "pip install 'hosedrogue[gym]'" in section and out.headline["docking_env"] == {"built": False}
