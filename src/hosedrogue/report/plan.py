"""The report's plan: its sections in build order (:data:`SECTIONS`), what each needs, the
closing sections (:data:`CLOSING`), which of them a partial build runs (:func:`sections_for`) and
how one is run (:func:`run_section`). :mod:`.build` runs the plan in one process or several
(:mod:`.parallel`).

Each entry of :data:`SECTIONS` is one progress-bar step and one entry of
``report.json["build"]["stage_times_s"]``; it names the section's ``build`` function and the
earlier sections whose results it needs (passed as keyword arguments of the same names).
:data:`CLOSING` sections run after all others, during the page step (they summarise the rest).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ..errors import ParameterError
from . import (accuracy, closed_loop, controllers, convergence, differences, docking, docking_env, drogue_actuator,
               engagement, hose_views, linear, long_runs, manoeuvres, paper_table, parameters, pid_tuning, receiver,
               sweep, turbulence_speeds, whip_loads)
from .settings import ReportSettings
from .writer import ReportFolder

__all__ = ["Section", "SECTIONS", "CLOSING", "COST_HINT_S", "section_keys", "sections_for", "run_section",
           "cpu_seconds"]


@dataclass(frozen=True)
class Section:
    """One step of the report build.

    Parameters
    ----------
    key : str
        Name of the section's result; later sections ask for it by this name.
    label : str
        Progress-bar text and key of its wall-clock time in ``report.json``.
    build : callable
        ``build(out, settings, **needs) -> result or None``: computes, writes its CSV and PNG
        files, adds its page section(s), summary points, comparison rows and headline numbers.
    needs : tuple of str
        Keys of the earlier sections whose results ``build`` takes as keyword arguments.
    dask : str, optional
        The field of :class:`~hosedrogue.report.settings.ReportSettings` that gives the dask
        workers of the section's campaigns (None there: in its process), for the build's one
        cluster (:mod:`.shared`); None: the section runs no campaign.
    """

    key: str
    label: str
    build: Callable
    needs: tuple[str, ...] = ()
    dask: str | None = None


#: The sections in build order (the page shows them in this order after :data:`.page.FRONT`).
SECTIONS: tuple[Section, ...] = (
    Section("parameters", "parameters", parameters.build),
    Section("convergence", "convergence", convergence.build, needs=("parameters",)),
    Section("accuracy", "accuracy per cost", accuracy.build, needs=("convergence",)),
    Section("sweep", "steady sweep (Fig. 3)", sweep.build),
    Section("turbulence_speeds", "turbulence at four airspeeds (Fig. 4)", turbulence_speeds.build),
    Section("linear", "linear model (Table 2, Figs. 5-8)", linear.build, needs=("sweep",)),
    Section("controllers", "controllers on linear models (Table 3, Figs. 10-11)", controllers.build, needs=("linear",)),
    Section("closed_loop", "controllers in turbulence (Figs. 12-13)", closed_loop.build, needs=("controllers",)),
    Section("pid_tuning", "PID tuned for the plant", pid_tuning.build),
    Section("hose_3d", "hose in 3D", hose_views.build_3d, needs=("closed_loop",)),
    Section("animation", "animation", hose_views.build_animation, needs=("closed_loop",)),
    Section("long_runs", "long runs", long_runs.build),
    Section("engagement", "engagement", engagement.build),
    Section("whip_loads", "whip loads", whip_loads.build),
    Section("docking", "docking statistics and bow wave", docking.build, dask="docking_workers"),
    Section("docking_env", "docking environment (Gymnasium)", docking_env.build, needs=("docking",)),
    Section("receiver", "receiver aircraft (F-16 trim, docking campaign)", receiver.build, dask="docking_workers"),
    Section("manoeuvres", "manoeuvres", manoeuvres.build, dask="manoeuvre_workers"),
    Section("drogue_actuator", "actuated drogue", drogue_actuator.build, dask="docking_workers"),
)

#: Wall time of each section in the full build [s], measured on the project's 2-core machine
#: (report.json's stage times of a fresh clone's ``make reproduce``, 2026-12-02, two processes):
#: only the order in which the parallel build starts its groups (longest first), never a result.
COST_HINT_S: dict[str, float] = {
    "docking": 430.0, "drogue_actuator": 426.0, "docking_env": 64.0, "whip_loads": 56.0, "engagement": 49.0,
    "long_runs": 42.0, "manoeuvres": 35.0, "convergence": 32.0, "pid_tuning": 23.0, "controllers": 13.0,
    "sweep": 10.0, "accuracy": 10.0, "linear": 5.0, "closed_loop": 4.0, "animation": 4.0,
    "turbulence_speeds": 1.0, "parameters": 0.3, "hose_3d": 0.2,
    # not yet from a full build: 84 trims at 0.33 s, 200 F-16 runs at 0.33 s and 200 point runs at
    # 0.03 s of CPU (docs/receiver.md) on the two docking workers, 2026-12-03
    "receiver": 70.0,
}

#: Sections built after all of :data:`SECTIONS`, in the page step, untimed.
CLOSING: tuple[Section, ...] = (
    Section("differences", "differences", differences.build, needs=("parameters", "convergence")),
    Section("comparison", "comparison", paper_table.build),
)


def section_keys() -> tuple[str, ...]:
    """The keys of :data:`SECTIONS`, in build order (what ``reproduce --only`` accepts)."""
    return tuple(s.key for s in SECTIONS)


def sections_for(only=None) -> tuple[Section, ...]:
    """The sections to build for ``only`` (keys of :data:`SECTIONS`), with every section they need,
    in build order; all of them for None.

    Parameters
    ----------
    only : sequence of str, optional
        Section keys (:func:`section_keys`).

    Returns
    -------
    tuple of Section

    Raises
    ------
    ParameterError
        A key that names no section.
    """
    if only is None:
        return SECTIONS
    by_key = {s.key: s for s in SECTIONS}
    wanted, stack = set(), list(only)
    while stack:
        key = stack.pop()
        if key not in by_key:
            raise ParameterError(f"only = {key!r}: no such report section; sections: {', '.join(by_key)}")
        if key not in wanted:
            wanted.add(key)
            stack.extend(by_key[key].needs)
    return tuple(s for s in SECTIONS if s.key in wanted)


def cpu_seconds() -> float:
    """CPU time [s] of this process and of its children that have ended (user and system): a
    section's difference counts the dask workers it started and closed
    (``report.json["build"]["stage_cpu_s"]``, beside the wall times). It leaves out the time spent
    waiting for other jobs, but contention still inflates it: compare builds made at the same load.
    Where there is no ``resource`` module (Windows): this process's only."""
    try:
        import resource
    except ImportError:
        import time

        return time.process_time()
    return sum(u.ru_utime + u.ru_stime for u in (resource.getrusage(resource.RUSAGE_SELF),
                                                 resource.getrusage(resource.RUSAGE_CHILDREN)))


def run_section(section: Section, out: ReportFolder, settings: ReportSettings, results: dict) -> None:
    """Build one section into ``out``, its result into ``results`` under its key.

    Parameters
    ----------
    section : Section
        The section.
    out : ReportFolder
        The report folder.
    settings : ReportSettings
        The build's settings.
    results : dict
        Earlier sections' results by key (it takes those it needs); its own is added.
    """
    results[section.key] = section.build(out, settings, **{name: results[name] for name in section.needs})
