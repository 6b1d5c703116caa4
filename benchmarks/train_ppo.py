"""A trained baseline for hosedrogue/Docking-v1 (docs/gym.md, "A trained baseline"): PPO of
stable-baselines3 trained on Docking-v1 in moderate turbulence with the reward's default
operational window (1.5-2.6 m/s), then flown on fixed seeds beside the scripted baseline
(hosedrogue.envs.PDFeedForward) on the same seeds.

stable-baselines3 and torch are not dependencies of hosedrogue (never imported by the package,
never by its tests). Install them in a virtual environment of their own, with the package:

    python3 -m venv rlvenv
    rlvenv/bin/pip install torch --index-url https://download.pytorch.org/whl/cpu   # the CPU wheel
    rlvenv/bin/pip install stable-baselines3 -e '.[gym]'

Sections (run in order; each reads what the one before wrote in --out):

* ``rate``     - environment steps per second alone and under PPO (a short training), to size the budget;
* ``train``    - PPO with SETTINGS for --timesteps steps; the training episodes' returns and outcomes
                 (stable-baselines3's Monitor, ``monitor.csv``) and, every ``curve_every`` steps, the
                 deterministic policy flown on the curve's seeds (``curve.json``); the model (``ppo.zip``);
* ``evaluate`` - the trained policy (deterministic) and the scripted baseline on the evaluation
                 seeds: capture rate (in the window) with its Wilson 95 % interval, outcomes, median
                 closure speed and median radial miss at the coupler plane, mean return (``evaluation.json``);
* ``returns``  - the undiscounted and discounted returns of three scripted policies (the baseline, no
                 command, the straight line) on the curve's seeds: what a policy that holds off scores;
* ``figure``   - the learning curves as a PNG (--png, default OUT/learning_curve.png), of --out's run
                 and of the runs of --compare: the share of training episodes that reach the coupler
                 plane, the capture rate of the curve's points, the training return.

Run:  rlvenv/bin/python benchmarks/train_ppo.py rate|train|evaluate|returns|figure [--timesteps N] [--out DIR]
One core (torch.set_num_threads(1), NUMBA_NUM_THREADS=1): the figures are for that.
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections import Counter  # noqa: E402
from pathlib import Path  # noqa: E402

import gymnasium  # noqa: E402
import numpy as np  # noqa: E402

import hosedrogue.envs as he  # noqa: E402
from hosedrogue.jsonio import dumps  # noqa: E402
from hosedrogue.studies.statistics import wilson_interval  # noqa: E402

#: The environment trained and evaluated: Docking-v1's defaults (approach-moderate, 10 s episodes
#: of at most 500 steps, the window 1.5-2.6 m/s) in MIL-F-8785C moderate turbulence.
ENV_KWARGS = {"turbulence": "moderate"}
#: Everything PPO is given; stable-baselines3's defaults but gamma, set to the reward's discount so
#: that the potential-based shaping leaves the optimal policy unchanged (docs/gym.md, "Reward").
SETTINGS = {
    "policy": "MlpPolicy",  # two hidden layers of 64 (tanh) for the actor and for the critic
    "n_envs": 1,
    "n_steps": 2048,
    "batch_size": 64,
    "n_epochs": 10,
    "learning_rate": 3e-4,
    "gamma": he.DockingRewardV1().discount,
    "gae_lambda": 0.95,
    "clip_range": 0.2,
    "ent_coef": 0.0,
    "seed": 0,  # PPO's (torch's and its action noise)
    "env_seed": 10_000,  # the training environment's reset(seed=...): episodes not among the seeds below
    "curve_every": 20_480,  # steps between two points of the curve (10 rollouts)
    "curve_seeds": list(range(1000, 1020)),  # 20 episodes, reset(seed=k), per point of the curve
    "eval_seeds": list(range(100)),  # the final evaluation, reset(seed=k)
}
OUT = Path("ppo-docking-v1")


def make_env(reward=None, turbulence=None):
    """Docking-v1 as ENV_KWARGS say; ``reward``: weights of the training reward that differ from
    the default (the curve and the evaluation fly the default reward); ``turbulence``: another
    intensity than the training's (evaluate --turbulence)."""
    kwargs = {**ENV_KWARGS, **({"turbulence": turbulence} if turbulence else {})}
    return gymnasium.make("hosedrogue/Docking-v1", reward=reward, **kwargs)


def flown(env, act, seeds) -> list[dict]:
    """One episode per seed (``reset(seed=k)``): its last info with its return and steps."""
    out = []
    for k in seeds:
        obs, info = env.reset(seed=int(k))
        total, steps = 0.0, 0
        while True:
            obs, reward, terminated, truncated, info = env.step(act(obs))
            total, steps = total + reward, steps + 1
            if terminated or truncated:
                break
        out.append({"seed": int(k), "outcome": info["outcome"], "return": total, "steps": steps,
                    "closure_speed_m_s": info.get("closure_speed_m_s"), "miss_distance_m": info.get("miss_distance_m"),
                    "peak_load_n": info.get("peak_load_n"), "end_distance_m": info["distance_m"]})
    return out


def summary(episodes: list[dict]) -> dict:
    """Capture rate (in the window) with its Wilson 95 % interval, outcomes, medians at the plane."""
    n = len(episodes)
    k = sum(e["outcome"] == "captured" for e in episodes)
    lo, hi = wilson_interval(k, n)
    closures = [e["closure_speed_m_s"] for e in episodes if e["closure_speed_m_s"] is not None
                and np.isfinite(e["closure_speed_m_s"])]
    misses = [e["miss_distance_m"] for e in episodes if e["miss_distance_m"] is not None
              and np.isfinite(e["miss_distance_m"])]
    return {"episodes": n, "captured": k, "capture_rate": k / n, "ci95": [lo, hi],
            "outcomes": dict(Counter(e["outcome"] for e in episodes)),
            "reached_plane": len(closures),
            "median_closure_m_s": float(np.median(closures)) if closures else None,
            "median_miss_m": float(np.median(misses)) if misses else None,
            "mean_return": float(np.mean([e["return"] for e in episodes])),
            "median_end_distance_m": float(np.median([e["end_distance_m"] for e in episodes])),
            "median_steps": float(np.median([e["steps"] for e in episodes]))}


def describe(name: str, s: dict) -> str:
    med = lambda v, f: "-" if v is None else format(v, f)  # noqa: E731
    return (f"  {name:22s} captured {s['captured']}/{s['episodes']} = {s['capture_rate']:.3f} (Wilson 95 % "
            f"{s['ci95'][0]:.3f}-{s['ci95'][1]:.3f}); median closure {med(s['median_closure_m_s'], '.2f')} m/s, "
            f"median miss {med(s['median_miss_m'], '.3f')} m ({s['reached_plane']} at the plane); mean return "
            f"{s['mean_return']:.2f}; probe-drogue distance at the end, median {s['median_end_distance_m']:.2f} m; {dict(sorted(s['outcomes'].items()))}")


def ppo_model(env_seed: int, monitor: Path | None, reward=None):
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.monitor import Monitor
    from stable_baselines3.common.vec_env import DummyVecEnv

    torch.set_num_threads(1)
    s = SETTINGS
    factory = lambda: Monitor(make_env(reward), str(monitor) if monitor else None, info_keywords=("outcome",))  # noqa: E731
    venv = DummyVecEnv([factory] * s["n_envs"])
    venv.seed(env_seed)  # sub-environment i: reset(seed=env_seed + i) at the first reset
    return PPO(s["policy"], venv, n_steps=s["n_steps"], batch_size=s["batch_size"], n_epochs=s["n_epochs"],
               learning_rate=s["learning_rate"], gamma=s["gamma"], gae_lambda=s["gae_lambda"],
               clip_range=s["clip_range"], ent_coef=s["ent_coef"], seed=s["seed"], device="cpu", verbose=0)


def deterministic(model):
    return lambda obs: model.predict(obs, deterministic=True)[0]


def rate(args):
    env = make_env()
    env.reset(seed=0)
    action = np.array([2.05 / 3, 0, 0], dtype=np.float32)
    c, steps = time.process_time(), 2000
    for _ in range(steps):
        if any(env.step(action)[2:4]):
            env.reset()
    print(f"  the environment alone: {steps / (time.process_time() - c):.0f} steps per CPU second")
    model = ppo_model(SETTINGS["env_seed"], None)
    c, w = time.process_time(), time.perf_counter()
    model.learn(total_timesteps=SETTINGS["n_steps"] * 2)
    c, w = time.process_time() - c, time.perf_counter() - w
    n = SETTINGS["n_steps"] * 2 * SETTINGS["n_envs"]
    print(f"  PPO ({n} steps, two rollouts and their updates): {n / c:.0f} steps per CPU second, {n / w:.0f} per "
          f"wall second")


def train(args):
    from stable_baselines3.common.callbacks import BaseCallback

    args.out.mkdir(parents=True, exist_ok=True)
    model = ppo_model(SETTINGS["env_seed"], args.out / "monitor.csv", args.reward)
    curve_env, curve = make_env(), []
    base = summary(flown(curve_env, he.PDFeedForward(curve_env), SETTINGS["curve_seeds"]))
    print(describe("scripted baseline", base), flush=True)

    class Curve(BaseCallback):
        def _on_step(self) -> bool:
            if self.num_timesteps % SETTINGS["curve_every"] == 0:
                point(self.num_timesteps)
            return True

    def point(steps):
        s = summary(flown(curve_env, deterministic(model), SETTINGS["curve_seeds"]))
        curve.append({"timesteps": steps, "cpu_s": time.process_time() - cpu, **s})
        print(describe(f"{steps} steps", s), flush=True)
        model.save(args.out / "ppo.zip")  # the policy of the curve's last point: a run cut short keeps it
        (args.out / "curve.json").write_text(dumps({"settings": SETTINGS, "env": ENV_KWARGS, "train_reward": args.reward,
                                                          "baseline": base,
                                                          "curve": curve}, indent=1))

    cpu = time.process_time()
    point(0)
    model.learn(total_timesteps=args.timesteps, callback=Curve())
    model.save(args.out / "ppo.zip")
    print(f"  {args.timesteps} steps in {time.process_time() - cpu:.0f} CPU s (the curve's episodes included)")


def evaluate(args):
    from stable_baselines3 import PPO

    import torch

    torch.set_num_threads(1)
    model = PPO.load(args.out / "ppo.zip", device="cpu")
    env = make_env(turbulence=args.turbulence)
    rows = {"PPO (deterministic)": flown(env, deterministic(model), SETTINGS["eval_seeds"]),
            "scripted baseline": flown(env, he.PDFeedForward(env), SETTINGS["eval_seeds"])}
    doc = {"settings": SETTINGS, "env": {**ENV_KWARGS, **({"turbulence": args.turbulence} if args.turbulence else {})},
           "summary": {}, "episodes": rows}
    for name, eps in rows.items():
        doc["summary"][name] = summary(eps)
        print(describe(name, doc["summary"][name]))
    both = sum(a["outcome"] == b["outcome"] == "captured" for a, b in zip(*rows.values()))
    print(f"  captured by both on the same seed: {both}")
    (args.out / (f"evaluation-{args.turbulence}.json" if args.turbulence else "evaluation.json")).write_text(
        dumps(doc, indent=1))


def returns(args):
    """Why a policy may learn to hold off: the undiscounted and the discounted (gamma) return of
    three scripted policies on the curve's seeds: the baseline, no command (the probe slows and
    holds off until the time limit) and the straight line at the window's middle."""
    env, gamma = make_env(args.reward), SETTINGS["gamma"]
    policies = {"scripted baseline": he.PDFeedForward(env), "no command (holds off)": lambda o: np.zeros(3, np.float32),
                "straight line, 2.05 m/s": he.StraightLine(env, closure_speed_m_s=2.05)}
    for name, policy in policies.items():
        plain, discounted, outcomes = [], [], Counter()
        for k in SETTINGS["curve_seeds"]:
            obs, info = env.reset(seed=k)
            u = d = 0.0
            g = 1.0
            while True:
                obs, reward, terminated, truncated, info = env.step(policy(obs))
                u, d, g = u + reward, d + g * reward, g * gamma
                if terminated or truncated:
                    break
            plain.append(u), discounted.append(d)
            outcomes[info["outcome"]] += 1
        print(f"  {name:24s} return {np.mean(plain):6.2f}, discounted ({gamma:g}) {np.mean(discounted):5.2f}; "
              f"{dict(outcomes)}")


def figure(args):
    """The learning curves of one run or more (--out, then --compare): per run, the share of
    training episodes that reach the coupler plane, the deterministic policy's capture rate on the
    curve's seeds, and the training return (the run's own reward)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pandas as pd

    window = 50
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4), layout="constrained")
    for k, out in enumerate([args.out, *args.compare]):
        doc = json.loads((out / "curve.json").read_text())
        mon = pd.read_csv(out / "monitor.csv", skiprows=1)
        steps = mon["l"].cumsum()
        label = "default reward" if not doc.get("train_reward") else \
            "trained with " + ", ".join(f"{key} = {v:g}" for key, v in doc["train_reward"].items())
        label = args.labels[k] if k < len(args.labels) else label
        color = f"C{k}"
        axes[0].plot(steps, (mon["outcome"] != "time-out").rolling(window, min_periods=1).mean(), color=color,
                     label=label)
        c = doc["curve"]
        rate_ = np.array([p["capture_rate"] for p in c])
        ci = np.array([p["ci95"] for p in c])
        axes[1].errorbar([p["timesteps"] for p in c], rate_, yerr=[rate_ - ci[:, 0], ci[:, 1] - rate_], color=color,
                         marker="o", ms=3, capsize=2, lw=1, label=label)
        axes[2].plot(steps, mon["r"].rolling(window, min_periods=1).mean(), color=color, label=label)
    axes[1].axhline(doc["baseline"]["capture_rate"], color="k", ls="--", lw=1, label="scripted baseline")
    axes[0].set_ylabel(f"training episodes reaching the plane [-]\n(mean of {window})")
    axes[1].set_ylabel(f"captured in the window [-]\n(deterministic, {len(doc['settings']['curve_seeds'])} seeds)")
    axes[2].set_ylabel(f"training return [-] (mean of {window},\neach run's own reward)")
    for ax in axes:
        ax.set_xlabel("training steps [thousands]")
        ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v / 1000:g}"))
    for ax in axes[:2]:
        ax.set_ylim(-0.03, 1.03)
    axes[0].legend(*axes[1].get_legend_handles_labels(), fontsize=7, loc="center right")  # where no curve runs
    fig.suptitle("PPO (stable-baselines3 defaults, gamma 0.99) on hosedrogue/Docking-v1, moderate turbulence, "
                 "window 1.5-2.6 m/s", fontsize=10)
    png = args.png or args.out / "learning_curve.png"
    fig.savefig(png, dpi=80)
    print(f"  {png}: {Path(png).stat().st_size / 1000:.0f} kB")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("section", choices=("rate", "train", "evaluate", "figure", "returns"))
    p.add_argument("--timesteps", type=int, default=200_000, help="training budget [steps]")
    p.add_argument("--out", type=Path, default=OUT, help="where the run's files go")
    p.add_argument("--png", type=Path, help="the figure's file (figure)")
    p.add_argument("--compare", type=Path, nargs="*", default=[], help="figure: other runs' folders drawn beside --out's")
    p.add_argument("--labels", nargs="*", default=[], help="figure: the runs' names in the legend, --out's first "
                   "(default: the training reward's weights that differ from the default)")
    p.add_argument("--reward", type=json.loads, help="train: reward weights that differ from the default, as a "
                   "JSON object, e.g. '{\"miss_penalty\": 0}' (the curve and the evaluation fly the default)")
    p.add_argument("--turbulence", help="evaluate: fly this turbulence intensity instead of the training's "
                   "(written to evaluation-<intensity>.json)")
    p.add_argument("--seed", type=int, help="train: PPO's seed instead of SETTINGS' 0 (recorded in curve.json)")
    args = p.parse_args(argv)
    if args.seed is not None:
        SETTINGS["seed"] = args.seed
    print(f"{args.section}: {ENV_KWARGS}, {SETTINGS['policy']}, n_steps {SETTINGS['n_steps']}, batch "
          f"{SETTINGS['batch_size']}, learning rate {SETTINGS['learning_rate']:g}, gamma {SETTINGS['gamma']:g}")
    globals()[args.section](args)


if __name__ == "__main__":
    sys.exit(main())
