"""hosedrogue/StationKeeping-v0 and hosedrogue/WhipSuppression-v0 (docs/gym.md, "More tasks"),
their scripted baselines against doing nothing, measured and printed (never asserted):

* ``station`` - StationKeeping-v0 in moderate and severe turbulence (MIL-F-8785C at 8000 m), 50
  episodes each (reset(seed=k), k = 0..49): the baseline (StationPD, the paper's PD gains, 100 N
  per axis) and no force: mean return, the drogue's RMS and peak lateral-vertical displacement
  (median over episodes), the share of steps with the force at its bound, steps per CPU second;
* ``whip`` - WhipSuppression-v0 (engage-response's engagement, light turbulence), 50 episodes:
  the baseline (SlackFeedback, 8 /s) and the reel held (a zero command): mean return, median
  peak slack, peak exit tension and peak probe load over the 4 s after contact, steps per CPU
  second (the run to contact included: a reset flies it).

One core (NUMBA_NUM_THREADS=1); CPU seconds are the process's own (time.process_time).

Run:  .venv/bin/python benchmarks/gym_tasks.py [station] [whip]
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

EPISODES = 50


def episodes(env, policy, count=EPISODES):
    """Per episode (reset(seed=k)): return, steps and the infos; the CPU seconds of all."""
    out, cpu = [], time.process_time()
    for k in range(count):
        obs, info = env.reset(seed=k)
        infos, total = [info], 0.0
        while True:
            obs, reward, terminated, truncated, info = env.step(policy(obs))
            infos.append(info)
            total += reward
            if terminated or truncated:
                break
        out.append((total, len(infos) - 1, infos))
    return out, time.process_time() - cpu


def station():
    for level in ("moderate", "severe"):
        env = gymnasium.make(he.STATION_ID, turbulence=level)
        for name, policy in (("StationPD", he.StationPD(env)), ("no force", lambda o: np.zeros(2))):
            eps, cpu = episodes(env, policy)
            rms, peak, sat = [], [], []
            for _, _, infos in eps:
                d = np.array([i["displacement_m"] for i in infos[1:]])
                r = np.sqrt(np.sum(d * d, axis=1))
                rms.append(np.sqrt(np.mean(r * r)))
                peak.append(r.max())
                sat.append(np.mean([np.any(np.abs(i["force_n"]) >= env.unwrapped.max_force_n) for i in infos[1:]]))
            steps = sum(e[1] for e in eps)
            outcomes = {o: sum(e[2][-1]["outcome"] == o for e in eps) for o in he.station.STATION_OUTCOMES}
            print(f"  {level:8s} {name:10s}: mean return {np.mean([e[0] for e in eps]):8.3f}; displacement RMS "
                  f"median {np.median(rms) * 1000:7.1f} mm, peak median {np.median(peak) * 1000:7.1f} mm; force at "
                  f"its bound in {np.mean(sat) * 100:4.1f} % of the steps; {outcomes}; {steps / cpu:,.0f} steps per "
                  f"CPU s")


def whip():
    env = gymnasium.make(he.WHIP_ID)
    for name, policy in (("SlackFeedback", he.SlackFeedback(env)), ("reel held", lambda o: np.zeros(1))):
        eps, cpu = episodes(env, policy)
        slack = [max(i["slack_m"] for i in infos) for _, _, infos in eps]
        tension = [max(i["exit_tension_n"] for i in infos) for _, _, infos in eps]
        load = [max(i["probe_force_n"] for i in infos) for _, _, infos in eps]
        steps = sum(e[1] for e in eps)
        outcomes = {o: sum(e[2][-1]["outcome"] == o for e in eps) for o in he.whip.WHIP_OUTCOMES}
        print(f"  {name:13s}: mean return {np.mean([e[0] for e in eps]):8.3f}; median peak slack "
              f"{np.median(slack):.3f} m, exit tension {np.median(tension) / 1000:.2f} kN, probe load "
              f"{np.median(load) / 1000:.2f} kN; {outcomes}; {steps / cpu:,.0f} steps per CPU s (resets included)")


SECTIONS = ("station", "whip")

if __name__ == "__main__":
    for section in sys.argv[1:] or SECTIONS:
        print(f"{section}:")
        globals()[section]()
