"""Report section "Engagement": the three shipped engagement scenarios (locked reel,
constant-tension reel, responsive reel; docs/engagement.md) side by side.

Computes the runs (library calls: :func:`hosedrogue.scenarios.runner.run`), a link-doubling
check of their peaks (which each run calls converged, and by how much they move), the tension
wave along the elastic hose around each run's largest exit tension (a run with an output at
every step), writes the time histories, the per-engagement outcomes, the hose shapes and the wave
as CSV, the figures through :mod:`hosedrogue.plotting.engagement`, a GIF of the whip, then the
HTML section with every number read from the runs. ``report.json`` gains an ``"engagement"``
block.

The fast version runs the scenarios on a coarser mesh for a shorter time (the report settings'
``engagement_*`` fields: 40 links, step 2.5 ms, 8 s instead of the shipped 160 links, 5 ms (2 ms locked) and
15 s) and checks the doubling 40 -> 80 instead of the shipped count's; the section says so at its top. The
doubled mesh is :func:`hosedrogue.studies.convergence.with_links`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .markup import esc, figure_html, fmt, html_table, viewer_html

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["EngagementSectionResult", "build", "SCENARIOS"]

#: The shipped engagement scenarios, in the order of the page's columns.
SCENARIOS = ("engage-locked", "engage-constant-tension", "engage-response")

#: Snapshot instants relative to contact [s]: 1 s before (the probe closing in), contact, 0.8 s
#: after (the slack building), 2.5 and 4 s after (the whip and the hose settling after it).
SNAPSHOT_OFFSETS_S = (-1.0, 0.0, 0.8, 2.5, 4.0)

#: The locked run's peak slack and peak probe load are looked for in this long after contact [s]:
#: the coupling's transient (the 2 m push and its stop take under 2 s at 1.5 m/s), not the later
#: swinging of the coupled hose.
PEAK_SEARCH_S = 3.0

#: Instants after contact shown in place of the peak slack and the peak probe load [s] when no
#: output sample lies in the search window (a run that ends at contact).
FALLBACK_PEAK_OFFSETS_S = (1.0, 2.0)

#: Contact time assumed when a run has none [s]: 3 m of standoff at 1.5 m/s.
NOMINAL_CONTACT_S = 2.0

#: The GIF starts this long before contact [s] (the probe's last 0.75 m).
ANIMATION_BEFORE_CONTACT_S = 0.5

#: The tolerance of the runs' verification: the relative change of a converged peak when the links are doubled [-].
DOUBLING_BOUND = 0.03

#: The peaks of the outcome and doubling tables, with their column titles.
PEAK_COLUMNS = (("peak_exit_tension_n", "peak exit tension [N]"), ("peak_tension_rise_n", "its rise [N]"),
                ("peak_drogue_tension_n", "peak drogue-end tension [N]"), ("peak_probe_load_n", "peak probe load [N]"),
                ("peak_slack_m", "peak slack [m]"))

#: The tension-wave figure shows this window around each run's largest exit tension of the
#: engagement transient (contact to PEAK_SEARCH_S after it) [s]: the wave crosses the 16 m hose
#: in about 34 ms at EA = 1e6 N.
WAVE_WINDOW_S = (-0.1, 0.2)

#: The GIF: simulated seconds per real second (the whip is fast).
ANIM_SPEED = 0.5

#: 3D frames per simulated second in the section's viewer page [1/s] (of the runs' 100 per second
#: of output; the page interpolates between frames): a quarter keeps the page of the three 15-s
#: runs at 160 links at 3.7 MB instead of 12.0 MB. Its charts keep every output time.
VIEW_FRAME_RATE_HZ = 25.0

#: The section's viewer page.
VIEW_FILE = "view_engagement.html"


@dataclass(frozen=True)
class EngagementSectionResult:
    """The runs' outcomes (``scenario -> outcome dict``), their mesh and whether it is the fast one."""

    outcomes: dict  #: scenario name -> the run's outcome dict (units in the keys)
    links: int  #: links of the runs
    duration_s: float  #: simulated length of the runs [s]
    fast: bool  #: the fast version (the report settings' engagement mesh and length)


def _scenario(name: str, settings, links: int | None = None):
    """The shipped scenario, on the settings' mesh and length if they give one, or on ``links``
    links with the step scaled with the link length (the doubling check)."""
    import dataclasses

    from ..scenarios import load_scenario
    from ..studies.convergence import with_links

    sc = load_scenario(name)
    if settings.engagement_duration_s is not None:
        sc = dataclasses.replace(sc, duration_s=settings.engagement_duration_s)
    if settings.engagement_links is not None:
        sc = dataclasses.replace(sc, params=sc.params.replace(
            hose={"links": settings.engagement_links},
            numerics={"step_s": settings.engagement_step_s, "output_every": settings.engagement_output_every}))
    return sc if links is None else with_links(sc, links)


def _runs(settings) -> tuple[dict, dict, dict, dict]:
    """The three scenarios, the same on twice the links (the doubling check), and each again up to
    just after its transient's largest exit tension with an output at every step (the tension
    wave; with its window [s])."""
    import dataclasses

    from ..scenarios.runner import run as run_engagement
    from ..studies.verify import verification

    runs, doubled, wave, windows = {}, {}, {}, {}
    for name in SCENARIOS:
        sc = _scenario(name, settings)
        r = run_engagement(sc)
        fine_sc = _scenario(name, settings, links=2 * sc.params.hose.links)
        doubled[name] = run_engagement(fine_sc)
        # the doubling is the run's verification: its converged flags are measured (docs/convergence.md)
        runs[name] = r = dataclasses.replace(r, verification=verification(sc, r, fine_sc, doubled[name], DOUBLING_BOUND))
        if r.step_loads is None:
            continue
        rec, tc = r.step_loads, r.outcome.get("contact_time_s") or NOMINAL_CONTACT_S
        sel = (rec[:, 0] >= tc) & (rec[:, 0] <= tc + PEAK_SEARCH_S)
        tp = float(rec[sel][np.argmax(rec[sel, 1]), 0]) if sel.any() else float(r.t_s[-1]) - WAVE_WINDOW_S[1]
        windows[name] = (tp + WAVE_WINDOW_S[0], tp + WAVE_WINDOW_S[1])
        fine = dataclasses.replace(sc, duration_s=min(sc.duration_s, windows[name][1]),
                                   params=sc.params.replace(numerics={"output_every": 1}))
        wave[name] = run_engagement(fine)
    return runs, doubled, wave, windows


def _label(name: str) -> str:
    return name.removeprefix("engage-")


def _probe_load(r) -> np.ndarray:
    return np.linalg.norm(r.probe_force_n, axis=1)


def _snapshot_times(r) -> list[float]:
    """Instants of the strip: before contact, contact, the locked run's peak slack and peak probe
    load in the 3 s after contact, and two later instants."""
    tc = r.outcome.get("contact_time_s") or NOMINAL_CONTACT_S
    t = r.t_s
    after = (t >= tc) & (t <= tc + PEAK_SEARCH_S)
    slack_fallback, load_fallback = FALLBACK_PEAK_OFFSETS_S
    t_slack = float(t[after][np.argmax(r.slack_m[after])]) if after.any() else tc + slack_fallback
    t_load = float(t[after][np.argmax(_probe_load(r)[after])]) if after.any() else tc + load_fallback
    around = [tc + dt for dt in SNAPSHOT_OFFSETS_S]
    times = sorted({round(x, 1) for x in (*around[:3], t_slack, t_load, *around[3:], t[-1])})
    return [x for x in times if t[0] <= x <= t[-1]]


def _write_csv(out, runs: dict, doubled: dict, times: list[float], frame_times: np.ndarray) -> None:
    import pandas as pd

    frames = []
    for name, r in runs.items():
        df = r.to_dataframe()
        df.insert(0, "scenario", name)
        frames.append(df)
    out.csv(pd.concat(frames, ignore_index=True), "engagement_timeseries.csv")
    rows = []
    for name, r in runs.items():
        o = r.outcome
        rows.append(dict(scenario=name, result=o["result"], links=int(r.links[0]), contact_time_s=o.get("contact_time_s"),
                         miss_distance_m=o["miss_distance_m"], closure_speed_m_s=o["closure_speed_m_s"],
                         peak_probe_load_n=o["peak_probe_load_n"], peak_exit_tension_n=o["peak_exit_tension_n"],
                         min_exit_tension_n=o["min_exit_tension_n"], peak_slack_m=o["peak_slack_m"],
                         peak_drogue_excursion_m=o["peak_drogue_excursion_m"],
                         length_taken_up_m=o["length_taken_up_m"],
                         doubled_links=int(doubled[name].links[0]),
                         doubled_peak_probe_load_n=doubled[name].outcome["peak_probe_load_n"],
                         doubled_peak_slack_m=doubled[name].outcome["peak_slack_m"],
                         doubled_peak_exit_tension_n=doubled[name].outcome["peak_exit_tension_n"]))
    out.csv(pd.DataFrame(rows), "engagement_outcomes.csv")

    def shapes(ts):
        srows = []
        for name, r in runs.items():
            for tt in ts:
                i = int(np.argmin(np.abs(r.t_s - tt)))
                for j, (x, y, z) in enumerate(r.joints_m[i]):
                    srows.append(dict(scenario=name, t_s=r.t_s[i], joint=j, x_m=x, y_m=y, z_m=z))
                px, py, pz = r.probe_position_m[i]
                srows.append(dict(scenario=name, t_s=r.t_s[i], joint="probe", x_m=px, y_m=py, z_m=pz))
        return pd.DataFrame(srows)

    out.csv(shapes(times), "engagement_snapshots.csv")
    out.csv(shapes(frame_times), "anim_engagement.csv")


def _write_wave_csv(out, st) -> None:
    """The tension-wave figure's data: scenario, time [s], arc length [m], tension [N]."""
    import pandas as pd

    from ..plotting.engagement import tension_field

    rows = [dict(scenario=name, t_s=t, s_m=x, tension_n=y)
            for name, r in st.wave.items() for t, s_m, tension in tension_field(r, st.link_length_m)
            if st.windows[name][0] <= t <= st.windows[name][1] for x, y in zip(s_m, tension)]
    out.csv(pd.DataFrame(rows, columns=["scenario", "t_s", "s_m", "tension_n"]), "engagement_wave.csv")


def _flagged(summary: dict, key: str) -> str:
    digits = 3 if key.endswith("_m") else 4
    return fmt(summary[key], digits) + ("" if summary["converged"][key] else " (not converged)")


def _outcome_table(runs: dict) -> str:
    rows = []
    for name, r in runs.items():
        s = r.summary()
        rows.append((_label(name), s["result"], fmt(s["miss_distance_m"], 3), fmt(s["closure_speed_m_s"], 4),
                     *(_flagged(s, k) for k, _ in PEAK_COLUMNS), fmt(s["peak_drogue_excursion_m"], 3),
                     fmt(s["length_taken_up_m"], 3)))
    return html_table(["reel", "result", "miss distance [m]", "closure speed [m/s]", *(t for _, t in PEAK_COLUMNS),
                       "peak drogue excursion [m]", "hose taken up [m]"], rows, table_id="table-engagement")


def _doubling(runs: dict, doubled: dict) -> dict:
    """Relative change of the peaks from the run's links to twice as many."""
    out = {}
    for name in runs:
        a, b = runs[name].outcome, doubled[name].outcome
        out[name] = {k: abs(b[k] - a[k]) / abs(a[k]) if a[k] else float("nan") for k, _ in PEAK_COLUMNS}
    return out


def _doubling_table(runs: dict, doubled: dict, change: dict) -> str:
    rows = []
    for name in runs:
        a, b, c, conv = runs[name].outcome, doubled[name].outcome, change[name], runs[name].summary()["converged"]
        digits = {k: 4 if k.endswith("_m") else 5 for k, _ in PEAK_COLUMNS}
        rows.append((_label(name), f"{int(runs[name].links[0])} -> {int(doubled[name].links[0])}",
                     *(f"{fmt(a[k], digits[k])} -> {fmt(b[k], digits[k])} ({100 * c[k]:.1f} %"
                       f"{'' if conv[k] else ', not converged'})" for k, _ in PEAK_COLUMNS)))
    return html_table(["reel", "links", *(t for _, t in PEAK_COLUMNS)], rows, table_id="table-engagement-doubling")


@dataclass(frozen=True)
class _Study:
    """What the section computes: the runs, their doubled-links twins and the numbers read from them."""

    runs: dict  #: scenario -> EngagementResult
    doubled: dict  #: scenario -> the same on twice the links
    wave: dict  #: scenario -> the run to its transient's peak exit tension, output at every step
    windows: dict  #: scenario -> the tension-wave figure's time window [s]
    slack: dict  #: scenario -> whether the hose went slack
    change: dict  #: scenario -> relative change of the peaks on doubling [-]
    times: list  #: snapshot instants [s]
    window: tuple  #: (start, end) of the animation [s]
    frame_times: np.ndarray  #: instants of the animation's frames [s]
    fast: bool
    link_length_m: float  #: the nominal link length [m]
    wave_speed_m_s: float  #: the axial wave speed sqrt(EA / mu) [m/s] (inf for rigid links)

    @property
    def outcomes(self) -> dict:
        return {name: r.outcome for name, r in self.runs.items()}

    @property
    def links(self) -> int:
        return int(self.runs["engage-locked"].links[0])

    @property
    def duration_s(self) -> float:
        return float(self.runs["engage-locked"].t_s[-1])

    @property
    def worst(self) -> float:
        """Largest relative change on doubling of a peak the runs call converged [-]."""
        return max((c[k] for name, c in self.change.items() for k, ok in self.runs[name].summary()["converged"].items()
                    if ok is True), default=0.0)


def _study(settings) -> _Study:
    """Run the scenarios and the doubling check; pick the snapshot instants and the animation window."""

    runs, doubled, wave, windows = _runs(settings)
    slack = {name: r.went_slack() for name, r in runs.items()}
    change = _doubling(runs, doubled)
    locked = runs["engage-locked"]
    times = _snapshot_times(locked)
    tc = locked.outcome.get("contact_time_s") or NOMINAL_CONTACT_S
    window = (max(0.0, tc - ANIMATION_BEFORE_CONTACT_S),
              min(float(locked.t_s[-1]), tc + settings.engagement_animation_after_contact_s))
    frame_times = np.arange(window[0], window[1] + 1e-9, ANIM_SPEED / settings.anim_fps)
    hose = _scenario(SCENARIOS[0], settings).params.hose
    return _Study(runs=runs, doubled=doubled, wave=wave, windows=windows, slack=slack, change=change, times=times,
                  window=window, frame_times=frame_times, fast=settings.fast, link_length_m=hose.link_length_m,
                  wave_speed_m_s=math.sqrt(hose.axial_stiffness_n / hose.mass_per_length_kg_m))


def _figures(out, st: _Study, settings) -> float:
    """The time histories, the hose shapes and the GIF; returns the GIF's size [MB]."""
    from ..plotting.engagement import (animate_engagement, plot_drogue_region, plot_engagement_history,
                                       plot_tension_wave)

    labelled = {_label(n): r for n, r in st.runs.items()}
    out.figure(plot_engagement_history(labelled), "fig_engagement_history.png")
    out.figure(plot_drogue_region(labelled, st.times), "fig_engagement_snapshots.png")
    if st.wave:
        out.figure(plot_tension_wave({_label(n): r for n, r in st.wave.items()}, st.link_length_m,
                                     {_label(n): w for n, w in st.windows.items()}, st.wave_speed_m_s),
                   "fig_engagement_wave.png")
    out.status("engagement animation")
    gif = animate_engagement(labelled, out.dir / "anim_engagement.gif", fps=settings.anim_fps, speed=ANIM_SPEED,
                             window_s=st.window)
    out.written(gif)
    return gif.stat().st_size / 1e6


def _viewer(out, st: _Study) -> float:
    """The three runs in the viewer (one page, overlaid); returns its size [MB]."""
    from ..viewer import ViewRun, write_view

    runs = [ViewRun.from_result(r, label=_label(n)) for n, r in st.runs.items()]
    path = write_view(runs, out.dir / VIEW_FILE, frame_rate_hz=VIEW_FRAME_RATE_HZ,
                      title="The engagement: three reels (locked, constant-tension, responsive)")
    out.written(path)
    return path.stat().st_size / 1e6


def _fast_note(st: _Study) -> str:
    n = st.links
    return (f'<p class=diff id="engagement-fast">FAST VERSION of this section: {n} links and {st.duration_s:g} s '
            f"per run, not the shipped scenarios' mesh and 15 s; the doubling check is {n} -&gt; {2 * n} links. "
            "The full report runs the shipped scenarios.</p>" if st.fast else "")


def _contact_text(o: dict) -> str:
    ol = o["engage-locked"]
    return (f"All three probes are {esc(ol['result'])} at t = {fmt(ol.get('contact_time_s'), 3)} s with a miss "
            f"of {fmt(ol['miss_distance_m'], 2)} m and a closure speed of {fmt(ol['closure_speed_m_s'], 3)} m/s "
            "seen by the coupler (the probe's 1.5 m/s along the inclined last link)."
            if all(v["result"] == "captured" for v in o.values()) else
            "Results: " + "; ".join(f"{_label(k)}: {esc(v['result'])}" for k, v in o.items()) + ".")


def _doubling_text(st: _Study) -> str:
    n, worst = st.links, st.worst
    conv = {k: st.runs[k].summary()["converged"] for k in SCENARIOS}
    head = (f"<p><b>Link doubling.</b> Each run is verified: run again on {2 * n} links of half the length at "
            "half the step (docs/convergence.md, \"Verifying a run\"); a peak that changes by less than 3 % "
            "is marked converged, the others not converged (the tables, and <code>run.json</code>'s "
            "<code>converged</code> and <code>verification</code>). ")
    if not any(v is True for c in conv.values() for v in c.values()):
        return head + f"On links of {st.link_length_m:g} m no peak of any run is converged.</p>"
    flailing = [_label(k) for k in SCENARIOS if st.runs[k].verification["notes"]
                and any("flailing" in note for note in st.runs[k].verification["notes"])]
    return (
        head + f"Every peak marked converged changed by at most {100 * worst:.1f} % (the peaks are taken at every "
        "step, not only at the 10 ms outputs). The hose is elastic (axial stiffness 1e6 N, axial damping 3000 N s; "
        "docs/model.md §11): when it snaps taut the load is a tension wave of about v sqrt(EA mu), a steep front "
        "whose peak the mesh resolves only as its links and step allow. "
        + (f"The {', '.join(flailing)} reel leaves its loop flailing in the stream to the end of the run, a "
           "chaotic motion whose tension and probe load peaks change with every change of mesh, step or "
           "probe path (a micrometre of the probe's offset moves its peak exit tension by 40 %): its peaks are "
           "a distribution (<code>hosedrogue simulate --ensemble</code>)." if flailing else "") + "</p>")


def _prose(st: _Study) -> str:
    o = st.outcomes
    ol, oc, orr = (o[s] for s in SCENARIOS)
    return (
        f"<p>The receiver's probe starts 3 m behind the drogue's balance position (150 m/s, 8000 m, tanker "
        f"wake on, no turbulence), closes at 1.5 m/s, couples, pushes the drogue 2 m further forward and holds "
        f"(docs/engagement.md). The hose has {st.links} links and the runs last {st.duration_s:g} s. "
        f"{_contact_text(o)}</p>"
        f"<p>The <b>locked</b> reel cannot take up the 2 m: the hose goes slack "
        f"(peak slack {fmt(ol['peak_slack_m'], 3)} m), bunches near the drogue into a loop that flails in the "
        f"stream to the end of the run. The <b>constant-tension</b> reel takes up "
        f"{fmt(oc['length_taken_up_m'], 3)} m as the tension drops: the slack stays at "
        f"{fmt(oc['peak_slack_m'], 3)} m, the exit tension rises by at most {fmt(oc['peak_tension_rise_n'])} N "
        f"above the trail tension and the probe sees {fmt(oc['peak_probe_load_n'])} N. The <b>responsive</b> "
        f"reel needs slack to move (its take-up speed is commanded by the slack beyond a dead band): it lets "
        f"{fmt(orr['peak_slack_m'], 3)} m build and takes up {fmt(orr['length_taken_up_m'], 3)} m; at the end "
        f"of the push the hose snaps taut and the exit tension rises by {fmt(orr['peak_tension_rise_n'])} N "
        f"(the tension wave of the figure below); the probe sees {fmt(orr['peak_probe_load_n'])} N.</p>"
        + _doubling_text(st)
    )


def _wave_figure(st: _Study) -> str:
    if not st.wave:
        return ""
    return figure_html(
        "fig-engagement-wave", "fig_engagement_wave.png", "The tension wave of the whip",
        "Tension along the hose (material arc length from the exit) against time around each run's largest exit "
        f"tension in the {PEAK_SEARCH_S:g} s after contact, from a run with an output at every step; the dashed "
        f"lines travel at the axial wave speed sqrt(EA / mu) = {st.wave_speed_m_s:.0f} m/s.",
        ("engagement_wave.csv",))


def _html(st: _Study, size_mb: float, view_mb: float) -> str:
    window = st.window
    return (
        '<section id="engagement"><h2>Beyond the paper: the refuelling engagement</h2>' + _fast_note(st)
        + _prose(st)
        + _outcome_table(st.runs)
        + _doubling_table(st.runs, st.doubled, st.change)
        + _wave_figure(st)
        + figure_html("fig-engagement-history", "fig_engagement_history.png", "Engagement time histories",
                      "Hose length, take-up speed (positive reeling in), exit tension, tension at the drogue end, "
                      "probe load, slack (hose length minus the straight exit-to-drogue distance), drogue x "
                      "offset and the coupled flag of the three reels; the dotted line is the contact.",
                      ("engagement_timeseries.csv",))
        + figure_html("fig-engagement-snapshots", "fig_engagement_snapshots.png", "Hose shapes",
                      "Side view of the aft 5 m of hose (x forward, z down) with the probe tip (triangle) at "
                      f"t = {', '.join(f'{x:g}' for x in st.times)} s: before contact, contact, and the locked "
                      "reel's peak slack and peak probe load.",
                      ("engagement_snapshots.csv",))
        + f'<figure id="anim-engagement"><img src="anim_engagement.gif" alt="engagement animation">'
        f"<figcaption><b>Animation of the whip.</b> Side view (x-z) of the three hoses and probe tips from "
        f"{window[0]:g} to {window[1]:g} s at {ANIM_SPEED:g} x real time ({size_mb:.1f} MB). "
        f'<span class=data>Data: <a href="anim_engagement.csv">anim_engagement.csv</a>.</span>'
        f"</figcaption></figure>"
        + viewer_html("view-engagement", VIEW_FILE, "The three engagements in 3D",
                      "The hoses, drogues, tow point and probes of the three reels overlaid (or side by side), "
                      "with the drogue offset, exit tension and probe load; play, scrub, change the speed and "
                      "the camera, drag to orbit. 3D frames at "
                      f"{VIEW_FRAME_RATE_HZ:g} per simulated second, interpolated; the charts at every output time.",
                      view_mb)
        + "</section>"
    )


def _summary(st: _Study) -> str:
    ol, oc, orr = (st.outcomes[k] for k in SCENARIOS)
    return (
        f"Engagement ({st.links} elastic links{', fast version' if st.fast else ''}): the locked reel lets "
        f"{ol['peak_slack_m']:.2f} m of slack build and its loop flails; the constant-tension reel takes up "
        f"{oc['length_taken_up_m']:.2f} m with {oc['peak_slack_m']:.3f} m of slack and a peak exit tension of "
        f"{oc['peak_exit_tension_n']:.0f} N; the responsive reel's hose snaps taut at {orr['peak_exit_tension_n']:.0f} N. "
        f"Doubling the links moves the converged peaks by at most {100 * st.worst:.1f} %.")


#: Outcome keys recorded per run in report.json (units in their names).
_RECORD_KEYS = ("miss_distance_m", "closure_speed_m_s", "contact_time_s", "peak_probe_load_n", "peak_exit_tension_n",
               "peak_tension_rise_n", "peak_drogue_tension_n", "min_exit_tension_n", "peak_slack_m",
               "peak_drogue_excursion_m", "length_taken_up_m")


def _record(st: _Study, size_mb: float, view_mb: float) -> dict:
    """The ``"engagement"`` block of report.json."""
    n, change = st.links, st.change
    return {
        "links": n, "duration_s": st.duration_s, "fast": st.fast,
        "runs": {_label(k): {"captured": v["result"] == "captured", **{x: v[x] for x in _RECORD_KEYS},
                             "converged": st.runs[k].summary()["converged"],
                             "doubling_change": change[k]}
                 for k, v in st.outcomes.items()},
        "doubling_links": 2 * n, "doubling_max_change": st.worst, "animation_size_mb": size_mb,
        "viewer_size_mb": view_mb, "viewer_frame_rate_hz": VIEW_FRAME_RATE_HZ,
    }


def build(out: ReportFolder, settings: ReportSettings) -> EngagementSectionResult:
    """Run the three engagement scenarios and write their section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        ``engagement_*``: the runs' mesh and length and the GIF's window; ``anim_fps``: GIF
        frames per real second [1/s]; ``fast``: the section says it is the fast version.

    Returns
    -------
    EngagementSectionResult
        The runs' outcomes, their links and duration [s].
    """
    out.status("engagement runs")
    st = _study(settings)
    _write_csv(out, st.runs, st.doubled, st.times, st.frame_times)
    if st.wave:
        _write_wave_csv(out, st)
    size_mb = _figures(out, st, settings)
    view_mb = _viewer(out, st)
    out.section("engagement", "engagement", _html(st, size_mb, view_mb))
    out.summarize(_summary(st))
    out.record("engagement", _record(st, size_mb, view_mb))
    return EngagementSectionResult(outcomes=st.outcomes, links=st.links, duration_s=st.duration_s, fast=st.fast)
