"""The report's sections on several cores: independent sections in separate processes, their
contributions merged in build order, so the report is the one a single process writes.

A *group* is a set of sections joined by what they need (``Section.needs``): a section runs in the
process that built the results it takes (sweep, linear model, controllers, closed loop, the 3D
views and the animation are one group; the docking statistics and the docking environment
another). Each process writes its sections' files into the report folder and returns what they
added to the page and to ``report.json`` (:class:`Contribution`); the parent adds the
contributions in the order of :data:`~hosedrogue.report.plan.SECTIONS`, whatever order the
processes finish in. The processes are started fresh (``spawn``): no state of the parent leaks
into them. The campaigns of every process run on the build's one dask cluster, which the parent
starts before them and closes after them (:mod:`.shared`); each process connects to it.
"""

from __future__ import annotations

import multiprocessing
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Contribution", "section_groups", "build_group", "run_groups"]


@dataclass(frozen=True)
class Contribution:
    """What one section added to the report folder, in the order it added it.

    Parameters
    ----------
    files : tuple of str
        Files written.
    sections : tuple of PageSection
        Page sections.
    summary : tuple of str
        Points of the page's summary.
    rows : tuple of dict
        Rows of the paper-against-ours table.
    headline : dict
        Headline numbers of ``report.json`` (top-level keys).
    """

    files: tuple
    sections: tuple
    summary: tuple
    rows: tuple
    headline: dict


def _mark(out) -> tuple:
    return len(out.files), len(out.sections), len(out.summary), len(out.comparison.rows), tuple(out.headline)


def _contribution(out, mark: tuple) -> Contribution:
    files, sections, summary, rows, keys = mark
    return Contribution(tuple(out.files[files:]), tuple(out.sections[sections:]), tuple(out.summary[summary:]),
                        tuple(out.comparison.rows[rows:]),
                        {k: v for k, v in out.headline.items() if k not in keys})


def apply(out, c: Contribution) -> None:
    """Add a section's contribution to the report folder ``out``.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The parent's folder.
    c : Contribution
        What the section added in its process.
    """
    out.files.extend(c.files)
    out.sections.extend(c.sections)
    out.summary.extend(c.summary)
    out.comparison.rows.extend(c.rows)
    out.headline.update(c.headline)


def section_groups(chosen) -> list[tuple[str, ...]]:
    """The chosen sections joined by what they need, each group in build order, the groups in the
    order of their first section.

    Parameters
    ----------
    chosen : sequence of Section
        The sections to build, in build order (every section they need among them).

    Returns
    -------
    list of tuple of str
        Section keys per group.
    """
    group = {s.key: s.key for s in chosen}

    def root(k: str) -> str:
        while group[k] != k:
            k = group[k]
        return k

    for s in chosen:
        for name in s.needs:
            group[root(s.key)] = root(name)
    order: dict[str, list[str]] = {}
    for s in chosen:
        order.setdefault(root(s.key), []).append(s.key)
    return [tuple(keys) for keys in order.values()]


def build_group(keys, out_dir, fast: bool, keep, shared=None) -> tuple[dict, dict, dict]:
    """Build one group's sections in this process, in order (what a worker runs).

    Parameters
    ----------
    keys : sequence of str
        The group's section keys, in build order.
    out_dir : str or Path
        The report folder (it exists).
    fast : bool
        The fast version's settings.
    keep : sequence of str
        Keys of the results the parent needs (the closing sections' needs).
    shared : hosedrogue.report.shared.Shared, optional
        The build's cluster and campaign register (:mod:`.shared`), used while the group builds.

    Returns
    -------
    results : dict
        The kept results, by key.
    contributions : dict
        Section key -> :class:`Contribution`.
    times : dict
        Section key -> (wall-clock time [s], CPU time [s] of this process and the children it
        ended: :func:`~hosedrogue.report.plan.cpu_seconds`).
    """
    from .plan import SECTIONS, cpu_seconds, run_section
    from .settings import FAST, FULL
    from .shared import attached
    from .writer import ReportFolder

    by_key = {s.key: s for s in SECTIONS}
    settings = FAST if fast else FULL
    out = ReportFolder(Path(out_dir))
    results: dict = {}
    contributions, times = {}, {}
    with attached(shared):
        for key in keys:
            mark = _mark(out)
            t0, c0 = time.perf_counter(), cpu_seconds()
            run_section(by_key[key], out, settings, results)
            times[key] = (time.perf_counter() - t0, cpu_seconds() - c0)
            contributions[key] = _contribution(out, mark)
    return {k: results[k] for k in keep if k in results}, contributions, times


def _ignore_interrupt() -> None:
    """A section process leaves Ctrl-C to the parent, which ends it (:func:`run_groups`): also one
    started when SIGINT was not ignored."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _terminate(pool: ProcessPoolExecutor) -> None:
    """End the pool's processes now, whatever they are building (``terminate_workers`` from Python
    3.14 on; before it the executor has no public way, so its process table is read)."""
    if hasattr(pool, "terminate_workers"):
        pool.terminate_workers()
        return
    for process in list((getattr(pool, "_processes", None) or {}).values()):
        process.terminate()


def run_groups(groups, out_dir, fast: bool, keep, workers: int, done=None, shared=None) -> tuple[dict, dict, dict]:
    """Build the groups on ``workers`` processes.

    The first error of a group, Ctrl-C or any other error here ends the build: the processes still
    building are terminated at once (what they were writing is left unfinished, as an interrupted
    single process leaves it) and the error is raised here. The processes ignore Ctrl-C themselves
    (a terminal sends it to all of them): the parent alone decides, so no process goes on to build
    a group it had already taken.

    Parameters
    ----------
    groups : list of tuple of str
        :func:`section_groups`, submitted in this order.
    out_dir : str or Path
        The report folder (it exists).
    fast : bool
        The fast version's settings.
    keep : sequence of str
        Keys of the results the parent needs.
    workers : int
        Processes [-], >= 1.
    done : callable, optional
        Called with each finished group's keys.
    shared : hosedrogue.report.shared.Shared, optional
        The build's cluster and campaign register, passed to every group.

    Returns
    -------
    results, contributions, times : dict
        As :func:`build_group`'s, over every group.
    """
    from .shared import children_ignore_interrupts

    results, contributions, times = {}, {}, {}
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"),
                               initializer=_ignore_interrupt)
    try:
        with children_ignore_interrupts():  # the processes start at the submissions
            pending = {pool.submit(build_group, keys, str(out_dir), fast, tuple(keep), shared): keys
                       for keys in groups}
        while pending:
            finished, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in finished:
                keys = pending.pop(future)
                r, c, t = future.result()  # a section's error stops the build here, as in one process
                results.update(r)
                contributions.update(c)
                times.update(t)
                if done is not None:
                    done(keys)
    except BaseException:
        _terminate(pool)
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)  # groups not started are dropped
    return results, contributions, times
