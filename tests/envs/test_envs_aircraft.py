"""The docking environment flying the receiver as an aircraft (``receiver_model="f16"``; docs/gym.md,
"The receiver as an aircraft"): Gymnasium's checker, the scripted baseline docking it, the same run
as the scenario's, snapshots that continue bit for bit, one-line errors."""

import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

from hosedrogue import load_scenario, run  # noqa: E402
from hosedrogue.engagement.aircraft_receiver import AircraftEngagementStepper  # noqa: E402
from hosedrogue.envs import DockingEnv, DockingEnvV1, PDFeedForward  # noqa: E402
from hosedrogue.errors import ParameterError  # noqa: E402


@pytest.mark.parametrize("kind", [DockingEnv, DockingEnvV1])
def test_the_checker_passes_with_the_aircraft(kind):
    env = kind(receiver_model="f16")
    assert isinstance(env.stepper, AircraftEngagementStepper)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env, skip_render_check=True)
    assert not [w for w in caught if "hosedrogue" in str(w.filename)]


def test_the_baseline_docks_the_aircraft_as_the_scenario_does():
    """The baseline (PD with feed-forward) through the environment with ``receiver_model="f16"`` on
    approach-moderate-docking, and ``pd_docking`` through approach-f16-moderate (seed 2018): one law
    on one aircraft and hose, so the same drogue path up to contact and the same capture. Tolerance
    1e-9 m: the action is the command over the speed bound, one rounding (2e-16 relative) from the
    controller's, through a damped 3 s approach."""
    sc = load_scenario("approach-f16-moderate")
    ref = run(sc)
    env = DockingEnv(scenario="approach-moderate-docking", receiver_model="f16", time_limit_s=sc.duration_s)
    policy = PDFeedForward(env)
    obs, info = env.reset(options={"turbulence_seed": sc.params.turbulence.seed})
    infos = []
    while True:
        obs, _, terminated, truncated, info = env.step(policy(obs))
        infos.append(info)
        if terminated or truncated:
            break
    assert terminated and info["outcome"] == "captured" and ref.outcome["result"] == "captured"
    t = np.array([i["t_s"] for i in infos])
    rows = np.searchsorted(ref.t_s, t - 1e-9)
    assert np.array_equal(ref.t_s[rows], t)
    path = np.array([i["measurement"]["drogue_position_m"] for i in infos])
    before = t < ref.outcome["contact_time_s"]
    assert before.sum() > 100
    assert np.max(np.abs(path[before] - ref.drogue_position_m[rows[before]])) < 1e-9
    assert abs(info["miss_distance_m"] - ref.outcome["miss_distance_m"]) < 1e-9


def test_a_snapshot_holds_the_aircraft():
    """get_state after 10 steps, 15 more, set_state, the same 15 again: the same observations bit for bit
    (the aircraft's state, its inner loop's reference and its clock are in the snapshot)."""
    env = DockingEnvV1(receiver_model="f16")
    env.reset(seed=3)
    act = np.array([0.3, 0.1, -0.1], dtype=np.float32)
    for _ in range(10):
        env.step(act)
    snap = env.get_state()
    a = [env.step(act)[0] for _ in range(15)]
    env.set_state(snap)
    b = [env.step(act)[0] for _ in range(15)]
    assert np.array_equal(np.array(a), np.array(b))


@pytest.mark.parametrize("value, words", [(3, "receiver_model = 3"), ("no-such-model", "receiver.model = 'no-such-model'")])
def test_a_bad_receiver_model_is_one_line(value, words):
    with pytest.raises(ParameterError) as err:
        DockingEnv(receiver_model=value)
    assert words in str(err.value) and "\n" not in str(err.value)
