"""``hosedrogue gym``: fly the docking environment (``hosedrogue/Docking-v0``, or with ``--env v1``
``hosedrogue/Docking-v1``) with a scripted policy and print how its episodes ended (docs/gym.md)."""

from __future__ import annotations

import math
import time
from collections import Counter

from ..errors import ParameterError
from ..jsonio import dumps
from .options import bounded_int, finite_float

NAME = "gym"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="fly the Gymnasium docking environment with a scripted policy: its capture rate",
                       description="Fly EPISODES episodes of the docking environment hosedrogue/Docking-v0 (the "
                                   "receiver's probe flown by a velocity command toward the drogue) with a scripted "
                                   "policy, on the turbulence seeds of a campaign (run i: the seed 'hosedrogue "
                                   "montecarlo --seed SEED' gives its run i), and print the capture rate with its "
                                   "Wilson 95 % interval, the outcomes and the environment's steps per second. "
                                   "Needs Gymnasium (pip install 'hosedrogue[gym]'; docs/gym.md).")
    s.add_argument("scenario", metavar="SCENARIO", nargs="?", default="approach-moderate",
                   help="engagement scenario name or TOML file (default approach-moderate)")
    s.add_argument("--policy", choices=("baseline", "straight"), default="baseline",
                   help="'baseline': PD with the drogue's velocity fed forward; 'straight': the prescribed probe, "
                        "straight ahead at the closure speed (default baseline)")
    s.add_argument("--episodes", metavar="N", type=bounded_int("--episodes", 1, 100_000), default=20,
                   help="episodes to fly [-] (default 20)")
    s.add_argument("--seed", metavar="SEED", type=bounded_int("--seed", 0, 2**63 - 1), default=0,
                   help="campaign seed of the episodes' turbulence seeds [-] (default 0)")
    s.add_argument("--turbulence", choices=("none", "light", "moderate", "severe"),
                   help="turbulence intensity (default the scenario's)")
    s.add_argument("--bow-wave", choices=("on", "off"), help="the receiver's bow wave (default the scenario's)")
    s.add_argument("--reel", choices=("locked", "constant-tension", "response"), help="reel law (default the scenario's)")
    s.add_argument("--drogue-controller", choices=("none", "pid", "lqr"),
                   help="built-in drogue controller (default the scenario's)")
    s.add_argument("--model", metavar="PRESET", help="model preset: 'converged' or 'paper' (default the scenario's)")
    s.add_argument("--time-limit", metavar="S", type=finite_float("--time-limit", 1e-3, 600.0, "s"), default=10.0,
                   help="episode length [s] (default 10; the approach scenarios' 4.5 s shares their campaigns' gusts)")
    s.add_argument("--env", choices=("v0", "v1"), default="v0",
                   help="'v0': hosedrogue/Docking-v0 (the default, unchanged); 'v1': hosedrogue/Docking-v1, scored "
                        "in a closure-speed window with the miss and the probe's load (the baseline then closes at "
                        "the window's middle)")
    s.add_argument("--closure-window", metavar=("LO", "HI"), nargs=2, type=finite_float("--closure-window", 0.0, 10.0,
                                                                                         "m/s"),
                   help="v1: the reward's closure-speed window [m/s] (default 1.5 2.6)")
    s.add_argument("--randomize", action="store_true",
                   help="v1: randomize every episode over the default ranges (docs/gym.md, 'Randomized episodes'); "
                        "with --turbulence, every quantity but the turbulence intensity")
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
        from ..envs import POLICIES, DockingEnv, DockingEnvV1, fly
    except ImportError as exc:
        raise ParameterError(f"hosedrogue gym: {exc}") from None
    from ..studies.seeds import run_seed
    from ..studies.statistics import wilson_interval

    options = dict(scenario=args.scenario, turbulence=args.turbulence,
                   bow_wave=None if args.bow_wave is None else args.bow_wave == "on", reel=args.reel,
                   drogue_controller=args.drogue_controller, model=args.model, time_limit_s=args.time_limit)
    if args.env == "v0":
        if args.closure_window or args.randomize:
            raise ParameterError("--closure-window, --randomize: only with --env v1")
        env = DockingEnv(**options)
    else:
        window = {} if not args.closure_window else dict(zip(("min_closure_m_s", "max_closure_m_s"),
                                                             args.closure_window))
        from ..envs import DEFAULT_RANGES

        ranges = {k: v for k, v in DEFAULT_RANGES.items() if args.turbulence is None or k != "turbulence_sigma_m_s"}
        env = DockingEnvV1(**options, reward=window, randomize=ranges if args.randomize else None)
    policy = POLICIES[args.policy](env)
    seeds = [run_seed(args.seed, i) for i in range(args.episodes)]
    cpu = time.process_time()
    ends = fly(env, policy, seeds, seed=args.seed)  # the seed also decides a randomized episode's draws
    cpu = time.process_time() - cpu
    captured = sum(e["outcome"] == "captured" for e in ends)
    lo, hi = wilson_interval(captured, len(ends))
    steps = sum(e["steps"] for e in ends)
    t = getattr(env, "base_scenario", env.scenario).params.turbulence
    doc = {"scenario": env.scenario.name, "policy": args.policy, "episodes": len(ends), "campaign_seed": args.seed,
           "turbulence_sigma_m_s": list(t.sigma_m_s) if t.enabled else [0.0, 0.0, 0.0],
           "time_limit_s": env.scenario.duration_s, "capture_rate": captured / len(ends), "ci95": [lo, hi],
           "outcomes": dict(Counter(e["outcome"] for e in ends)), "steps": steps,
           "steps_per_cpu_s": steps / cpu if cpu > 0 else None,
           "episodes_detail": [{"turbulence_seed": e["turbulence_seed"], "outcome": e["outcome"],
                                "miss_distance_m": e.get("miss_distance_m"),
                                "closure_speed_m_s": e.get("closure_speed_m_s"), "t_s": e["t_s"],
                                "return": e["return"]} for e in ends]}
    if args.env == "v1":
        doc.update(env="hosedrogue/Docking-v1", mean_return=sum(e["return"] for e in ends) / len(ends),
                   closure_window_m_s=[env.reward_weights.min_closure_m_s, env.reward_weights.max_closure_m_s],
                   randomized=bool(args.randomize))
        for d, e in zip(doc["episodes_detail"], ends):
            d.update(peak_load_n=e.get("peak_load_n"), randomized=e["randomized"])
    if args.json:
        print(dumps(doc))
        return 0
    sigma = doc["turbulence_sigma_m_s"][0]
    print(f"{doc['scenario']}, {args.policy} policy, {len(ends)} episodes (campaign seed {args.seed}), turbulence "
          f"sigma {sigma:.2f} m/s, time limit {doc['time_limit_s']:g} s")
    print(f"  captured {captured} of {len(ends)}: {doc['capture_rate']:.3f} (Wilson 95 % {lo:.3f}-{hi:.3f})")
    print("  outcomes: " + ", ".join(f"{k} {v}" for k, v in sorted(doc["outcomes"].items())))
    if args.env == "v1":
        lo_w, hi_w = doc["closure_window_m_s"]
        closures = sorted(e["closure_speed_m_s"] for e in ends if not math.isnan(e.get("closure_speed_m_s", math.nan)))
        median = f"{closures[len(closures) // 2]:.2f} m/s" if closures else "-"
        print(f"  Docking-v1: mean return {doc['mean_return']:.2f}; closure window {lo_w:g}-{hi_w:g} m/s, median "
              f"closure at the plane {median}{'; randomized episodes' if args.randomize else ''}")
    if doc["steps_per_cpu_s"] is not None:
        print(f"  {steps} environment steps, {doc['steps_per_cpu_s']:.0f} per CPU second")
    return 0
