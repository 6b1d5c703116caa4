"""hosedrogue/Docking-v1 (docs/gym.md, "Docking-v1"): Gymnasium's checker on every registered
environment, its spaces and time limit, snapshots and copies that continue bit for bit, seeds
that decide every randomized draw, the randomization reaching the physics, and a reward whose
terms are what the page says. Each test flies a few episodes (seconds)."""

import copy
import math
import pickle
import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

import hosedrogue.envs as he  # noqa: E402
from hosedrogue.envs import DOCKING_V1_ID, OBSERVATION_SCALE, DockingEnvV1, PDFeedForward  # noqa: E402
from hosedrogue.errors import ParameterError  # noqa: E402


def fly(env, policy, steps=None):
    """(observations, rewards, infos, terminated, truncated) of the episode from here on (or ``steps`` steps)."""
    out, k = ([], [], []), 0
    while steps is None or k < steps:
        obs, reward, terminated, truncated, info = env.step(policy(env.last_obs))
        out[0].append(obs), out[1].append(reward), out[2].append(info)
        env.last_obs, k = obs, k + 1
        if terminated or truncated:
            return (*out, terminated, truncated)
    return (*out, False, False)


def same(a, b):
    """Bit-for-bit equality of two flights (observations, rewards, the infos' numbers)."""
    assert np.array_equal(np.array(a[0]), np.array(b[0])) and a[1] == b[1] and a[3:] == b[3:]
    for i, j in zip(a[2], b[2]):
        assert i["outcome"] == j["outcome"] and i["reward_terms"] == j["reward_terms"] and i["t_s"] == j["t_s"]
        assert np.array_equal(i["measurement"]["drogue_position_m"], j["measurement"]["drogue_position_m"])


@pytest.mark.parametrize("env_id, kwargs", [(k, {}) for k in sorted(gymnasium.registry) if k.startswith("hosedrogue/")]
                         + [("hosedrogue/Docking-v1", {"randomize": True})])
def test_gymnasium_env_checker_passes_on_every_registered_environment(env_id, kwargs):
    modes = gymnasium.envs.registration.load_env_creator(gymnasium.spec(env_id).entry_point).metadata["render_modes"]
    e = gymnasium.make(env_id, render_mode="rgb_array" if modes else None, **kwargs).unwrapped
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(e)
    assert [str(w.message) for w in caught] == []


def test_float32_spaces_normalized_observation_and_the_time_limit_in_the_spec():
    env = gymnasium.make(DOCKING_V1_ID, turbulence="none")
    assert env.spec.max_episode_steps == he.MAX_EPISODE_STEPS == 500
    assert env.observation_space.dtype == np.float32 and env.action_space.dtype == np.float32
    obs, info = env.reset(seed=1)
    # the observation times its scale is the measurement, to float32's rounding (6e-8 relative)
    rel = info["measurement"]["relative_position_m"]
    assert obs.dtype == np.float32 and np.allclose(obs[:3] * OBSERVATION_SCALE[:3], rel, rtol=1e-7, atol=0)
    steps, truncated = 0, False
    while not truncated:  # holding station 3 m aft in still air: nothing ends it but the TimeLimit
        obs, _, terminated, truncated, info = env.step(np.zeros(3, dtype=np.float32))
        steps += 1
        assert not terminated
    assert steps == 500 and info["t_s"] == pytest.approx(10.0, abs=1e-12)
    short = gymnasium.make(DOCKING_V1_ID, turbulence="none", max_episode_steps=100)
    short.reset(seed=1)
    ends = [short.step(np.zeros(3))[3] for _ in range(100)]
    assert ends == [False] * 99 + [True]


@pytest.mark.parametrize("clone", ["deepcopy", "pickle", "state"])
def test_a_copy_in_mid_episode_continues_bit_for_bit_like_the_original(clone):
    """Through the rest of the episode and the next (randomized) reset: the copy holds the run,
    the bookkeeping and the generator."""
    env = DockingEnvV1(randomize=True)
    policy = PDFeedForward(env)
    env.last_obs, _ = env.reset(seed=7)
    fly(env, policy, steps=20)
    if clone == "deepcopy":
        twin = copy.deepcopy(env)
    elif clone == "pickle":
        twin = pickle.loads(pickle.dumps(env))
    else:  # a snapshot restored on another environment made with the same arguments
        twin = DockingEnvV1(randomize=True)
        twin.set_state(env.get_state())
    twin.last_obs = env.last_obs
    a, b = fly(env, policy), fly(twin, policy)
    same(a, b)
    assert a[3] or a[4]
    assert "peak_load_n" in a[2][-1] or a[2][-1]["outcome"] != "captured"
    env.last_obs, info_a = env.reset()
    twin.last_obs, info_b = twin.reset()
    assert "peak_load_n" not in info_a and "miss_distance_m" not in info_a  # not known before the capture test
    assert info_a["randomized"] == info_b["randomized"] and info_a["turbulence_seed"] == info_b["turbulence_seed"]
    same(fly(env, policy, steps=30), fly(twin, policy, steps=30))


def test_a_snapshot_restores_the_same_future_again_and_again():
    env = DockingEnvV1()
    policy = PDFeedForward(env)
    env.last_obs, _ = env.reset(seed=3)
    fly(env, policy, steps=15)
    state, obs = env.get_state(), env.last_obs
    first = fly(env, policy)
    env.set_state(state)
    env.last_obs = obs
    same(first, fly(env, policy))
    with pytest.raises(ParameterError, match="get_state"):
        env.set_state({"nonsense": 1})


def test_the_seed_decides_every_randomized_draw():
    env = DockingEnvV1(randomize=True)
    policy = PDFeedForward(env)

    def episode(seed):
        env.last_obs, info = env.reset(seed=seed)
        return info, fly(env, policy, steps=40)

    (i1, a), (i2, b), (i3, c) = episode(11), episode(11), episode(12)
    assert i1["randomized"] == i2["randomized"] and set(i1["randomized"]) == set(he.RANDOMIZABLE)
    same(a, b)
    assert all(i1["randomized"][k] != i3["randomized"][k] for k in he.RANDOMIZABLE)
    assert not np.array_equal(np.array(a[0]), np.array(c[0]))  # another episode
    # a hose of another length and mass flies another path: the drogue's balance differs by centimetres at least
    assert np.max(np.abs(i1["measurement"]["drogue_balance_m"] - i3["measurement"]["drogue_balance_m"])) > 0.01


def test_the_randomization_reaches_the_physics_and_a_curriculum_changes_it_from_a_reset_on():
    fixed = {"start_standoff_m": 4.0, "start_offset_y_m": 0.3, "start_offset_z_m": -0.2, "hose_length_m": 12.0,
             "sensor_delay_s": 0.05}
    env = DockingEnvV1(turbulence="none", bow_wave=False, randomize=fixed)
    obs, info = env.reset(seed=0)
    # the probe starts where it was put (drogue minus probe), to float32's rounding of the observation
    assert np.allclose(obs[:3] * OBSERVATION_SCALE[:3], [4.0, -0.3, 0.2], rtol=1e-7, atol=0)
    assert info["measurement"]["hose_length_m"] == pytest.approx(12.0, abs=1e-12)
    assert env.scenario.loop.sensor.delay_s == pytest.approx(0.04, abs=1e-12)  # rounded down to 2 control steps
    balance = {}
    for speed in (130.0, 200.0):  # faster air lifts and streams the drogue: decimetres
        _, info = env.reset(options={"randomize": {"airspeed_m_s": speed}})
        balance[speed] = info["measurement"]["drogue_balance_m"]
        assert env.scenario.params.flight.airspeed_m_s == speed
    assert np.max(np.abs(balance[130.0] - balance[200.0])) > 0.1
    _, info = env.reset()  # the curriculum's last setting holds
    assert info["randomized"] == {"airspeed_m_s": 200.0}
    _, info = env.reset(options={"randomize": None})
    assert info["randomized"] == {} and env.scenario is env.base_scenario


@pytest.mark.parametrize("kwargs, names", [
    ({"randomize": {"wingspan_m": (1, 2)}}, "unknown name(s) 'wingspan_m'"),
    ({"randomize": {"hose_length_m": (20, 30)}}, "randomize['hose_length_m'] = (20, 30)"),
    ({"randomize": {"airspeed_m_s": (160, 140)}}, "low <= high"),
    ({"randomize": "yes"}, "randomize = 'yes'"),
    ({"randomize": {"start_standoff_m": 5.0, "start_offset_y_m": 1.5}, "breakaway_distance_m": 5.0},
     "must stay below breakaway_distance_m = 5"),
    ({"reward": {"min_closure_m_s": 3.0}}, "reward.min_closure_m_s = 3.0"),
])
def test_a_bad_option_is_one_line_naming_it(kwargs, names):
    with pytest.raises(ParameterError) as err:
        DockingEnvV1(**kwargs)
    assert names in str(err.value) and "\n" not in str(err.value)
    with pytest.raises(ParameterError, match="unknown key"):
        DockingEnvV1().reset(options={"seed": 3})


def phi(w, obs):
    """The shaping potential of an observation by the formula of docs/gym.md, "Reward" (not the
    environment's code): the offset less the weighted radial offset, axial distance and closure
    speed's distance outside the window."""
    x, y, z, vx = (np.asarray(obs[:4]) * OBSERVATION_SCALE[:4]).astype(np.float64)
    closure = -vx  # the drogue minus the probe closes: its rate is minus the closure speed
    outside = max(w.min_closure_m_s - closure, closure - w.max_closure_m_s, 0.0)
    return w.potential_offset - (w.radial_per_m * math.hypot(y, z) + w.axial_per_m * abs(x) + w.speed_per_m_s * outside)


@pytest.mark.parametrize("turbulence, seed, policy, outcome", [
    ("moderate", 4, lambda env: PDFeedForward(env), "captured"),
    ("moderate", 1, lambda env: he.StraightLine(env, closure_speed_m_s=2.05), "miss"),
    ("none", 0, lambda env: PDFeedForward(env, closure_speed_m_s=3.0), ("outside window", "failed latch")),
])
def test_the_shaping_telescopes_to_minus_the_start_potential(turbulence, seed, policy, outcome):
    """With discount 1 the shaping terms of an episode that ends in an outcome (a capture, a
    miss, a ram) sum to -Phi(s_0) (Phi = 0 at the end): what the path was does not count, only
    the other terms. Tolerance: Phi(s_0) from the float32 observation, good to 3e-7 m (or m/s)
    times weights of order 1, with the round-off of about 80 additions (1e-12)."""
    env = DockingEnvV1(turbulence=turbulence, reward={"discount": 1.0})
    w = env.reward_weights
    env.last_obs, _ = env.reset(seed=seed)
    phi0 = phi(w, env.last_obs)
    assert phi0 > 0.0  # the offset keeps the start's potential positive
    _, rewards, infos, terminated, _ = fly(env, policy(env))
    assert terminated and infos[-1]["outcome"] in ((outcome,) if isinstance(outcome, str) else outcome)
    shaping = sum(i["reward_terms"]["shaping"] for i in infos)
    assert shaping == pytest.approx(-phi0, abs=1e-5)
    assert sum(rewards) == pytest.approx(sum(sum(i["reward_terms"].values()) for i in infos), abs=1e-12)


def test_a_probe_that_waits_pays_for_it():
    """No command from the start: the probe holds off until the 10 s time-out (a truncation, Phi
    of the last state kept). Each step's shaping is discount Phi(s') - Phi(s) with Phi from the
    observations, Phi > 0 all along (the offset), so the waiting costs (1 - discount) Phi a step:
    the episode's shaping is Phi(s_T) - Phi(s_0) - (1 - discount) sum Phi(s_t), below the
    telescoped Phi(s_T) - Phi(s_0); the time penalty adds -time_penalty_1_s x 10 s."""
    env = DockingEnvV1()
    w = env.reward_weights
    env.last_obs, _ = env.reset(seed=2)
    phis = [phi(w, env.last_obs)]
    observations, _, infos, terminated, truncated = fly(env, lambda o: np.zeros(3, np.float32))
    phis += [phi(w, o) for o in observations]
    assert truncated and not terminated and infos[-1]["outcome"] == "time-out" and len(infos) == 500
    assert min(phis) > 0.0
    # float32 observations: each Phi good to about 1e-6 (weights of order 1 times 3e-7 m), 500 of them
    for info, a, b in zip(infos, phis, phis[1:]):
        assert info["reward_terms"]["shaping"] == pytest.approx(w.discount * b - a, abs=1e-5)
    shaping = sum(i["reward_terms"]["shaping"] for i in infos)
    waiting = (1.0 - w.discount) * sum(phis[1:])
    assert shaping == pytest.approx(phis[-1] - phis[0] - waiting, abs=5e-4)
    assert waiting > 0.0
    # the time penalty: every step's -time_penalty_1_s dt, 10 s in all (round-off of 500 additions)
    assert sum(i["reward_terms"]["time"] for i in infos) == pytest.approx(-w.time_penalty_1_s * 10.0, abs=1e-9)


def test_holding_off_ranks_below_the_baseline_and_below_an_attempt():
    """The finding that changed the reward (docs/gym.md, "A trained baseline (PPO)"): on the
    same seeds, holding off (no command, a time-out) scores below the scripted baseline in the
    undiscounted and in the discounted (0.99) return, and, discounted, below a straight line
    at 2.05 m/s that misses (so an attempt that misses is not worse than waiting)."""
    env = DockingEnvV1(turbulence="moderate")
    gamma = env.reward_weights.discount
    policies = {"baseline": PDFeedForward(env), "hold": lambda o: np.zeros(3, np.float32),
                "line": he.StraightLine(env, closure_speed_m_s=2.05)}
    scores = {}
    for name, policy in policies.items():
        env.last_obs, _ = env.reset(seed=1)
        _, rewards, infos, _, _ = fly(env, policy)
        scores[name] = (sum(rewards), sum(r * gamma**k for k, r in enumerate(rewards)), infos[-1]["outcome"])
    assert [scores[k][2] for k in policies] == ["captured", "time-out", "miss"]
    # measured 2026-12-03 (seed 1): undiscounted -57.3 against -11.5, discounted -12.43 against -6.89 and
    # -12.08 (the miss); the margins 5 and 1 are a tenth of the time penalty's 24.9 between 500 and 85 steps
    # and of the capture's discounted bonus (10 x 0.99^85 = 4.3); the old reward (no offset, no time
    # penalty) fails the first (22.7 > 12.0), the offset alone the last (-8.74 < -6.47)
    assert scores["hold"][0] < scores["baseline"][0] - 5.0 and scores["hold"][1] < scores["baseline"][1] - 1.0
    assert scores["hold"][1] < scores["line"][1]


def test_the_closure_window_changes_the_score_not_the_flight():
    """One flight in still air at the baseline's 2.05 m/s, scored with the default window
    (1.5-2.6 m/s: a capture) and with a window that ends below it (0.5-1.5 m/s: outside): the
    same path, and terminal terms that differ by the bonus, the penalty and the miss term."""
    runs = {}
    for window in ((1.5, 2.6), (0.5, 1.5)):
        env = DockingEnvV1(turbulence="none", reward={"min_closure_m_s": window[0], "max_closure_m_s": window[1]})
        env.last_obs, _ = env.reset(seed=0)
        runs[window] = fly(env, PDFeedForward(env, closure_speed_m_s=2.05))
    a, b = runs[(1.5, 2.6)], runs[(0.5, 1.5)]
    assert np.array_equal(np.array(a[0]), np.array(b[0]))
    last_a, last_b = a[2][-1], b[2][-1]
    assert (last_a["outcome"], last_b["outcome"]) == ("captured", "outside window") and a[3] and b[3]
    assert 1.5 < last_a["closure_speed_m_s"] < 2.6
    # the step's time is the agent's (the load window's steps after it are not): one control step per action
    assert last_a["t_s"] == pytest.approx(len(a[0]) * 0.02, abs=1e-12) and last_a["t_s"] >= last_a["contact_time_s"]
    w = DockingEnvV1().reward_weights
    ta, tb = last_a["reward_terms"], last_b["reward_terms"]
    assert ta["capture"] == w.capture_bonus and tb["capture"] == -w.window_penalty
    assert ta["miss"] == -w.miss_penalty_per_m * last_a["miss_distance_m"] and tb["miss"] == 0.0
    assert ta["load"] == tb["load"] == -last_a["peak_load_n"] / 1000.0 * w.load_penalty_per_kn
    # the peak load after contact: of the order of the probe's spring over the push (5000 N/m, 0.2-0.6 m), kN
    assert 1000.0 < last_a["peak_load_n"] < 5000.0


def test_ramming_scores_below_the_operators_approach():
    """In still air, dead centre: the baseline at 2.05 m/s against the same law at the receiver's
    3 m/s bound (the ramming v0 rewarded): the ram ends outside the window or in a failed latch and
    scores below."""
    scores = {}
    for v in (2.05, 3.0):
        env = DockingEnvV1(turbulence="none")
        env.last_obs, _ = env.reset(seed=0)
        run = fly(env, PDFeedForward(env, closure_speed_m_s=v))
        scores[v] = (sum(run[1]), run[2][-1]["outcome"])
    assert scores[2.05][1] == "captured" and scores[3.0][1] in ("outside window", "failed latch")
    assert scores[3.0][0] < scores[2.05][0] - 10.0


def test_gym_command_flies_v1_as_python_does(capsys):
    """``hosedrogue gym --env v1 --json``: the episodes of :func:`fly` on Docking-v1, the same
    outcomes, returns and peak loads bit for bit; a v1 option without --env v1 is one line, exit 2."""
    import json

    from hosedrogue.cli import main
    from hosedrogue.envs import fly
    from hosedrogue.studies.seeds import run_seed

    argv = ["gym", "--env", "v1", "--episodes", "3", "--seed", "7", "--time-limit", "4.5", "--closure-window",
            "1.0", "2.2", "--randomize", "--turbulence", "light", "--json"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    ranges = {k: v for k, v in he.DEFAULT_RANGES.items() if k != "turbulence_sigma_m_s"}
    e = DockingEnvV1(turbulence="light", time_limit_s=4.5, randomize=ranges,
                     reward={"min_closure_m_s": 1.0, "max_closure_m_s": 2.2})
    ends = fly(e, PDFeedForward(e), [run_seed(7, i) for i in range(3)], seed=7)
    assert doc["closure_window_m_s"] == [1.0, 2.2] and doc["randomized"] is True
    assert [d["outcome"] for d in doc["episodes_detail"]] == [x["outcome"] for x in ends]
    assert [d["return"] for d in doc["episodes_detail"]] == [x["return"] for x in ends]
    assert [d["peak_load_n"] for d in doc["episodes_detail"]] == [x.get("peak_load_n") for x in ends]
    assert all("turbulence_sigma_m_s" not in d["randomized"] for d in doc["episodes_detail"])
    with pytest.raises(SystemExit) as exc:
        raise SystemExit(main(["gym", "--randomize"]))
    assert exc.value.code == 2 and "only with --env v1" in capsys.readouterr().err


@pytest.mark.parametrize("end", [0, 1])
def test_every_quantity_at_either_end_of_its_allowed_range_flies(end):
    """Each randomizable quantity at its lowest and its highest allowed value builds an episode
    that flies half a second toward the drogue without failing."""
    for name, row in he.RANDOMIZABLE.items():
        env = DockingEnvV1(randomize={name: row[2 + end]})
        env.reset(seed=0)
        for _ in range(25):
            _, _, terminated, truncated, info = env.step(np.array([0.68, 0.0, 0.0]))
            assert not (terminated or truncated), (name, info["outcome"])


def test_the_page_shows_the_ranges_of_the_code():
    from pathlib import Path

    from hosedrogue.envs.randomize import ranges_markdown

    page = (Path(__file__).resolve().parents[2] / "docs" / "gym.md").read_text()
    assert ranges_markdown() in page


@pytest.mark.subprocess
def test_a_pickled_environment_continues_bit_for_bit_in_another_process(tmp_path):
    """Pickled mid-episode, loaded by a fresh Python: its next 30 observations are the
    original's, bit for bit (the compiled functions found again by name, the state copied)."""
    import os
    import subprocess
    import sys

    env = DockingEnvV1(randomize=True)
    policy = PDFeedForward(env)
    env.last_obs, _ = env.reset(seed=5)
    fly(env, policy, steps=10)
    (tmp_path / "env.pkl").write_bytes(pickle.dumps((env, env.last_obs)))
    ahead = np.array(fly(env, policy, steps=30)[0])
    code = ("import pickle, sys, numpy as np\n"
            "from hosedrogue.envs import PDFeedForward\n"
            f"env, obs = pickle.loads(open({str(tmp_path / 'env.pkl')!r}, 'rb').read())\n"
            "policy, out = PDFeedForward(env), []\n"
            "for _ in range(30):\n"
            "    obs = env.step(policy(obs))[0]\n"
            "    out.append(obs)\n"
            f"np.save({str(tmp_path / 'out.npy')!r}, np.array(out))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, env=os.environ)
    assert r.returncode == 0, r.stderr[-2000:]
    assert np.array_equal(np.load(tmp_path / "out.npy"), ahead)
