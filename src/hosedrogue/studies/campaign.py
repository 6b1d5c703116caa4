"""Monte Carlo campaigns: many turbulence realisations of one scenario, run in parallel with
dask.distributed, summarised per run in ``runs.csv`` and over the campaign in ``summary.json``.

Run ``i`` uses the turbulence seed :func:`hosedrogue.studies.seeds.run_seed` ``(seed, i)``,
which depends on ``(seed, i)`` only, so ``runs.csv`` sorted by run index does not depend on the
number of workers, the order in which runs finish or whether the campaign was resumed.

Files in the output folder ``DIR``
----------------------------------
``campaign.json``
    The settings. Resuming with different settings is an error.
``runs.csv``
    One row per finished run (:func:`hosedrogue.studies.store.run_columns`), appended and
    flushed as runs finish, so an interrupted campaign loses at most the runs in flight and at
    most one partial last line, which resuming detects and drops. Wall-clock times are kept out
    of it (they would make identical campaigns differ); they go to ``timings.csv``, a log.
``summary.json``, ``summary.csv``
    Per controller and statistic: mean, standard deviation, 95 % confidence interval of the
    mean (Student t), median, 5th and 95th percentiles, count; and the fraction of runs that
    completed. Statistics are over completed runs only (a run that stopped early has no
    displacement record for the rest of its window); ``count`` says how many.
``histograms.png``, ``cdf.png``
    Distributions of the per-run statistics, one colour per controller.
``miss_cdf.png``, and ``"capture"`` in summary.json
    Engagement scenarios (``[reel]``/``[probe]``, run by the engagement driver): the miss-distance
    CDF and the capture rate with its Wilson 95 % interval; runs.csv then also holds ``result``,
    ``miss_distance_m`` and ``closure_speed_m_s`` (docs/engagement.md, "Docking statistics").
``runs/run_XXXXX.csv``
    With ``keep_timeseries``: each run's time series, written by the worker that ran it
    (``run_XXXXX_CONTROLLER.csv`` with ``compare_controller``).

Per-run statistics
------------------
Those of :mod:`hosedrogue.results.statistics` (peaks, RMS, time inside the capture radii, peak control
forces), computed over each run's saved time series inside the turbulence window (the whole run
when turbulence is off), with the window rule written down there.

Bounded memory
--------------
Tasks are generated lazily and at most ``4 K`` dask tasks (K worker threads), each a batch of up
to 16 runs, are submitted at a time (:func:`hosedrogue.studies.executor.execute_dask`); each worker
returns one small dict per run (the time series stays on the worker and is discarded, or written
to disk there), which the client appends to runs.csv at once and forgets. A campaign of 10 000
runs therefore needs the memory of a few hundred runs; only the final summary reads all rows back
(about 200 bytes each).
"""

from __future__ import annotations

import math
import os
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator, Sequence

import numpy as np

from .. import jsonio
from ..errors import ParameterError
from ..results.statistics import DEFAULT_CAPTURE_RADII_M, capture_column, turbulence_window, window_statistics
from .progress import progress_bar, progress_enabled
from ..scenarios import Scenario, load_scenario
from ..scenarios.runner import run, sampled_controllers
from ..simulation.budget import check_memory, check_run
from . import executor
from .executor import IN_FLIGHT_PER_WORKER, SYNCHRONOUS
from ..results.convergence import DEFAULT_TOLERANCE
from .campaign_verify import campaign_verification, check_sample
from .seeds import run_seed
from .verify import check_tolerance
from .statistics import CampaignSummary, summarize_campaign
from .folder import FolderLock
from .store import (AppendLog, check_rows, check_same_settings, make_settings, read_runs, read_settings, run_columns,
                    todo, write_atomic)

__all__ = ["CampaignSummary", "DEFAULT_CAPTURE_RADII_M", "RunTask", "SYNCHRONOUS", "run_campaign", "run_seed",
           "run_task", "statistics_window", "summarize_run"]


#: Memory [bytes] of one row of runs.csv read back for the summary (as a dict and in a DataFrame):
#: 2.4 kB measured for a fixed-length campaign's row (2026-12-03, tracemalloc over 20 000 rows);
#: an engagement's has 6 columns more.
ROW_BYTES = 4096


@dataclass(frozen=True)
class RunTask:
    """One simulation of a campaign: picklable, sent to a worker."""

    scenario: Any  #: hosedrogue.scenarios.Scenario with the campaign's duration
    index: int  #: run index
    seed: int  #: turbulence seed (:func:`run_seed`)
    controller: str  #: controller type ("pid", "lqr", "none")
    window_s: tuple[float, float]  #: statistics window [start, end) [s]
    #: radii [m] of the time-inside-radius statistics, each > 0 (:func:`summarize_run`)
    capture_radii_m: tuple[float, ...]
    #: file the worker writes the run's time series to (CSV, atomically); None: not kept
    timeseries_path: str | None = None


def _check_int(name: str, value: Any, lo: int, hi: int | None = None) -> int:
    ok = not isinstance(value, bool) and isinstance(value, (int, np.integer))
    if not ok or value < lo or (hi is not None and value > hi):
        allowed = f"an integer in [{lo}, {hi}]" if hi is not None else f"an integer >= {lo}"
        raise ParameterError(f"{name} = {value!r}: must be {allowed}")
    return int(value)


def _check_radii(radii: Any) -> tuple[float, ...]:
    try:
        values = tuple(radii)
    except TypeError:
        values = ()
    good = bool(values) and all(
        not isinstance(r, bool) and isinstance(r, (int, float, np.floating)) and math.isfinite(r) and r > 0
        for r in values
    )
    if not good:
        raise ParameterError(f"capture_radii_m = {radii!r}: must be one or more finite numbers > 0 m")
    values = tuple(float(r) for r in values)
    if len({capture_column(r) for r in values}) != len(values):
        raise ParameterError(f"capture_radii_m = {radii!r}: must be distinct to 6 significant digits")
    return values


def statistics_window(scenario) -> tuple[float, float]:
    """The window [start, end) [s] of the per-run statistics of a scenario.

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The scenario with the campaign's duration [s].

    Returns
    -------
    (float, float)
        :func:`hosedrogue.results.statistics.turbulence_window`: the turbulence window, or the whole run
        ``(0, inf)`` when turbulence is off.

    Raises
    ------
    ParameterError
        When the turbulence window does not overlap the run ``[0, duration_s]``.
    """
    if not scenario.params.turbulence.enabled:
        return 0.0, math.inf
    start, end = turbulence_window(scenario.params.turbulence)
    if start >= scenario.duration_s or end <= start:
        raise ParameterError(
            f"turbulence.start_s = {start!r}: the turbulence window [{start:g}, {end:g}) s must overlap "
            f"the run [0, {scenario.duration_s:g}] s"
        )
    return start, end


# --- one run (executes on a worker) --------------------------------------------------------------
def summarize_run(result, window_s: tuple[float, float], capture_radii_m: Sequence[float]) -> dict:
    """Per-run statistics of a simulation result (:func:`hosedrogue.results.statistics.window_statistics`).

    Parameters
    ----------
    result : hosedrogue.results.run.SimulationResult
        The run.
    window_s : (float, float)
        Statistics window [start, end) [s] (:func:`statistics_window`).
    capture_radii_m : sequence of float
        Capture radii [m].

    Returns
    -------
    dict
        Column -> value; NaN where the window holds no sample (a run that stopped before it).
    """
    return window_statistics(result.t_s, result.drogue_offset_m, result.control_force_n, window_s, capture_radii_m)


def run_task(task: RunTask) -> dict:
    """Simulate one run and return its row of ``runs.csv`` (plus ``_wall_s`` [s], kept out of it).

    Runs single-threaded: the model's kernels are serial, and LocalCluster workers get one thread
    with ``NUMBA_NUM_THREADS = OMP_NUM_THREADS = 1``. The drogue controller is designed once per
    process (:func:`hosedrogue.scenarios.runner.drogue_controller`).

    Parameters
    ----------
    task : RunTask
        What to run; with ``timeseries_path`` the time series is also written there (atomically).

    Returns
    -------
    dict
        Column of :func:`hosedrogue.studies.store.run_columns` -> value, and ``_wall_s`` [s].
    """
    start = time.perf_counter()
    scenario = task.scenario.with_overrides(seed=task.seed).with_controller(task.controller)
    result = run(scenario)
    row = {
        "run": task.index,
        "controller": task.controller,
        "seed": task.seed,
        "completed": bool(result.completed),
        "t_end_s": float(result.t_s[-1]) if result.t_s.size else 0.0,
        **summarize_run(result, task.window_s, task.capture_radii_m),
        **result.outcome_columns(),
        **result.surface_statistics(task.window_s),  # a drogue actuator's columns (to contact)
        "message": result.row_message(),
    }
    _write_series(result, task.timeseries_path)
    row["_wall_s"] = time.perf_counter() - start
    return row


def lost_row(task: RunTask, columns: Sequence[str], reason: str) -> dict:
    """The ``runs.csv`` row of a run whose worker died under it: not completed, no statistics.

    Parameters
    ----------
    task : RunTask
        The run.
    columns : sequence of str
        The columns of runs.csv (:func:`hosedrogue.studies.store.run_columns`).
    reason : str
        Why, in one line.

    Returns
    -------
    dict
        Column -> value: the run's index, controller and seed, ``completed`` false, ``result``
        "stopped" (an engagement), NaN elsewhere, and the message.
    """
    row = {c: math.nan for c in columns}
    row.update({"run": task.index, "controller": task.controller, "seed": task.seed, "completed": False,
                "message": f"stopped: {reason} (user code that ends its process, os._exit or a crash, does this)"})
    if "result" in row:
        row["result"] = "stopped"
    return row


def _write_series(result, path: str | None) -> None:
    """Write the run's time series to ``path`` atomically (nothing if None)."""
    if path:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.name + ".tmp")
        result.to_csv(tmp)
        os.replace(tmp, path)


# --- the campaign --------------------------------------------------------------------------------
def run_campaign(
    scenario: str | Path | Scenario,
    runs: int,
    out_dir: str | Path,
    workers: int | None = None,
    scheduler: str | None = None,
    seed: int = 0,
    capture_radii_m: Sequence[float] = DEFAULT_CAPTURE_RADII_M,
    keep_timeseries: bool = False,
    compare_controller: bool = False,
    duration_s: float | None = None,
    progress: bool = True,
    client=None,
    verify_sample: int = 0,
    tolerance: float = DEFAULT_TOLERANCE,
    plots: bool = True,
) -> CampaignSummary:
    """Run (or resume) a Monte Carlo campaign of ``runs`` turbulence realisations of a scenario.

    Parameters
    ----------
    scenario : str, Path or Scenario
        A shipped scenario name, a TOML file (:func:`hosedrogue.scenarios.load_scenario`) or a
        :class:`~hosedrogue.scenarios.Scenario` built in Python.
    runs : int
        Number of runs (turbulence seeds), >= 1; run ``i`` uses ``run_seed(seed, i)``.
    out_dir : str or Path
        Output folder; if it holds this campaign's files the finished runs are kept (resume).
    workers : int, optional
        Worker processes of a local dask cluster, >= 1 (default ``min(2, os.cpu_count())``).
    scheduler : str, optional
        Address of a running dask scheduler (``tcp://host:8786``) instead of a local cluster, or
        ``"synchronous"`` to run in this process without dask (debugging, profiling). With a remote
        scheduler, ``keep_timeseries`` needs ``out_dir`` on a file system the workers share.
    seed : int
        Campaign seed, >= 0.
    capture_radii_m : sequence of float
        Radii [m] of the time-inside-radius statistics, each > 0.
    keep_timeseries : bool
        Also write each run's time series to ``out_dir/runs/``.
    compare_controller : bool
        Run every seed twice, with the scenario's controller and with none.
    duration_s : float, optional
        Simulated time per run [s] (default: the scenario's).
    progress : bool
        Show a progress bar on stderr (only when it is a terminal).
    client : distributed.Client, optional
        Use this dask client (not closed here) instead of ``workers``/``scheduler``.
    verify_sample : int
        Runs to verify [-] (0: none): run again, and on twice the links at the refined step, in
        this process after the campaign (:mod:`hosedrogue.studies.campaign_verify`: which runs,
        verification.json and .csv, summary.json's ``"verification"``).
    tolerance : float
        Relative tolerance of the verification [-] (default 0.03).
    plots : bool
        Also draw the campaign's own figures (``histograms.png``, ``cdf.png``, ``miss_cdf.png``);
        a study that draws its own from many campaigns (the report's docking grids) leaves them out:
        three figures of many axes, about 0.5 s of CPU per campaign. Resuming the campaign with
        nothing left to run draws them.

    Returns
    -------
    CampaignSummary
        The statistics over all finished runs (also written to ``summary.json`` and
        ``summary.csv``), with how many runs this call added.

    Raises
    ------
    ParameterError
        On bad input (an unknown scenario, ``runs``, ``seed``, ``capture_radii_m``, ``workers``/
        ``scheduler``/``client``, a scenario without a controller for ``compare_controller``, a
        turbulence window outside the run, a controller's entry that cannot be imported), or an
        ``out_dir`` that is a file or holds a campaign with other settings; nothing is written then.
    """
    runs = _check_int("runs", runs, 1)
    if not isinstance(plots, bool):
        raise ParameterError(f"plots = {plots!r}: must be True or False")
    verify_sample, tolerance = check_sample(verify_sample), check_tolerance(tolerance)
    seed = _check_int("seed", seed, 0, 2**63 - 1)
    radii = _check_radii(capture_radii_m)
    workers = _check_execution(workers, scheduler, client)
    if not isinstance(scenario, Scenario):
        scenario = load_scenario(scenario)
    scenario = scenario.with_overrides(duration_s=duration_s)
    for spec in sampled_controllers(scenario).values():
        spec.build()  # every entry imports and its factory builds here, or a one-line error before any run starts
    window = statistics_window(scenario)
    controllers = _controllers(scenario, compare_controller)
    check_run(scenario.params, scenario.duration_s, command=True)  # each run's grids and memory, before any run
    check_memory(runs * len(controllers) * ROW_BYTES, f"runs = {runs}",
                 f"the summary reads {runs * len(controllers)} rows of runs.csv back", "run fewer")
    use_dask = _use_dask(workers, scheduler, client)

    out = Path(out_dir)
    settings = make_settings(scenario, runs, seed, radii, compare_controller, controllers, window)
    _previous_settings(out, settings)  # a folder of other settings: refused before it is locked

    engagement = scenario.engagement is not None
    actuated = scenario.loop.drogue_actuator is not None
    with FolderLock(out):  # this campaign owns the folder until it returns; nothing is written before
        # again, now that no other campaign can write: the settings and rows are final
        old = _previous_settings(out, settings)
        done = read_runs(out / "runs.csv", radii, engagement, actuated) if old is not None else []
        check_rows(out / "runs.csv", done, settings)
        remaining = todo(done, runs, controllers)
        with executor.dask_client(client, workers, scheduler, use_dask and bool(remaining)) as dask_client:
            # bad input and an unreachable scheduler leave no trace (the lock file goes with the folder it made)
            if old is None:
                write_atomic(out / "campaign.json", jsonio.dumps(settings, indent=2) + "\n")
            if remaining:
                series_dir = (out / "runs").resolve() if keep_timeseries else None
                tasks = _tasks(scenario, remaining, seed, window, radii, series_dir, compare_controller)
                total = runs * len(controllers)
                log = AppendLog(out / "runs.csv", run_columns(radii, engagement, actuated))
                try:
                    _execute(tasks, log, out, total, total - len(remaining), progress, dask_client)
                finally:
                    log.close()
        verification = campaign_verification(out, scenario, settings, verify_sample, tolerance, progress)
        return summarize_campaign(out, settings, new_runs=len(remaining), plots=plots, verification=verification)


def _controllers(scenario, compare_controller: bool) -> tuple[str, ...]:
    """The controllers run for every seed: the scenario's, and "none" with ``compare_controller``."""
    if compare_controller and scenario.controller == "none":
        raise ParameterError(
            f"compare_controller = True: scenario {scenario.name!r} has no controller (controller.type = 'none'); "
            "nothing to compare"
        )
    return (scenario.controller, "none") if compare_controller else (scenario.controller,)


def _previous_settings(out: Path, settings: dict) -> dict | None:
    """The settings of a campaign already in ``out`` (None if there is none); ParameterError when
    ``out`` is not a folder or holds a campaign with other settings."""
    if out.exists() and not out.is_dir():
        raise ParameterError(f"out = {str(out)!r}: exists and is not a directory")
    old = read_settings(out) if out.is_dir() else None
    if old is not None:
        check_same_settings(out, old, settings)
    return old


def _check_execution(workers: int | None, scheduler: str | None, client) -> int | None:
    """Validate the choice of where to run; returns ``workers`` as an int (or None)."""
    if sum(x is not None for x in (workers, scheduler, client)) > 1:
        raise ParameterError("workers, scheduler, client: give at most one of them")
    if workers is not None:
        workers = _check_int("workers", workers, 1, 4096)
    if scheduler is not None and (not isinstance(scheduler, str) or not scheduler.strip()):
        raise ParameterError(f"scheduler = {scheduler!r}: must be a scheduler address or {SYNCHRONOUS!r}")
    return workers


def _use_dask(workers: int | None, scheduler: str | None, client) -> bool:
    """Whether the runs go to dask: a client or scheduler address was given, or by default when
    dask.distributed is installed (else this process, with a warning)."""
    use_dask = client is not None or scheduler not in (None, SYNCHRONOUS)
    if not use_dask and scheduler is None:
        if executor.dask_available():
            use_dask = True
        elif workers not in (None, 1):
            raise ParameterError(f"workers = {workers}: needs dask.distributed (pip install 'hosedrogue[dask]')")
        else:
            warnings.warn("dask.distributed is not installed: running the campaign in this process",
                          RuntimeWarning, stacklevel=3)
    elif use_dask and client is None and not executor.dask_available():
        raise ParameterError(f"scheduler = {scheduler!r}: needs dask.distributed (pip install 'hosedrogue[dask]')")
    return use_dask


def _tasks(scenario, pairs: list[tuple[int, str]], seed: int, window: tuple[float, float],
           radii: tuple[float, ...], series_dir: Path | None, compare_controller: bool) -> Iterator[RunTask]:
    """The RunTasks of the (run index, controller) pairs, generated lazily."""
    for i, c in pairs:
        name = f"run_{i:05d}_{c}.csv" if compare_controller else f"run_{i:05d}.csv"
        yield RunTask(scenario, i, run_seed(seed, i), c, window, radii,
                      str(series_dir / name) if series_dir else None)


def _execute(tasks: Iterator[RunTask], log: AppendLog, out: Path, total: int, initial: int,
             progress: bool, client) -> None:
    """Run the tasks (on dask if ``client`` is given, else here), appending rows as they finish."""
    timings = AppendLog(out / "timings.csv", ["run", "controller", "wall_s"])
    bar = progress_bar(total, "montecarlo", enabled=progress_enabled(progress), unit="run", initial=initial,
                       leave=True)

    def on_result(row: dict) -> None:
        wall = row.pop("_wall_s", math.nan)
        log.append(row)
        if math.isfinite(wall):
            timings.append({"run": row["run"], "controller": row["controller"], "wall_s": round(wall, 6)})
        bar.update(1)

    def on_lost(task: RunTask, reason: str) -> None:
        on_result(lost_row(task, log.columns, reason))

    try:
        if client is None:
            executor.execute_synchronous(tasks, run_task, on_result)
        else:
            executor.execute_dask(client, tasks, run_task, IN_FLIGHT_PER_WORKER * executor.total_threads(client),
                                  on_result, on_lost)
    finally:
        bar.close()
        timings.close()
