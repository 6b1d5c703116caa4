"""Report section "Docking environment": the Gymnasium environment ``hosedrogue/Docking-v0``
(docs/gym.md) flown by its scripted baseline (PD with feed-forward) and by the straight-line
policy on the docking campaigns' turbulence seeds (run i: ``run_seed(CAMPAIGN_SEED, i)``, the
approach scenarios' 4.5 s), beside the docking section's straight-line probe and pilot model
campaigns of the same seeds, and one episode of the baseline as the environment draws it.

Without Gymnasium (an optional dependency, ``pip install 'hosedrogue[gym]'``) the section says
so and computes nothing.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..studies.docking_grid import CAMPAIGN_SEED, LEVELS, cell_name
from .markup import figure_html, html_table

if TYPE_CHECKING:
    from .docking import DockingSectionResult
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["build", "EPISODE_S", "POLICIES"]

#: Episode length [s]: the shipped approach scenarios' (a gust record depends on its length, so
#: the episodes meet the campaigns' gusts).
EPISODE_S = 4.5
#: The policies flown, by the names of :data:`hosedrogue.envs.POLICIES`, with their page names.
POLICIES = {"baseline": "PD + feed-forward (the environment)", "straight": "straight line (the environment)"}
#: The level and run of the episode drawn (the docking section's approach seen from behind is run 0 too).
DRAWN_LEVEL, DRAWN_RUN = "moderate", 0
TABLE_CSV, EPISODE_CSV, FIGURE_PNG = "docking_env.csv", "docking_env_episode.csv", "fig_docking_env.png"


def _fly(runs: int) -> list[dict]:
    """One row per level x policy: the capture rate with its Wilson interval and the outcomes."""
    from ..envs import POLICIES as CLASSES, DockingEnv, fly
    from ..studies.seeds import run_seed
    from ..studies.statistics import wilson_interval

    seeds = [run_seed(CAMPAIGN_SEED, i) for i in range(runs)]
    rows = []
    for level in LEVELS:
        env = DockingEnv(turbulence=level, time_limit_s=EPISODE_S)
        for policy in POLICIES:
            ends = fly(env, CLASSES[policy](env), seeds)
            k = sum(e["outcome"] == "captured" for e in ends)
            lo, hi = wilson_interval(k, runs)
            misses = [e["miss_distance_m"] for e in ends if e["miss_distance_m"] is not None]
            outcomes = {o: sum(e["outcome"] == o for e in ends) for o in sorted({e["outcome"] for e in ends})}
            rows.append({"level": level, "policy": policy, "episodes": runs, "captured": k, "rate": k / runs,
                         "ci95_lo": lo, "ci95_hi": hi,
                         "outcomes": ", ".join(f"{o} {n}" for o, n in outcomes.items()),
                         "median_miss_m": float(np.median(misses)) if misses else float("nan")})
    return rows


def _episode():
    """The drawn episode: its time series and the pictures at the start and at the end."""
    from ..envs import DockingEnv, PDFeedForward
    from ..studies.seeds import run_seed

    env = DockingEnv(render_mode="rgb_array", turbulence=DRAWN_LEVEL, time_limit_s=EPISODE_S)
    policy = PDFeedForward(env)
    obs, info = env.reset(options={"turbulence_seed": run_seed(CAMPAIGN_SEED, DRAWN_RUN)})
    frames, series = [env.render()], []
    while True:
        m = info["measurement"]
        series.append((info["t_s"], *m["probe_position_m"], *m["drogue_position_m"], *info["command_m_s"]))
        obs, _, terminated, truncated, info = env.step(policy(obs))
        if terminated or truncated:
            break
    frames.append(env.render())
    return np.array(series), frames, info


def _figure(frames):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 8.0))
    for k, (frame, when) in enumerate(zip(frames, ("the start", "the capture test"))):
        ax = fig.add_subplot(2, 1, k + 1)
        ax.imshow(frame)
        ax.set_axis_off()
        ax.set_title(f"render() at {when}", fontsize=10)
    fig.tight_layout()
    return fig


def _campaign_cell(docking, level: str, pilot: bool) -> str:
    block = docking.capture.get(cell_name(level, "none", True, pilot=pilot)) if docking is not None else None
    if not block:
        return "-"
    return f"{block['rate']:.3f} ({block['ci95'][0]:.3f}-{block['ci95'][1]:.3f})"


def _html(rows, docking, info, runs: int, fast: bool) -> str:
    by = {(r["level"], r["policy"]): r for r in rows}
    body = []
    for level in LEVELS:
        cells = [f"{by[level, p]['rate']:.3f} ({by[level, p]['ci95_lo']:.3f}-{by[level, p]['ci95_hi']:.3f}); "
                 f"{by[level, p]['outcomes']}" for p in POLICIES]
        body.append((level, *cells, _campaign_cell(docking, level, False), _campaign_cell(docking, level, True)))
    table = html_table(["turbulence", *POLICIES.values(), "straight-line probe (campaign)", "pilot model (campaign)"],
                       body, table_id="table-docking-env")
    b, s = by["moderate", "baseline"], by["moderate", "straight"]
    return (
        '<section id="docking-env"><h2>Docking environment</h2>'
        "<p>The Gymnasium environment <code>hosedrogue/Docking-v0</code> (docs/gym.md) lets an agent fly the "
        "receiver's probe by a bounded velocity command on the engagement's own loop. Its scripted baseline, PD "
        "control of the measured drogue-minus-probe offset with the drogue's velocity fed forward, and the "
        f"straight-line policy each fly {runs} episodes per turbulence level{' (fast version)' if fast else ''} "
        f"on the docking campaigns' turbulence seeds (campaign seed {CAMPAIGN_SEED}, {EPISODE_S:g} s, bow wave on, "
        "no drogue controller). The straight line flown through the environment is the campaigns' prescribed "
        "probe, so its column repeats the docking section's (docs/gym.md checks it seed by seed). In moderate "
        f"turbulence the baseline captures {b['rate']:.3f} ({b['ci95_lo']:.3f}-{b['ci95_hi']:.3f}) against the "
        f"straight line's {s['rate']:.3f} ({s['ci95_lo']:.3f}-{s['ci95_hi']:.3f}); capture rate with the Wilson "
        "95 % interval and the outcomes:</p>"
        + table
        + figure_html("fig-docking-env", FIGURE_PNG, "One episode of the baseline",
                      f"The environment's picture (render_mode=\"rgb_array\") at the start and at the capture test of "
                      f"the baseline's episode on run {DRAWN_RUN}'s seed in {DRAWN_LEVEL} turbulence: "
                      f"{info['outcome']}, radial miss {info['miss_distance_m']:.3f} m at {info['t_s']:.2f} s. Left "
                      "of each: the drogue, its capture circle and the probe tip seen from behind; right: the hose "
                      "from the tanker's exit and the probe from the side.", (EPISODE_CSV,))
        + "</section>")


def build(out: ReportFolder, settings: ReportSettings, *, docking: DockingSectionResult | None = None) -> None:
    """Fly the environment's policies, draw one episode, write the section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        ``docking_runs``: episodes per level and policy (the campaigns' runs per cell).
    docking : hosedrogue.report.docking.DockingSectionResult, optional
        The docking section's campaigns (the straight-line probe's and the pilot's columns).

    Returns
    -------
    None
    """
    import pandas as pd

    try:
        import gymnasium  # noqa: F401
    except ImportError:
        out.section("docking-env", "environment", '<section id="docking-env"><h2>Docking environment</h2><p>'
                    "Not built: the Gymnasium docking environment needs Gymnasium, "
                    "<code>pip install 'hosedrogue[gym]'</code> (docs/gym.md).</p></section>")
        out.record("docking_env", {"built": False})
        return None
    runs = settings.docking_runs
    rows = _fly(runs)
    out.csv(pd.DataFrame(rows), TABLE_CSV)
    series, frames, info = _episode()
    out.csv(pd.DataFrame(series, columns=["t_s", "probe_x_m", "probe_y_m", "probe_z_m", "drogue_x_m", "drogue_y_m",
                                          "drogue_z_m", "command_vx_m_s", "command_vy_m_s", "command_vz_m_s"]),
            EPISODE_CSV)
    out.figure(_figure(frames), FIGURE_PNG)
    out.section("docking-env", "environment", _html(rows, docking, info, runs, settings.fast))
    b = {r["level"]: r for r in rows if r["policy"] == "baseline"}
    out.summarize("Docking environment: the scripted baseline (PD with feed-forward) captures "
                  + ", ".join(f"{b[lv]['rate']:.2f} in {lv}" for lv in LEVELS)
                  + f" turbulence ({runs} episodes each).")
    out.record("docking_env", {"built": True, "episodes": runs, "campaign_seed": CAMPAIGN_SEED,
                               "episode_s": EPISODE_S, "cells": {f"{r['level']}-{r['policy']}": {
                                   "rate": r["rate"], "ci95": [r["ci95_lo"], r["ci95_hi"]],
                                   "captured": r["captured"]} for r in rows}})
    return None
