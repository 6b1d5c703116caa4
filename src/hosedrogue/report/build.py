"""Build the reproduction report (``hosedrogue reproduce``): the ordered list of sections and the
loop that runs them.

Each entry of :data:`SECTIONS` is one progress-bar step and one entry of
``report.json["build"]["stage_times_s"]``; it names the section's ``build`` function and the
earlier sections whose results it needs (passed as keyword arguments of the same names).
:data:`CLOSING` sections run after all others, during the page step (they summarise the rest).
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from ..errors import ParameterError
from ..version import __version__
from . import (accuracy, closed_loop, controllers, convergence, differences, docking, docking_env, drogue_actuator,
               engagement, hose_views, linear, long_runs, manoeuvres, paper_table, parameters, pid_tuning, sweep,
               turbulence_speeds, whip_loads)
from .page import render_page
from .settings import FAST, FULL, ReportSettings
from .writer import ReportFolder

__all__ = ["ReportSettings", "FULL", "FAST", "Section", "SECTIONS", "CLOSING", "build_report", "section_keys",
           "sections_for"]


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
    """

    key: str
    label: str
    build: Callable
    needs: tuple[str, ...] = ()


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
    Section("docking", "docking statistics and bow wave", docking.build),
    Section("docking_env", "docking environment (Gymnasium)", docking_env.build, needs=("docking",)),
    Section("manoeuvres", "manoeuvres", manoeuvres.build),
    Section("drogue_actuator", "actuated drogue", drogue_actuator.build),
)

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


def _run(section: Section, out: ReportFolder, settings: ReportSettings, results: dict) -> None:
    results[section.key] = section.build(out, settings, **{name: results[name] for name in section.needs})


def build_report(out_dir, fast: bool = False, progress: bool = True, only=None) -> dict:
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

    Returns
    -------
    dict
        The headline numbers, as written to ``report.json``.
    """
    from tqdm import tqdm

    settings = FAST if fast else FULL
    chosen = sections_for(only)
    out = ReportFolder(Path(out_dir))
    out.dir.mkdir(parents=True, exist_ok=True)
    results: dict[str, object] = {}
    timings: dict[str, float] = {}
    t_start = time.perf_counter()
    bar = tqdm(total=len(chosen) + 1, desc="reproduce", unit="stage", disable=not progress, file=sys.stderr)
    out.status = bar.set_postfix_str
    try:
        for section in chosen:
            bar.set_description(f"reproduce: {section.label}")
            t0 = time.perf_counter()
            _run(section, out, settings, results)
            timings[section.label] = time.perf_counter() - t0
            bar.update(1)
        bar.set_description("reproduce: page")
        for section in CLOSING:
            if all(name in results for name in section.needs):
                _run(section, out, settings, results)
        elapsed = time.perf_counter() - t_start
        build = {"version": __version__, "settings": settings.name, "fast": bool(fast),
                 "elapsed_s": elapsed, "stage_times_s": timings}
        if only is not None:
            build["sections"] = [s.key for s in chosen]
        headline = out.write_json({"build": build, **out.headline})
        out.write_text(render_page(out, settings, elapsed, build.get("sections")), "index.html")
        bar.update(1)
    finally:
        bar.close()
    return headline
