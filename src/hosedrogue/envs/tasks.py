"""The station-keeping and whip-suppression tasks flown by a policy, episode by episode, with
the figures each task is judged by (docs/gym.md, "More tasks"; the command ``hosedrogue
gym-task``, benchmarks/gym_tasks.py):

* station keeping: the return, the drogue's RMS and peak lateral-vertical displacement [m] and
  the share of steps with the force at its bound;
* whip suppression: the return, the peak slack [m], exit tension [N] and probe load [N] after contact.
"""

from __future__ import annotations

import math

import numpy as np

from .station import StationKeepingEnv, StationPD
from .whip import SlackFeedback, WhipSuppressionEnv

#: The tasks by name: (environment class, scripted baseline, the action of doing nothing).
TASKS = {"station": (StationKeepingEnv, StationPD, np.zeros(2)), "whip": (WhipSuppressionEnv, SlackFeedback, np.zeros(1))}


def task_policy(task: str, env, name: str):
    """A task's scripted policy by name: "baseline" or "none" (the zero action: no force, the reel held).

    Parameters
    ----------
    task : str
        "station" or "whip".
    env : gymnasium.Env
        The task's environment.
    name : str
        "baseline" or "none".

    Returns
    -------
    callable
        Observation -> action.
    """
    _, baseline, idle = TASKS[task]
    return baseline(env) if name == "baseline" else (lambda obs: idle.copy())


def fly_task(env, policy, seeds) -> list[dict]:
    """One episode per seed (``reset(seed=k)``) and its figures.

    Parameters
    ----------
    env : gymnasium.Env
        A station-keeping or whip-suppression environment.
    policy : callable
        Observation -> action.
    seeds : sequence of int
        The seeds of ``reset``.

    Returns
    -------
    list of dict
        Per episode: ``seed``, ``turbulence_seed``, ``outcome``, ``steps``, ``return`` and the task's
        figures (station: ``rms_displacement_m``, ``peak_displacement_m``, ``saturated_fraction``;
        whip: ``peak_slack_m``, ``peak_exit_tension_n``, ``peak_probe_force_n``; over the valid states).
    """
    station = isinstance(env.unwrapped, StationKeepingEnv)
    out = []
    for k in seeds:
        obs, info = env.reset(seed=int(k))
        infos, total = [], 0.0
        while True:
            obs, reward, terminated, truncated, info = env.step(policy(obs))
            infos.append(info)
            total += reward
            if terminated or truncated:
                break
        row = {"seed": int(k), "turbulence_seed": info["turbulence_seed"], "outcome": info["outcome"],
               "steps": len(infos), "return": total}
        row.update(_station(env.unwrapped, infos) if station else _whip(infos))
        out.append(row)
    return out


def _station(env, infos) -> dict:
    r = np.array([math.hypot(*i["displacement_m"]) for i in infos])
    bound = env.max_force_n
    return {"rms_displacement_m": float(np.sqrt(np.nanmean(r * r))), "peak_displacement_m": float(np.nanmax(r)),
            "saturated_fraction": float(np.mean([np.any(np.abs(i["force_n"]) >= bound) for i in infos]))}


def _whip(infos) -> dict:
    """The peaks over the episode's valid states (a failed state's numbers are not finite)."""
    return {f"peak_{key}": float(np.nanmax([i[key] for i in infos]))
            for key in ("slack_m", "exit_tension_n", "probe_force_n")}
