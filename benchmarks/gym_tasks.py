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

The figures are hosedrogue.envs.tasks.fly_task's (what ``hosedrogue gym-task`` prints). One core
(NUMBA_NUM_THREADS=1); CPU seconds are the process's own (time.process_time).

Run:  .venv/bin/python benchmarks/gym_tasks.py [station] [whip]
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys  # noqa: E402
import time  # noqa: E402
from collections import Counter  # noqa: E402

import gymnasium  # noqa: E402
import numpy as np  # noqa: E402

import hosedrogue.envs as he  # noqa: E402
from hosedrogue.envs.tasks import fly_task, task_policy  # noqa: E402

EPISODES = 50
FIGURES = {"station": (("rms_displacement_m", "displacement RMS", 1000, "mm"),
                       ("peak_displacement_m", "peak", 1000, "mm"), ("saturated_fraction", "force at its bound", 100, "%")),
           "whip": (("peak_slack_m", "peak slack", 1, "m"), ("peak_exit_tension_n", "exit tension", 1e-3, "kN"),
                    ("peak_probe_force_n", "probe load", 1e-3, "kN"))}


def measure(task, env_id, **kwargs):
    env = gymnasium.make(env_id, **kwargs)
    for name in ("baseline", "none"):
        cpu = time.process_time()
        rows = fly_task(env, task_policy(task, env, name), range(EPISODES))
        cpu = time.process_time() - cpu
        figures = "; ".join(f"{label} {np.median([r[key] for r in rows]) * factor:.3g} {unit}"
                            for key, label, factor, unit in FIGURES[task])
        print(f"  {kwargs.get('turbulence', 'default'):8s} {name:8s}: mean return {np.mean([r['return'] for r in rows]):8.3f}; "
              f"medians: {figures}; {dict(Counter(r['outcome'] for r in rows))}; "
              f"{sum(r['steps'] for r in rows) / cpu:,.0f} steps per CPU s")


def station():
    for level in ("moderate", "severe"):
        measure("station", he.STATION_ID, turbulence=level)


def whip():
    measure("whip", he.WHIP_ID)


SECTIONS = ("station", "whip")

if __name__ == "__main__":
    for section in sys.argv[1:] or SECTIONS:
        print(f"{section}:")
        globals()[section]()
