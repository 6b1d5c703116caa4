"""The docking environment's own vector environment (hosedrogue.envs.vector, docs/gym.md "Many
environments"): every sub-environment gives, step for step and bit for bit, what
gymnasium.make gives on the same seed and actions, in each of Gymnasium's autoreset modes,
through captures and time limits."""

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from gymnasium.vector import AutoresetMode  # noqa: E402

from hosedrogue.envs import DOCKING_V1_ID, PDFeedForward  # noqa: E402
from hosedrogue.envs.vector import DockingVectorEnv  # noqa: E402
from hosedrogue.errors import ParameterError  # noqa: E402

N, SEED, LIMIT = 3, 20, 79  # the baseline captures seeds 20-22 at steps 76-82: some captured, some truncated


def policy_of(vec):
    base = PDFeedForward(vec.envs[0])
    return lambda obs: np.array([base(o) for o in obs])


@pytest.mark.parametrize("mode", ["NextStep", "SameStep"])
def test_every_sub_environment_is_what_make_gives_on_the_same_seed_and_actions(mode):
    vec = gymnasium.make_vec(DOCKING_V1_ID, num_envs=N, max_episode_steps=LIMIT, autoreset_mode=mode)
    assert isinstance(vec, DockingVectorEnv) and vec.metadata["autoreset_mode"] == AutoresetMode(mode)
    singles = [gymnasium.make(DOCKING_V1_ID, max_episode_steps=LIMIT) for _ in range(N)]
    obs, _ = vec.reset(seed=SEED)
    for i, env in enumerate(singles):
        assert np.array_equal(env.reset(seed=SEED + i)[0], obs[i])
    policy, pending, ends, seen = policy_of(vec), [False] * N, 0, set()
    for _ in range(2 * LIMIT + 5):
        actions = policy(obs)
        obs, rewards, terminated, truncated, infos = vec.step(actions)
        for i, env in enumerate(singles):
            if pending[i]:  # NextStep: this step is the reset
                o, info = env.reset()
                assert np.array_equal(o, obs[i]) and rewards[i] == 0.0 and not (terminated[i] or truncated[i])
                pending[i] = False
                continue
            o, r, te, tr, info = env.step(actions[i])
            assert (r, te, tr) == (rewards[i], terminated[i], truncated[i])
            step_info = infos
            if te or tr:
                seen.add("terminated" if te else "truncated")
                ends += 1
                if mode == "SameStep":  # the step's end in final_obs and final_info, the reset's in obs and info
                    assert np.array_equal(o, infos["final_obs"][i])
                    step_info = infos["final_info"]
                    o, reset_info = env.reset()
                    assert infos["turbulence_seed"][i] == reset_info["turbulence_seed"]
                else:
                    pending[i] = True
            assert info["outcome"] == step_info["outcome"][i] and info["t_s"] == step_info["t_s"][i]
            assert np.array_equal(o, obs[i])
    assert ends >= 2 * N and seen == {"terminated", "truncated"}  # every sub-environment ended twice at least


def test_disabled_autoreset_resets_the_masked_ones():
    vec = gymnasium.make_vec(DOCKING_V1_ID, num_envs=2, max_episode_steps=5, autoreset_mode="Disabled")
    obs, _ = vec.reset(seed=0)
    for _ in range(5):
        obs, _, _, truncated, _ = vec.step(np.zeros((2, 3), dtype=np.float32))
    assert truncated.all()
    with pytest.raises(RuntimeError, match="reset_mask"):
        vec.step(np.zeros((2, 3)))
    single = gymnasium.make(DOCKING_V1_ID)
    single.reset(seed=1)
    for _ in range(5):
        single.step(np.zeros(3))
    obs, infos = vec.reset(options={"reset_mask": np.array([False, True])})
    assert list(infos["_outcome"]) == [False, True]
    assert np.array_equal(obs[1], single.reset()[0])  # the generator of seed 1 carried on
    with pytest.raises(ParameterError, match="autoreset_mode"):
        DockingVectorEnv(2, autoreset_mode="sometimes")


def test_the_batched_info_is_gymnasiums():
    """batch_infos builds at once what Gymnasium's VectorEnv._add_info builds one
    sub-environment at a time: the same keys, masks, dtypes and values."""
    from hosedrogue.envs.vector import batch_infos

    vec = DockingVectorEnv(3)
    infos = [{"a": 1.0, "b": {"c": np.arange(3.0), "s": "x"}, "final_obs": np.ones(2)}, None,
             {"a": 2.0, "b": {"c": np.arange(3.0) + 1, "s": "y"}, "d": np.int64(4)}]
    expected = {}
    for i, info in enumerate(infos):
        if info is not None:
            expected = vec._add_info(expected, info, i)
    got = batch_infos(infos)

    def check(a, b):
        assert list(a) == list(b)
        for key in a:
            if isinstance(a[key], dict):
                check(a[key], b[key])
            else:
                assert a[key].dtype == b[key].dtype and a[key].shape == b[key].shape
                assert all(np.array_equal(x, y) if isinstance(x, np.ndarray) else x == y
                           for x, y in zip(a[key], b[key]))

    check(expected, got)
