"""hosedrogue/Docking-v1 measured and printed (never asserted; docs/gym.md "Many environments"):

* ``throughput`` - environment steps per CPU second and per wall second of one environment
  (gymnasium.make, its TimeLimit included) and of gymnasium.make_vec at 8 and 64
  sub-environments (the spec's vector_entry_point), the ratio of each to the single one
  (target: 20 at 64), and the share of a step spent in the compiled control step (what one
  compiled call for the N episodes could not shorten);
* ``resets`` - what a reset costs: the same scenario, a new turbulence intensity (a new gust
  record), a new hose (length and mass: a new balance position), every quantity of the default
  randomization.

The actions are the same fixed command for every step (0.68 forward: 2.05 m/s, the middle of
the closure window), so that the figures are the environment's and not a policy's; episodes end
at the capture test and reset (the vector's autoreset). One core per process
(NUMBA_NUM_THREADS=1); CPU seconds are the process's own (time.process_time).

Run:  .venv/bin/python benchmarks/gym_vector.py [throughput] [resets]
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys  # noqa: E402
import time  # noqa: E402

import gymnasium  # noqa: E402
import numpy as np  # noqa: E402

import hosedrogue.envs as he  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gym_env import compiled_share  # noqa: E402  (the same measurement as gym_env.py's speed section)

ACTION = np.array([2.05 / 3.0, 0.0, 0.0], dtype=np.float32)
STEPS = 6400  # environment steps per measurement (about 80 episodes; 100 steps of 64)


def single(env, steps=STEPS):
    for k in range(steps):
        _, _, terminated, truncated, _ = env.step(ACTION)
        if terminated or truncated:
            env.reset()


def vector(vec, steps=STEPS):
    actions = np.tile(ACTION, (vec.num_envs, 1))
    for _ in range(steps // vec.num_envs):
        vec.step(actions)


def measure(fn, env):
    """Best of three, the environment made and reset before: (steps per CPU s, steps per wall s)."""
    best = (0.0, 0.0)
    for _ in range(3):
        w, c = time.perf_counter(), time.process_time()
        fn(env)
        w, c = time.perf_counter() - w, time.process_time() - c
        best = max(best, (STEPS / c, STEPS / w))
    return best


def throughput():
    env = gymnasium.make(he.DOCKING_V1_ID)
    env.reset(seed=0)
    single(env, 200)  # compiled code loaded
    one = measure(single, env)
    print(f"  gymnasium.make                  {one[0]:7.0f} steps per CPU s ({one[1]:7.0f} per wall s)")
    vecs = {}
    for n in (8, 64):
        vecs[n] = vec = gymnasium.make_vec(he.DOCKING_V1_ID, num_envs=n)
        vec.reset(seed=0)
        v = measure(vector, vec)
        print(f"  make_vec num_envs={n:<3d}           {v[0]:7.0f} steps per CPU s ({v[1]:7.0f} per wall s): "
              f"{v[0] / one[0]:.2f} x the single environment per CPU s, {v[1] / one[1]:.2f} x per wall s "
              f"(target 20 at 64)")
    share = compiled_share(vector, vecs[64])
    print(f"  the compiled control step (eng_advance) is {share * 100:.0f} % of make_vec(64)'s CPU time: one compiled "
          f"call for the 64 episodes could at most make it {1 / share:.2f} x faster on one core "
          f"({2 / share:.2f} x on two)")


def resets(count=30):
    cases = {"the same scenario": None, "a new turbulence intensity": {"turbulence_sigma_m_s": (0.5, 3.0)},
             "a new hose (length and mass)": {"hose_length_m": (14.0, 18.0), "hose_mass_kg_m": (3.5, 5.5)},
             "the default randomization (13 quantities)": True}
    for name, randomize in cases.items():
        env = he.DockingEnvV1(randomize=randomize)
        env.reset(seed=0)
        c = time.process_time()
        for _ in range(count):
            env.reset()
        c = (time.process_time() - c) / count
        print(f"  reset, {name:42s}: {c * 1000:6.1f} ms CPU (an episode of 80 steps at 5000 steps/s: 16 ms)")


SECTIONS = ("throughput", "resets")

if __name__ == "__main__":
    for name in sys.argv[1:] or SECTIONS:
        print(f"{name}:")
        globals()[name]()
