"""Report section "Long runs" (docs/long-runs.md): the paper's model blows up in lasting
turbulence; the zigzag modes behind it and the ``converged`` preset that cures it.

The study is library code (:func:`hosedrogue.studies.long_runs.long_runs_study`, imported in
:func:`_study` only); this module reads its numbers into the page. The fast build runs a cheaper,
honestly labelled variant (fewer seeds, shorter cap, a shorter run of the stable model; see
:mod:`.settings`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..results import statistics
from .markup import esc, figure_html, html_table

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["LongRunsResult", "build"]


@dataclass(frozen=True)
class LongRunsResult:
    """Headline numbers of the long-runs section.

    Parameters
    ----------
    paper_damping_ratio : float
        Least damping ratio of the paper's model [-].
    converged_damping_ratio : float
        Least damping ratio of the ``converged`` preset [-].
    damping_gain : float
        Their ratio, converged / paper [-].
    earliest_stop_s : float
        Earliest blow-up of the paper's model over the study's runs [s]; NaN if none stopped.
    stable_run_s : float
        Simulated length of the converged model's run in severe turbulence [s].
    stable_run_completed : bool
        Whether that run completed.
    """

    paper_damping_ratio: float
    converged_damping_ratio: float
    damping_gain: float
    earliest_stop_s: float
    stable_run_s: float
    stable_run_completed: bool


def _study(settings):
    """Run the study at the build's seeds, cap and stable-run length."""
    from ..studies.long_runs import long_runs_study

    return long_runs_study(seeds=settings.long_run_seeds, cap_s=settings.long_run_cap_s,
                           hour_duration_s=settings.long_run_hour_s)


def _hour_stats(study) -> dict:
    """Length, completion, RMS (turbulence on, from its start to the end) and peaks of the stable run [m]."""
    from ..studies.long_runs import TURBULENCE_START_S

    h = study.hour
    off = h.drogue_offset_m
    rms_y, rms_z = statistics.rms_in_window(h.t_s, off, (TURBULENCE_START_S, np.inf))
    peak_y, peak_z = statistics.peaks(off)
    return {"duration_s": float(h.t_s[-1]), "completed": bool(h.completed), "rms_lateral_m": rms_y,
            "rms_vertical_m": rms_z, "peak_lateral_m": peak_y, "peak_vertical_m": peak_z}


def _write_csv(out, study) -> None:
    import pandas as pd

    out.csv(study.blowup, "long_runs_blowup.csv")
    out.csv(study.modes, "long_runs_modes.csv")
    h = study.hour
    off = h.drogue_offset_m
    out.csv(pd.DataFrame({"t_s": h.t_s, "dy_m": off[:, 1], "dz_m": off[:, 2]}), "long_runs_stable_run.csv")


def _stop(row, cap_s: float) -> str:
    return f"completes {cap_s:g} s" if bool(row.completed) else f"stops at {row.t_end_s:.0f} s"


def _tables(study, stats: dict) -> str:
    """Blow-up table (intensity x seed), mode table and the stable run's statistics."""
    b = study.blowup
    seeds = list(dict.fromkeys(int(s) for s in b["seed"]))
    rows = []
    for level, grp in b.groupby("intensity", sort=False):
        cells = {int(r.seed): _stop(r, study.cap_s) for r in grp.itertuples()}
        rows.append((level, f"{grp['sigma_m_s'].iloc[0]:.2f}", *(cells.get(s, "-") for s in seeds)))
    blowup = html_table(["intensity", "sigma [m/s]", *(f"seed {s}" for s in seeds)], rows,
                        table_id="table-long-runs-blowup",
                        caption="Paper's model, open loop, turbulence from 10 s to the end")
    z_paper = float(study.modes.set_index("option")["damping_ratio"]["paper"])
    mrows = [(r.option, f"{r.damping_ratio:.2e}", f"{r.natural_frequency_rad_s:.1f}", f"{r.damping_ratio / z_paper:.1f}")
             for r in study.modes.itertuples()]
    modes = html_table(["model option", "damping ratio [-]", "natural frequency [rad/s]", "x paper's"], mrows,
                       table_id="table-long-runs-modes",
                       caption="Least damped oscillatory mode of the linearization (balance position, steady air)")
    stable = html_table(["run length [s]", "completed", "RMS dy [m]", "RMS dz [m]", "peak |dy| [m]", "peak |dz| [m]"],
                        [(f"{stats['duration_s']:.0f}", "yes" if stats["completed"] else "NO",
                          *(f"{stats[k]:.2f}" for k in ("rms_lateral_m", "rms_vertical_m", "peak_lateral_m",
                                                        "peak_vertical_m")))],
                        table_id="table-long-runs-stable",
                        caption="Converged model in severe turbulence (scenario long-turbulence-severe)")
    return blowup + modes + stable


def _stops_text(study) -> str:
    """Per intensity: 'light (0.74 m/s) completes 3600 s with every seed; moderate ... stops at 384 / 538 s'."""
    parts = []
    for level, grp in study.blowup.groupby("intensity", sort=False):
        sigma = grp["sigma_m_s"].iloc[0]
        if grp["completed"].all():
            what = f"completes {study.cap_s:g} s with {'every seed' if len(grp) > 1 else 'its seed'}"
        else:
            what = "stops at " + " / ".join("completes" if c else f"{t:.0f} s"
                                            for c, t in zip(grp["completed"], grp["t_end_s"]))
        parts.append(f"{esc(level)} ({sigma:.2f} m/s) {what}")
    return "; ".join(parts)


def _mode(study, option: str) -> tuple[float, float]:
    row = study.modes.set_index("option").loc[option]
    return float(row["damping_ratio"]), float(row["natural_frequency_rad_s"])


def _zigzag_prose(study, stats: dict) -> str:
    """The paragraph on the zigzag mode and the remedy; every number read from the study."""
    (zp, wp), (zg, _), (zd, wd), (zr, wr), (zc, wc) = (_mode(study, o) for o in (
        "paper", "+gauss2 drag", "+structural damping", "rod inertia", "converged"))
    outcome = "completes" if stats["completed"] else "does NOT complete"
    return (
        f"<p><b>Why the paper's model blows up.</b> Its least damped modes are the link chain's <i>zigzag</i> "
        f"modes (neighbouring links turning in opposite senses): damping ratio <b>{zp:.1e}</b> at {wp:.1f} rad/s. "
        f"The paper evaluates each link's drag at its midpoint from the mean of its end velocities, so a link "
        f"turning about its midpoint feels no drag, and nothing else damps these modes: lasting turbulence feeds "
        f"them until a link's yaw reaches the limit where the angle coordinates become singular. Here: "
        f"{_stops_text(study)}. It is not the integrator (RK4 at the default step is converged, "
        f'<a href="#convergence">convergence section</a>). Drag integrated along each link by two-point Gauss '
        f"quadrature raises the damping ratio to {zg:.1e}; Kelvin-Voigt structural damping of the hose wall to "
        f"{zd:.1e} (at {wd:.1f} rad/s); rod link inertia alone leaves the zigzag modes as undamped ({zr:.1e}) but "
        f"moves them to {wr:.1f} rad/s, where the gusts put less energy, so it is not relied on alone. "
        f"<b>Remedy:</b> the model preset <code>converged</code> (rod inertia, <code>moment</code> bending, "
        f"Gauss drag, structural damping, <code>split</code> lumping at 20 links, docs/long-runs.md) has damping "
        f"ratio <b>{zc:.1e}</b> at {wc:.1f} rad/s, <b>{study.damping_gain:.0f} x</b> the paper's, and "
        f"{outcome} its {stats['duration_s']:.0f} s in severe turbulence. Use it for every run beyond the "
        f"paper's 20 s window: <code>--config converged</code> on the command line, "
        f"<code>[model] preset = \"converged\"</code> in a scenario file (e.g. the shipped "
        f"<code>long-turbulence-severe</code>), <code>hosedrogue.spec.config.load_preset(\"converged\")</code> from "
        f"Python. The paper's case keeps the paper's model, so the rest of this report is unaffected; the "
        f'preset\'s link count comes from the <a href="#accuracy">accuracy-per-cost section</a>.</p>'
    )


def _fast_note(settings) -> str:
    if not settings.fast:
        return ""
    return (f'<p class=diff id="long-runs-fast">FAST VERSION of this section: seed '
            f"{'/'.join(str(s) for s in settings.long_run_seeds)} only, runs capped at "
            f"{settings.long_run_cap_s:g} s, the converged model run for {settings.long_run_hour_s:g} s instead of "
            f"an hour. The turbulence record is as long as the cap, and a run's stop time is a random variable of "
            f"the record, so the stop times differ from the full report's (three seeds, an hour).</p>")


def _html(settings, study, stats: dict) -> str:
    run = "hour-long run" if stats["duration_s"] >= 3599 else f"{stats['duration_s']:.0f} s run"
    return (
        '<section id="long-runs"><h2>Long runs: the paper\'s model in lasting turbulence</h2>'
        + _fast_note(settings)
        + "<p>The paper's turbulence lasts 20 s. Here it stays on from 10 s to the end of open-loop runs of the "
          f"paper's model (150 m/s, 8000 m, standard MIL-F-8785C intensities at the flight altitude), capped at "
          f"{study.cap_s:g} s, against the least damped mode of each model option and {'an' if run[0] == 'h' else 'a'} "
          f"{run} of the stable "
          "model in severe turbulence.</p>"
        + _zigzag_prose(study, stats) + _tables(study, stats)
        + figure_html("fig-long-runs", "fig_long_runs.png", "Long runs",
                      "(a) Time to blow-up of the paper's model against the turbulence intensity (circles: "
                      "stopped at the yaw limit; triangles: completed the cap, dashed); (b) damping ratio of "
                      "the least damped mode per model option, with its natural frequency; (c) drogue "
                      f"displacement in the converged model's {run} in severe turbulence.",
                      ("long_runs_blowup.csv", "long_runs_modes.csv", "long_runs_stable_run.csv"))
        + "</section>"
    )


def _finding(study, stats: dict) -> LongRunsResult:
    stops = study.blowup.loc[~study.blowup["completed"].astype(bool), "t_end_s"]
    return LongRunsResult(
        paper_damping_ratio=_mode(study, "paper")[0], converged_damping_ratio=_mode(study, "converged")[0],
        damping_gain=study.damping_gain, earliest_stop_s=float(stops.min()) if len(stops) else float("nan"),
        stable_run_s=stats["duration_s"], stable_run_completed=stats["completed"])


def build(out: ReportFolder, settings: ReportSettings) -> LongRunsResult:
    """Run the long-runs study; write its CSV files, figure and section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Seeds, cap [s] and stable-run length [s] of the study.

    Returns
    -------
    LongRunsResult
        Headline numbers.
    """

    study = _study(settings)
    stats = _hour_stats(study)
    f = _finding(study, stats)
    _write_csv(out, study)
    out.figure(study.figures()["long_runs"], "fig_long_runs.png")
    out.section("long-runs", "long runs", _html(settings, study, stats))
    stop = "never stops" if not np.isfinite(f.earliest_stop_s) else f"stops as early as {f.earliest_stop_s:.0f} s"
    out.summarize(f"Long runs: the paper's model has zigzag modes with damping ratio {f.paper_damping_ratio:.1e} and "
                  f"in lasting turbulence {stop}; the 'converged' preset ({f.damping_gain:.0f} x the damping) "
                  f"{'completes' if f.stable_run_completed else 'does not complete'} {f.stable_run_s:.0f} s of "
                  "severe turbulence.")
    out.record("long_runs", {
        "cap_s": study.cap_s,
        "blowup": [{"intensity": r.intensity, "sigma_m_s": r.sigma_m_s, "seed": int(r.seed),
                    "completed": bool(r.completed), "t_end_s": r.t_end_s} for r in study.blowup.itertuples()],
        "modes": {r.option: {"damping_ratio": r.damping_ratio, "natural_frequency_rad_s": r.natural_frequency_rad_s}
                  for r in study.modes.itertuples()},
        "damping_gain": f.damping_gain,
        "stable_run": stats,
    })
    return f
