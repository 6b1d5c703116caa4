"""``hosedrogue gym-task``: fly the station-keeping or the whip-suppression environment
(``hosedrogue/StationKeeping-v0``, ``hosedrogue/WhipSuppression-v0``) with its scripted baseline or
with no action, and print what its episodes gave (docs/gym.md, "More tasks")."""

from __future__ import annotations

import statistics
import time
from collections import Counter

from ..errors import ParameterError
from ..jsonio import dumps
from .options import bounded_int

NAME = "gym-task"
#: The figures printed per task: (key, label, factor, unit).
_FIGURES = {"station": (("rms_displacement_m", "drogue displacement RMS", 1000.0, "mm"),
                        ("peak_displacement_m", "peak", 1000.0, "mm"),
                        ("saturated_fraction", "steps with the force at its bound", 100.0, "%")),
            "whip": (("peak_slack_m", "peak slack", 1.0, "m"), ("peak_exit_tension_n", "peak exit tension", 1e-3, "kN"),
                     ("peak_probe_force_n", "peak probe load", 1e-3, "kN"))}


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="fly the station-keeping or whip-suppression Gymnasium task with a scripted policy",
                       description="Fly EPISODES episodes (reset(seed=SEED + k)) of hosedrogue/StationKeeping-v0 (the "
                                   "actuated drogue holds its balance position in turbulence; 'station') or "
                                   "hosedrogue/WhipSuppression-v0 (the reel takes up the slack after contact; 'whip') "
                                   "with the scripted baseline or no action, and print the mean return and the "
                                   "medians of the task's figures: the drogue's RMS and peak displacement [mm] and "
                                   "the share of steps with the force at its bound [%]; the peak slack [m], exit "
                                   "tension [kN] and probe load [kN]. Needs Gymnasium (pip install "
                                   "'hosedrogue[gym]'; docs/gym.md).")
    s.add_argument("task", choices=("station", "whip"), help="the task")
    s.add_argument("--policy", choices=("baseline", "none"), default="baseline",
                   help="'baseline': the task's scripted policy (station: the paper's PD gains; whip: the take-up "
                        "law of 8 /s per metre of slack); 'none': no force, or the reel held (default baseline)")
    s.add_argument("--episodes", metavar="N", type=bounded_int("--episodes", 1, 100_000), default=20,
                   help="episodes to fly [-] (default 20)")
    s.add_argument("--seed", metavar="SEED", type=bounded_int("--seed", 0, 2**62), default=0,
                   help="episode k is reset(seed=SEED + k) [-] (default 0)")
    s.add_argument("--turbulence", choices=("none", "light", "moderate", "severe"),
                   help="turbulence intensity (default: station the scenario's, moderate; whip light)")
    s.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    s.set_defaults(func=run)


def run(args) -> int:
    """Fly the episodes and print what they gave; exit status 0.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    try:
        from ..envs import STATION_ID, WHIP_ID
        from ..envs.tasks import fly_task, task_policy
        import gymnasium
    except ImportError as exc:
        raise ParameterError(f"hosedrogue gym-task: {exc}") from None
    env_id = {"station": STATION_ID, "whip": WHIP_ID}[args.task]
    env = gymnasium.make(env_id, **({} if args.turbulence is None else {"turbulence": args.turbulence}))
    cpu = time.process_time()
    rows = fly_task(env, task_policy(args.task, env, args.policy), range(args.seed, args.seed + args.episodes))
    cpu = time.process_time() - cpu
    steps = sum(r["steps"] for r in rows)
    medians = {key: statistics.median(r[key] for r in rows) for key, *_ in _FIGURES[args.task]}
    doc = {"env": env_id, "policy": args.policy, "episodes": len(rows), "seed": args.seed,
           "mean_return": sum(r["return"] for r in rows) / len(rows), "medians": medians,
           "outcomes": dict(Counter(r["outcome"] for r in rows)), "steps": steps,
           "steps_per_cpu_s": steps / cpu if cpu > 0 else None, "episodes_detail": rows}
    if args.json:
        print(dumps(doc))
        return 0
    print(f"{env_id}, {args.policy} policy, {len(rows)} episodes (reset seeds {args.seed}-{args.seed + len(rows) - 1})")
    print(f"  mean return {doc['mean_return']:.3f}; outcomes: "
          + ", ".join(f"{k} {v}" for k, v in sorted(doc["outcomes"].items())))
    print("  medians over the episodes: " + "; ".join(f"{label} {medians[key] * factor:.3g} {unit}"
                                                      for key, label, factor, unit in _FIGURES[args.task]))
    if doc["steps_per_cpu_s"] is not None:
        print(f"  {steps} environment steps, {doc['steps_per_cpu_s']:.0f} per CPU second")
    return 0
