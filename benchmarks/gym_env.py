"""The Gymnasium docking environment (hosedrogue/Docking-v0, docs/gym.md), measured and printed next
to its targets (never asserted).

Sections (all by default, or name some on the command line):

* ``speed`` - environment steps per CPU second on one core at 20 links and a 0.02 s control step
  (the default environment: approach-moderate, converged preset, RK4 at 5 ms, moderate
  turbulence, bow wave, responsive reel; the baseline policy computed in Python every step;
  resets included; target >= 5,000, the Air Force Arcade anchor 140), the environment alone and
  through gymnasium.make's wrappers, and the share of a step spent in compiled code;
* ``vector`` - gymnasium.make_vec: 8 environments in one process ("sync", one core) and 2 in two
  worker processes ("async", two cores), steps of all environments per second;
* ``baseline`` - the scripted PD-with-feed-forward baseline (hosedrogue.envs.PDFeedForward) and
  the straight-line policy (hosedrogue.envs.StraightLine), 200 episodes each per turbulence level
  (light, moderate, severe) on the campaigns' turbulence seeds (run_seed(0, i)) with the
  scenarios' 4.5 s: capture rate with its Wilson 95 % interval and the outcomes;
* ``severe`` - why the baseline misses in severe turbulence: the drogue's peak lateral and
  vertical speed against the receiver's 1 m/s bound, and how often the command exceeds it (50
  episodes);
* ``campaigns`` - the straight-line probe (approach-LEVEL) and the pilot model (the docking grid's
  LEVEL-pilot-bow-on cells) as 200-run campaigns (campaign seed 0, the same turbulence seeds) on 2
  Dask workers, and approach-moderate-docking (the baseline's law as a user's controller); with
  ``baseline`` run first, the environment's episodes against the campaigns' rows seed by seed
  (the straight-line policy against approach-LEVEL, the baseline against approach-moderate-docking).

Run:  .venv/bin/python benchmarks/gym_env.py [speed] [vector] [baseline] [severe] [campaigns]
(one core per process: NUMBA_NUM_THREADS=1 is set here). CPU seconds are the process's own
(time.process_time), the fairest figure on a shared machine; wall seconds are printed too.
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from collections import Counter  # noqa: E402
from pathlib import Path  # noqa: E402

import gymnasium  # noqa: E402
import numpy as np  # noqa: E402

import hosedrogue.envs as he  # noqa: E402
from hosedrogue.model.engagement import steps as ES  # noqa: E402
from hosedrogue.studies.seeds import run_seed  # noqa: E402
from hosedrogue.studies.statistics import wilson_interval  # noqa: E402

LEVELS = ("light", "moderate", "severe")
RUNS = 200
CAMPAIGN_SEED = 0
#: The shipped approach scenarios' duration [s]: episodes of that length share the campaigns' gust records.
APPROACH_S = 4.5


def episodes(env, policy, count, seeds=None):
    """Fly ``count`` episodes; (steps, outcomes, final infos)."""
    steps, infos = 0, []
    for k in range(count):
        options = None if seeds is None else {"turbulence_seed": seeds[k]}
        obs, info = env.reset(seed=k if seeds is None else None, options=options)
        while True:
            obs, _, terminated, truncated, info = env.step(policy(obs))
            steps += 1
            if terminated or truncated:
                break
        infos.append(info)
    return steps, infos


def speed():
    for name, env in (("DockingEnv", he.DockingEnv()), ("gymnasium.make", gymnasium.make(he.DOCKING_ID))):
        policy = he.PDFeedForward(env)
        episodes(env, policy, 2)  # compiled code loaded
        best = (0.0, 0.0, 0)
        for _ in range(3):
            w, c = time.perf_counter(), time.process_time()
            steps, _ = episodes(env, policy, 40)
            w, c = time.perf_counter() - w, time.process_time() - c
            best = max(best, (steps / c, steps / w, steps))
        print(f"  {name:15s} {best[0]:7.0f} steps per CPU s ({best[1]:7.0f} per wall s; {best[2]} steps, 40 resets; "
              f"target >= 5000, Air Force Arcade Refueling-v0: 140)")
    env = he.DockingEnv()
    policy = he.PDFeedForward(env)
    share = compiled_share(episodes, env, policy, 40)
    print(f"  the compiled steps and measurement are {share * 100:.0f} % of a step's CPU time: one compiled "
          f"call for many environments could save at most the other {100 - share * 100:.0f} %")


def compiled_share(run, *args):
    """The share of ``run(*args)``'s CPU time spent in the compiled functions of a control step
    (``model.engagement.steps.eng_advance``, itself Python: the compiled steps, the raw
    measurement and its delivery)."""
    names = ("steps_kernel", "raw_kernel", "deliver")
    original, spent = {k: getattr(ES, k) for k in names}, [0.0]

    def timed(function):
        def call(*a):
            t = time.process_time()
            out = function(*a)
            spent[0] += time.process_time() - t
            return out
        return call

    ES.steps_kernel = lambda ep: timed(original["steps_kernel"](ep))
    ES.raw_kernel = lambda *a: timed(original["raw_kernel"](*a))
    ES.deliver = timed(original["deliver"])
    try:
        c = time.process_time()
        run(*args)
        c = time.process_time() - c
    finally:
        for k, v in original.items():
            setattr(ES, k, v)
    return spent[0] / c


def vector():
    for mode, count in (("sync", 8), ("async", 2)):
        vec = gymnasium.make_vec(he.DOCKING_ID, num_envs=count, vectorization_mode=mode)
        policy = he.PDFeedForward(vec.envs[0] if mode == "sync" else he.DockingEnv())
        obs, _ = vec.reset(seed=0)
        for _ in range(50):
            obs, *_ = vec.step(np.array([policy(o) for o in obs]))
        w, c = time.perf_counter(), time.process_time()
        calls = 1000
        for _ in range(calls):
            obs, *_ = vec.step(np.array([policy(o) for o in obs]))
        w, c = time.perf_counter() - w, time.process_time() - c
        vec.close()
        what = f"{count / c * calls:7.0f} per CPU s of this process" if mode == "sync" else \
            f"(this process: {c:.1f} CPU s)"
        print(f"  make_vec {mode:5s} x {count}: {count * calls / w:7.0f} environment steps per wall s {what}; "
              f"{calls} vector steps, autoreset")


def baseline():
    seeds = [run_seed(CAMPAIGN_SEED, i) for i in range(RUNS)]
    out = {}
    for level in LEVELS:
        env = he.DockingEnv(turbulence=level, time_limit_s=APPROACH_S)
        for name, policy in (("PD + feed-forward", he.PDFeedForward(env)), ("straight line", he.StraightLine(env))):
            t = time.process_time()
            steps, infos = episodes(env, policy, RUNS, seeds)
            t = time.process_time() - t
            k = sum(i["outcome"] == "captured" for i in infos)
            lo, hi = wilson_interval(k, RUNS)
            counts = Counter(i["outcome"] for i in infos)
            misses = [i["miss_distance_m"] for i in infos if i["miss_distance_m"] is not None]
            print(f"  {level:8s} {name:17s}: captured {k / RUNS:.3f} (Wilson 95 % {lo:.3f}-{hi:.3f}) of {RUNS}; "
                  f"{dict(counts)}; miss median {np.median(misses):.3f} m; {steps} steps in {t:.1f} CPU s")
            out[level, name] = infos
    return out


def campaigns(baseline_infos=None):
    from hosedrogue.studies import executor
    from hosedrogue.studies.campaign import run_campaign
    from hosedrogue.studies.docking_grid import CellSpec, cell_scenario

    scratch = tempfile.TemporaryDirectory(prefix="hosedrogue-gym-")
    root = Path(scratch.name)
    cluster, client = executor.local_cluster(2)
    rows = {}
    try:
        cases = [(f"approach-{lv}", f"approach-{lv}") for lv in LEVELS]
        cases += [(f"{lv}-pilot", cell_scenario(CellSpec(lv, "none", True, pilot=True))) for lv in LEVELS]
        cases.append(("approach-moderate-docking", "approach-moderate-docking"))
        for name, scenario in cases:
            t = time.perf_counter()
            summary = run_campaign(scenario, RUNS, root / name, client=client, seed=CAMPAIGN_SEED, progress=False)
            cap = summary.capture
            rows[name] = summary.runs.sort_values("run")
            print(f"  {name:26s} captured {cap['rate']:.3f} (Wilson 95 % {cap['ci95'][0]:.3f}-{cap['ci95'][1]:.3f}) "
                  f"of {cap['runs']}, {time.perf_counter() - t:.0f} s wall")
    finally:
        client.close()
        cluster.close()
        scratch.cleanup()
    if baseline_infos is not None:
        pairs = [(("moderate", "PD + feed-forward"), "approach-moderate-docking")]
        pairs += [((lv, "straight line"), f"approach-{lv}") for lv in LEVELS]
        for key, name in pairs:
            rows_ = rows[name]
            infos = baseline_infos[key]
            same = sum({"time-out": "no contact"}.get(i["outcome"], i["outcome"]) == r
                       for i, r in zip(infos, rows_["result"]))
            misses = np.array([np.nan if i["miss_distance_m"] is None else i["miss_distance_m"] for i in infos])
            diff = np.nanmax(np.abs(misses - rows_["miss_distance_m"].to_numpy(dtype=float)))
            print(f"  the environment's {key[0]} {key[1]} episodes against {name}'s runs, seed by seed: the same "
                  f"outcome in {same} of {RUNS}, miss distances within {diff:.1e} m")


def severe(count=50):
    """Why the baseline misses in severe turbulence: the drogue's lateral and vertical speed
    against the receiver's 1 m/s bound, and how often the baseline's command exceeds it."""
    env = he.DockingEnv(turbulence="severe", time_limit_s=APPROACH_S)
    policy = he.PDFeedForward(env)
    rows = []
    for i in range(count):
        obs, info = env.reset(options={"turbulence_seed": run_seed(CAMPAIGN_SEED, i)})
        vmax, saturated, steps = 0.0, 0, 0
        while True:
            vmax = max(vmax, float(np.max(np.abs(obs[10:12]))))
            saturated += bool(np.any(np.abs(policy.command(obs)[1:]) > env.max_speed_m_s[1:]))
            steps += 1
            obs, _, terminated, truncated, info = env.step(policy(obs))
            if terminated or truncated:
                break
        rows.append((info["outcome"] == "captured", vmax, saturated / steps))
    for captured in (True, False):
        a = np.array([r[1:] for r in rows if r[0] == captured])
        print(f"  severe, {'captured' if captured else 'not captured':12s} ({len(a)} of {count}): the drogue's peak "
              f"lateral/vertical speed median {np.median(a[:, 0]):.2f} m/s (the receiver's bound 1 m/s); the "
              f"baseline's command beyond the bound in a median {np.median(a[:, 1]) * 100:.0f} % of the steps")


SECTIONS = ("speed", "vector", "baseline", "severe", "campaigns")

if __name__ == "__main__":
    chosen = sys.argv[1:] or list(SECTIONS)
    found = None
    for name in chosen:
        print(f"{name}:")
        if name == "baseline":
            found = baseline()
        elif name == "campaigns":
            campaigns(found)
        else:
            globals()[name]()
