"""Build the reproduction report (``hosedrogue reproduce``): run the plan's sections
(:mod:`.plan`) in this process or, independent ones side by side, in several (:mod:`.parallel`),
every section's campaigns on one dask cluster of the build (:mod:`.shared`), then the closing
sections and the page.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from ..errors import ParameterError
from ..version import __version__
from .page import render_page
from .plan import CLOSING, COST_HINT_S, SECTIONS, Section, cpu_seconds, run_section, section_keys, sections_for
from .settings import FAST, FULL, ReportSettings
from .writer import ReportFolder

__all__ = ["ReportSettings", "FULL", "FAST", "Section", "SECTIONS", "CLOSING", "build_report", "section_keys",
           "sections_for"]


def build_report(out_dir, fast: bool = False, progress: bool = True, only=None, workers: int = 1) -> dict:
    """Regenerate the paper's Sec. 2.3 and 3 results and write the report into ``out_dir``.

    Parameters
    ----------
    out_dir : str or Path
        Output folder (created if needed; existing files of the same names are overwritten).
    fast : bool
        Coarser grids, shorter runs and fewer convergence steps (well under a minute); the page
        says prominently that it is the fast version.
    progress : bool
        Show a tqdm progress bar over the sections on stderr.
    only : sequence of str, optional
        Build only these sections (keys of :data:`SECTIONS`) and those they need
        (:func:`sections_for`); the closing sections whose needs were built follow. The page and
        ``report.json`` (``build.sections``) say which were built.
    workers : int
        Processes that build independent sections side by side (:mod:`.parallel`); 1: all in this
        process. The report is the same either way.

    Returns
    -------
    dict
        The headline numbers, as written to ``report.json``.
    """
    from tqdm import tqdm

    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ParameterError(f"workers = {workers!r}: must be an integer >= 1")
    settings = FAST if fast else FULL
    chosen = sections_for(only)
    out = ReportFolder(Path(out_dir))
    out.dir.mkdir(parents=True, exist_ok=True)
    t_start, c_start = time.perf_counter(), cpu_seconds()
    bar = tqdm(total=len(chosen) + 1, desc="reproduce", unit="stage", disable=not progress, file=sys.stderr)
    out.status = bar.set_postfix_str
    try:
        results, timings, cluster_cpu_s = _build_sections(chosen, out, settings, bar, workers)
        extra = {} if cluster_cpu_s is None else {"campaign_workers_cpu_s": cluster_cpu_s}
        bar.set_description("reproduce: page")
        for section in CLOSING:
            if all(name in results for name in section.needs):
                run_section(section, out, settings, results)
        elapsed = time.perf_counter() - t_start
        build = {"version": __version__, "settings": settings.name, "fast": bool(fast), "workers": workers,
                 "elapsed_s": elapsed, "stage_times_s": {k: w for k, (w, _) in timings.items()},
                 "cpu_s": cpu_seconds() - c_start, "stage_cpu_s": {k: c for k, (_, c) in timings.items()}, **extra}
        if only is not None:
            build["sections"] = [s.key for s in chosen]
        headline = out.write_json({"build": build, **out.headline})
        out.write_text(render_page(out, settings, elapsed, build.get("sections")), "index.html")
        bar.update(1)
    finally:
        bar.close()
    return headline


def _build_sections(chosen, out: ReportFolder, settings: ReportSettings, bar, workers: int) -> tuple:
    """The chosen sections, in this process or on ``workers`` processes, every campaign on the build's
    one cluster (:mod:`.shared`, closed before this returns, also on an error): their results, their
    wall and CPU times [s] by label, and the CPU time [s] of the cluster's worker processes (the
    campaigns' runs: not in the sections' CPU times, which count their own processes; None: no
    cluster)."""
    from .shared import attached, cluster_workers, shared_resources

    cluster = cluster_workers(chosen, settings)
    with shared_resources(cluster) as shared:
        if workers > 1:
            results, timings = _build_parallel(chosen, out, settings, bar, workers, shared)
        else:
            with attached(shared):
                results, timings = _build_serial(chosen, out, settings, bar)
        closing = cpu_seconds()
    # the cluster's workers are this process's children: their CPU time counts once they have ended
    return results, timings, None if cluster is None else cpu_seconds() - closing


def _build_serial(chosen, out: ReportFolder, settings: ReportSettings, bar) -> tuple[dict, dict]:
    """The sections one after the other in this process: their results, and their wall and CPU
    times [s] (:func:`~hosedrogue.report.plan.cpu_seconds`) by label."""
    results: dict[str, object] = {}
    timings: dict[str, tuple] = {}
    for section in chosen:
        bar.set_description(f"reproduce: {section.label}")
        t0, c0 = time.perf_counter(), cpu_seconds()
        run_section(section, out, settings, results)
        timings[section.label] = (time.perf_counter() - t0, cpu_seconds() - c0)
        bar.update(1)
    return results, timings


def _build_parallel(chosen, out: ReportFolder, settings: ReportSettings, bar, workers: int,
                    shared=None) -> tuple[dict, dict]:
    """The sections' groups on ``workers`` processes, longest first (:data:`COST_HINT_S`); their
    contributions added in build order. The kept results (the closing sections' needs) and the
    sections' wall and CPU times [s] by label, in build order."""
    from .parallel import apply, run_groups, section_groups

    groups = sorted(section_groups(chosen), key=lambda keys: -sum(COST_HINT_S.get(k, 0.0) for k in keys))
    keep = {name for section in CLOSING for name in section.needs}
    bar.set_description(f"reproduce: {len(groups)} groups of sections on {workers} processes")

    def done(keys):
        bar.update(len(keys))
        bar.set_postfix_str(f"done: {', '.join(keys)}")

    results, contributions, times = run_groups(groups, out.dir, settings.fast, keep, min(workers, len(groups)), done,
                                               shared)
    for section in chosen:
        apply(out, contributions[section.key])
    return results, {s.label: times[s.key] for s in chosen}
