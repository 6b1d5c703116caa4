"""Monte Carlo campaigns: many turbulence realisations of one scenario, run in parallel with
dask.distributed, summarised per run in ``runs.csv`` and over the campaign in ``summary.json``.

Reproducibility
---------------
Run ``i`` of a campaign with seed ``S`` uses the turbulence seed (:func:`run_seed`)::

    numpy.random.SeedSequence([S, i]).generate_state(1, dtype=numpy.uint64)[0] % 2**63

It depends on ``(S, i)`` only, not on the number of workers, the order in which runs finish or
whether the campaign was interrupted and resumed, so ``runs.csv`` sorted by run index is identical
for any of these. ``SeedSequence`` hashes its entropy, so neighbouring indices give unrelated
seeds, and its output is stable across numpy versions (numpy's documented guarantee). The value is
reduced modulo 2**63 because ``turbulence.seed`` is limited to [0, 2**63 - 1].

Files in the output folder ``DIR``
----------------------------------
``campaign.json``
    The settings. Resuming with different settings is an error.
``runs.csv``
    One row per finished run (:func:`run_columns`), appended and flushed as runs finish, so an
    interrupted campaign loses at most the runs in flight and at most one partial last line,
    which resuming detects and drops. Wall-clock times are kept out of it (they would make
    identical campaigns differ); they go to ``timings.csv``, a log.
``summary.json``, ``summary.csv``
    Per controller and statistic: mean, standard deviation, 95 % confidence interval of the
    mean (Student t), median, 5th and 95th percentiles, count; and the fraction of runs that
    completed. Statistics are over completed runs only (a run that stopped early has no
    displacement record for the rest of its window); ``count`` says how many.
``histograms.png``, ``cdf.png``
    Distributions of the per-run statistics, one colour per controller.
``runs/run_XXXXX.csv``
    With ``keep_timeseries``: each run's time series, written by the worker that ran it
    (``run_XXXXX_CONTROLLER.csv`` with ``compare_controller``).

Per-run statistics
------------------
Displacements are of the drogue from its balance position in S_p (y lateral, right; z vertical,
down) inside the turbulence window ``[turbulence.start_s, start_s + duration_s)`` (the whole run
when turbulence is off): peak ``max |d|`` and RMS about the balance position ``sqrt(mean(d^2))``
of lateral ``dy``, vertical ``dz`` and radial ``sqrt(dy^2 + dz^2)`` displacement [m]; the fraction
of the window's samples with the radial displacement inside each capture radius [-]; and the
peak control forces ``|u_hor|``, ``|u_ver|`` and ``sqrt(u_hor^2 + u_ver^2)`` [N].

Bounded memory
--------------
Tasks are generated lazily and at most ``4 K`` runs (K worker threads) are submitted at a time
(:func:`execute_dask`); each worker returns one small dict per run (the time series stays on the
worker and is discarded, or written to disk there), which the client appends to runs.csv at once
and forgets. A campaign of 10 000 runs therefore needs the memory of a few dozen runs; only the
final summary reads all rows back (about 200 bytes each).
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import io
import json
import math
import os
import sys
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator, Sequence

import numpy as np

from .params import ParameterError

#: Capture radii [m]: 0.1 m, the drogue positioning accuracy required in Wu et al. (2018); 0.305 m,
#: the radius of the paper's drogue basket (diameter 0.61 m, Table 1).
DEFAULT_CAPTURE_RADII_M = (0.1, 0.305)

#: Runs in flight per worker thread: enough to keep workers busy while the client writes rows.
IN_FLIGHT_PER_WORKER = 4

#: Tolerance on the window's edges [s]: output times t = k h carry rounding errors.
_WINDOW_EPS_S = 1e-9

#: The scheduler value that runs every simulation in this process, without dask.
SYNCHRONOUS = "synchronous"

_FORMAT = "hosedrogue-montecarlo/1"

#: Settings that must agree when a campaign is resumed (see campaign.json).
_COMPARED_SETTINGS = ("scenario", "runs", "seed", "capture_radii_m", "compare_controller",
                      "controllers", "duration_s")

#: (column, unit) of the per-run statistics; the names and their order are those of
#: hosedrogue.batch.SUMMARY_COLUMNS, so a campaign's runs.csv and a batch's table read alike.
_DISPLACEMENT_STATS = (
    ("peak_dy_m", "m"), ("peak_dz_m", "m"), ("peak_radial_m", "m"),
    ("rms_dy_m", "m"), ("rms_dz_m", "m"), ("rms_radial_m", "m"),
)
_FORCE_STATS = (("peak_u_hor_n", "N"), ("peak_u_ver_n", "N"), ("peak_u_n", "N"))
_KEY_COLUMNS = ("run", "controller", "seed", "completed", "t_end_s")


def capture_column(radius_m: float) -> str:
    """Column of the time fraction inside ``radius_m`` [m], e.g. ``inside_0.1m_frac`` (as in batch)."""
    return f"inside_{float(radius_m):g}m_frac"


def statistic_units(capture_radii_m: Sequence[float]) -> dict[str, str]:
    """The per-run statistics (CSV columns) and their units, in column order."""
    units = dict(_DISPLACEMENT_STATS)
    units.update(dict(_FORCE_STATS))
    units.update({capture_column(r): "1" for r in capture_radii_m})
    return units


def run_columns(capture_radii_m: Sequence[float]) -> list[str]:
    """The columns of ``runs.csv``."""
    return [*_KEY_COLUMNS, *statistic_units(capture_radii_m), "message"]


def run_seed(campaign_seed: int, index: int) -> int:
    """Turbulence seed of run ``index`` of the campaign with seed ``campaign_seed`` (module docstring)."""
    state = np.random.SeedSequence([int(campaign_seed), int(index)]).generate_state(1, dtype=np.uint64)
    return int(state[0]) % 2**63


# --- settings and validation ---------------------------------------------------------------------
@dataclass(frozen=True)
class RunTask:
    """One simulation of a campaign: picklable, sent to a worker."""

    scenario: Any  #: hosedrogue.scenarios.Scenario with the campaign's duration
    index: int
    seed: int
    controller: str
    window_s: tuple[float, float]  #: statistics window [start, end) [s]
    capture_radii_m: tuple[float, ...]
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
        raise ParameterError(f"--capture-radii = {radii!r}: must be one or more finite numbers > 0 m")
    values = tuple(float(r) for r in values)
    if len({capture_column(r) for r in values}) != len(values):
        raise ParameterError(f"--capture-radii = {radii!r}: must be distinct to 6 significant digits")
    return values


def statistics_window(scenario) -> tuple[float, float]:
    """The window [start, end) [s] of the per-run statistics: the turbulence window, clipped to the
    run, or the whole run (end = inf) when turbulence is off."""
    turb = scenario.params.turbulence
    if not turb.enabled:
        return 0.0, math.inf
    start, end = turb.start_s, turb.start_s + turb.duration_s
    if start >= scenario.duration_s or end <= start:
        raise ParameterError(
            f"turbulence.start_s = {start!r}: the turbulence window [{start:g}, {end:g}) s must overlap "
            f"the run [0, {scenario.duration_s:g}] s"
        )
    return start, end


def _json_normal(value: Any) -> Any:
    """The value as it reads back from JSON (tuples become lists), for comparisons."""
    return json.loads(json.dumps(value))


def _scenario_content(scenario) -> dict:
    """Everything that determines the runs (the file path and description do not)."""
    data = dataclasses.asdict(scenario)
    for key in ("source", "description"):
        data.pop(key, None)
    return _json_normal(data)


def _first_difference(a: Any, b: Any, path: str) -> str | None:
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b)):
            found = _first_difference(a.get(key), b.get(key), f"{path}.{key}")
            if found:
                return found
        return None
    return None if a == b else path


def _settings(scenario, runs, seed, radii, compare_controller, controllers, window) -> dict:
    from . import __version__

    return _json_normal({
        "format": _FORMAT,
        "scenario_name": scenario.name,
        "scenario_source": scenario.source,
        "scenario": _scenario_content(scenario),
        "runs": runs,
        "seed": seed,
        "seed_rule": "numpy.random.SeedSequence([seed, run]).generate_state(1, dtype=uint64)[0] % 2**63",
        "capture_radii_m": list(radii),
        "compare_controller": compare_controller,
        "controllers": list(controllers),
        "duration_s": scenario.duration_s,
        "statistics_window_s": [window[0], None if math.isinf(window[1]) else window[1]],
        "hosedrogue_version": __version__,
    })


def _check_same_settings(out: Path, old: dict, new: dict) -> None:
    for key in _COMPARED_SETTINGS:
        where = _first_difference(old.get(key), new.get(key), key)
        if where:
            raise ParameterError(
                f"--out = {str(out)!r}: holds a campaign with different settings ({where} differs; "
                f"see {out / 'campaign.json'}); use another --out or the same settings to resume"
            )


def _read_settings(out: Path) -> dict | None:
    path = out / "campaign.json"
    if not path.exists():
        if (out / "runs.csv").exists():
            raise ParameterError(f"--out = {str(out)!r}: holds runs.csv but no campaign.json; use another --out")
        return None
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        raise ParameterError(f"--out = {str(out)!r}: campaign.json is not readable JSON ({exc})") from None


def _write_atomic(path: Path, text: str) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


# --- one run (executes on a worker) --------------------------------------------------------------
def summarize_run(result, window_s: tuple[float, float], capture_radii_m: Sequence[float]) -> dict:
    """Per-run statistics of a SimulationResult inside ``window_s`` (see the module docstring).

    NaN where the window holds no sample (a run that stopped before the window).
    """
    t = result.t_s
    inside = (t >= window_s[0] - _WINDOW_EPS_S) & (t < window_s[1] - _WINDOW_EPS_S)
    off = result.drogue_offset_m[inside]
    u = result.control_n[inside]
    dy, dz = off[:, 1], off[:, 2]
    dr = np.hypot(dy, dz)
    force = np.hypot(u[:, 0], u[:, 1])

    def peak(x):
        return float(np.max(np.abs(x))) if x.size else math.nan

    def rms(x):
        return float(np.sqrt(np.mean(x * x))) if x.size else math.nan

    row = {
        "peak_dy_m": peak(dy), "peak_dz_m": peak(dz), "peak_radial_m": peak(dr),
        "rms_dy_m": rms(dy), "rms_dz_m": rms(dz), "rms_radial_m": rms(dr),
        "peak_u_hor_n": peak(u[:, 0]), "peak_u_ver_n": peak(u[:, 1]), "peak_u_n": peak(force),
    }
    for r in capture_radii_m:
        row[capture_column(r)] = float(np.mean(dr <= r)) if dr.size else math.nan
    return row


def run_task(task: RunTask) -> dict:
    """Simulate one run and return its row of ``runs.csv`` (plus ``_wall_s``, kept out of it).

    Runs single-threaded: the model's kernels are serial, and LocalCluster workers get one thread
    with ``NUMBA_NUM_THREADS = OMP_NUM_THREADS = 1``.
    """
    from .runner import run_scenario

    start = time.perf_counter()
    scenario = dataclasses.replace(task.scenario.with_overrides(seed=task.seed), controller=task.controller)
    result = run_scenario(scenario)
    row = {
        "run": task.index,
        "controller": task.controller,
        "seed": task.seed,
        "completed": bool(result.completed),
        "t_end_s": float(result.t_s[-1]) if result.t_s.size else 0.0,
        **summarize_run(result, task.window_s, task.capture_radii_m),
        "message": result.message,
    }
    if task.timeseries_path:
        path = Path(task.timeseries_path)
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.name + ".tmp")
        result.to_csv(tmp)
        os.replace(tmp, path)
    row["_wall_s"] = time.perf_counter() - start
    return row


# --- runs.csv: append, read back, resume ---------------------------------------------------------
def _format_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)  # shortest string that reads back to the same double
    return str(v).replace("\n", " ").replace("\r", " ")


def _csv_line(values: Iterable[Any]) -> str:
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([_format_value(v) for v in values])
    return buf.getvalue()


def _drop_partial_line(path: Path) -> int:
    """Cut a last line without newline (a write interrupted by a kill); return bytes dropped."""
    if not path.exists():
        return 0
    data = path.read_bytes()
    if not data or data.endswith(b"\n"):
        return 0
    keep = data.rfind(b"\n") + 1
    with path.open("r+b") as fh:
        fh.truncate(keep)
    return len(data) - keep


def _parse_value(column: str, text: str) -> Any:
    if column in ("run", "seed"):
        return int(text)
    if column == "completed":
        if text not in ("true", "false"):
            raise ValueError(f"completed = {text!r}")
        return text == "true"
    if column in ("controller", "message"):
        return text
    return float(text)


def read_runs(path: str | Path, capture_radii_m: Sequence[float] = DEFAULT_CAPTURE_RADII_M) -> list[dict]:
    """Rows of a ``runs.csv`` as typed dicts, in file order; a partial last line is ignored."""
    path = Path(path)
    columns = run_columns(capture_radii_m)
    data = path.read_text() if path.exists() else ""
    if data and not data.endswith("\n"):
        data = data[: data.rfind("\n") + 1]
    lines = list(csv.reader(io.StringIO(data)))
    if not lines:
        return []
    if lines[0] != columns:
        raise ParameterError(f"{path}: header {lines[0]!r} does not match the campaign's columns {columns!r}")
    rows = []
    for number, fields in enumerate(lines[1:], start=2):
        try:
            if len(fields) != len(columns):
                raise ValueError(f"{len(fields)} fields, expected {len(columns)}")
            rows.append({c: _parse_value(c, f) for c, f in zip(columns, fields)})
        except ValueError as exc:
            raise ParameterError(f"{path}, line {number}: not a valid run row ({exc})") from None
    return rows


class _AppendLog:
    """A CSV file appended one flushed line at a time, header once, locked against a second writer."""

    def __init__(self, path: Path, columns: Sequence[str], lock: bool = False):
        self.columns = list(columns)
        self.fh = path.open("a", newline="")
        if lock:
            _lock_or_fail(self.fh, path)
        _drop_partial_line(path)  # O_APPEND: the next write goes to the new end
        if path.stat().st_size == 0:
            self._write(self.columns)

    def _write(self, values: Iterable[Any]) -> None:
        self.fh.write(_csv_line(values))  # one write of a whole line: a kill leaves a partial line at most
        self.fh.flush()

    def append(self, row: dict) -> None:
        self._write(row[c] for c in self.columns)

    def close(self) -> None:
        self.fh.close()


def _lock_or_fail(fh, path: Path) -> None:
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX: no protection against two writers
        return
    try:
        fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        fh.close()
        raise ParameterError(f"--out = {str(path.parent)!r}: another campaign is writing to it") from None


# --- execution -----------------------------------------------------------------------------------
def execute_dask(client, tasks: Iterator, fn: Callable, max_in_flight: int, on_result: Callable) -> int:
    """Run ``fn(task)`` for every task on a dask client, at most ``max_in_flight`` at a time, calling
    ``on_result(result)`` in completion order. Returns the largest number of tasks in flight.

    On any error (including KeyboardInterrupt) the outstanding tasks are cancelled and the error
    propagates; results already passed to ``on_result`` stay.
    """
    from concurrent.futures import CancelledError

    from distributed import as_completed
    from distributed.comm.core import CommClosedError

    pending = iter(tasks)
    outstanding: set = set()
    queue = as_completed()
    peak = 0

    def submit_next() -> None:
        nonlocal peak
        task = next(pending, None)
        if task is not None:
            future = client.submit(fn, task, pure=False)
            outstanding.add(future)
            queue.add(future)
            peak = max(peak, len(outstanding))

    for _ in range(max_in_flight):
        submit_next()
    try:
        for future in queue:
            outstanding.discard(future)
            result = future.result()
            future.release()
            on_result(result)
            submit_next()
    except (CancelledError, CommClosedError) as exc:
        # The scheduler went away: it cancels every future (reason "scheduler-connection-lost") or a
        # result's transfer breaks off (CommClosedError). No one is left to cancel the rest with, and
        # the rows passed to on_result are final: stop with one line (exit 3), ready for a resume.
        if isinstance(exc, CancelledError) and getattr(exc, "reason", None) != "scheduler-connection-lost":
            client.cancel(list(outstanding))
            raise
        import logging

        from .errors import IncompleteError

        quiet = logging.getLogger("distributed.client")
        level = quiet.level
        quiet.setLevel(logging.CRITICAL)  # closing cuts its reconnection attempts short: no tracebacks
        try:
            client.close()
        finally:
            quiet.setLevel(level)
        raise IncompleteError("the dask scheduler went away (connection lost); the finished runs are kept: "
                              "run the same command again with a reachable --scheduler to resume") from None
    except BaseException:
        client.cancel(list(outstanding))
        raise
    return peak


def _execute_synchronous(tasks: Iterator, fn: Callable, on_result: Callable) -> None:
    for task in tasks:
        on_result(fn(task))


def _dask_available() -> bool:
    try:
        import distributed  # noqa: F401
    except ImportError:
        return False
    return True


#: No dashboard, and the scheduler's HTTP endpoints on a free port (by default they take 8787, and a
#: second cluster on the machine would warn).
_NO_DASHBOARD = {"dashboard_address": None, "scheduler_kwargs": {"dashboard": False, "dashboard_address": ":0"}}

#: Environment of LocalCluster worker processes (set in the child only, before it imports numba): one
#: thread per process and no thread pools inside it, since the model's kernels are serial.
WORKER_ENVIRON = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
                  "OPENBLAS_NUM_THREADS": "1"}

#: How long to try to reach a --scheduler address.
CONNECT_TIMEOUT_S = 10.0


def _local_cluster(workers: int):
    """A LocalCluster of single-threaded worker processes, and its client."""
    import logging

    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           silence_logs=logging.ERROR, env=dict(WORKER_ENVIRON), **_NO_DASHBOARD)
    return cluster, Client(cluster)


def _connect(scheduler: str):
    from distributed import Client

    try:
        return Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S}s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise ParameterError(f"--scheduler = {scheduler!r}: cannot connect ({exc})") from None


def _total_threads(client) -> int:
    return max(1, sum(client.nthreads().values()))


# --- the campaign --------------------------------------------------------------------------------
@dataclass(frozen=True)
class CampaignSummary:
    """What a campaign produced.

    ``statistics[controller][column]`` holds ``mean``, ``std``, ``ci95_mean`` (low, high),
    ``median``, ``p05``, ``p95``, ``count`` and ``unit`` (None where undefined, e.g. the standard
    deviation of one run); ``completed_fraction[controller]`` the fraction of runs that completed.
    """

    out_dir: Path
    settings: dict
    runs: Any  #: pandas.DataFrame of runs.csv sorted by (controller, run)
    statistics: dict
    completed_fraction: dict
    files: tuple
    new_runs: int  #: runs executed by this call (the rest were resumed from runs.csv)

    def to_dict(self) -> dict:
        """The content of summary.json."""
        return {
            "campaign": self.settings,
            "controllers": {
                c: {
                    "runs": int((self.runs["controller"] == c).sum()),
                    "completed_fraction": self.completed_fraction[c],
                    "statistics": self.statistics[c],
                }
                for c in self.settings["controllers"]
            },
        }


def run_campaign(
    scenario_name_or_path: str,
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
) -> CampaignSummary:
    """Run (or resume) a Monte Carlo campaign of ``runs`` turbulence realisations of a scenario.

    Parameters
    ----------
    scenario_name_or_path : str
        A shipped scenario name or a TOML file (:func:`hosedrogue.scenarios.load_scenario`).
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

    Returns
    -------
    CampaignSummary
    """
    from .scenarios import load_scenario

    runs = _check_int("--runs", runs, 1)
    seed = _check_int("--seed", seed, 0, 2**63 - 1)
    radii = _check_radii(capture_radii_m)
    if sum(x is not None for x in (workers, scheduler, client)) > 1:
        raise ParameterError("--workers, --scheduler: give at most one of them (and no client with either)")
    if workers is not None:
        workers = _check_int("--workers", workers, 1, 4096)
    if scheduler is not None and (not isinstance(scheduler, str) or not scheduler.strip()):
        raise ParameterError(f"--scheduler = {scheduler!r}: must be a scheduler address or {SYNCHRONOUS!r}")
    scenario = load_scenario(scenario_name_or_path).with_overrides(duration_s=duration_s)
    window = statistics_window(scenario)
    if compare_controller and scenario.controller == "none":
        raise ParameterError(
            f"--compare-controller: scenario {scenario.name!r} has no controller (controller.type = 'none'); "
            "nothing to compare"
        )
    controllers = (scenario.controller, "none") if compare_controller else (scenario.controller,)
    use_dask = client is not None or scheduler not in (None, SYNCHRONOUS)
    if not use_dask and scheduler is None:
        if _dask_available():
            use_dask = True
        elif workers not in (None, 1):
            raise ParameterError(f"--workers = {workers}: needs dask.distributed (pip install 'hosedrogue[dask]')")
        else:
            warnings.warn("dask.distributed is not installed: running the campaign in this process",
                          RuntimeWarning, stacklevel=2)
    elif use_dask and client is None and not _dask_available():
        raise ParameterError(f"--scheduler = {scheduler!r}: needs dask.distributed (pip install 'hosedrogue[dask]')")

    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ParameterError(f"--out = {str(out)!r}: exists and is not a directory")
    settings = _settings(scenario, runs, seed, radii, compare_controller, controllers, window)
    old = _read_settings(out) if out.is_dir() else None
    if old is not None:
        _check_same_settings(out, old, settings)

    columns = run_columns(radii)
    pending = _todo(read_runs(out / "runs.csv", radii) if old is not None else [], runs, controllers)
    with _dask_client(client, workers, scheduler, use_dask and bool(pending)) as dask_client:
        # nothing is written before this point: bad input and an unreachable scheduler leave no trace
        out.mkdir(parents=True, exist_ok=True)
        if old is None:
            _write_atomic(out / "campaign.json", json.dumps(settings, indent=2) + "\n")
        log = _AppendLog(out / "runs.csv", columns, lock=True)
        try:
            # again under the lock: the rows are now final
            done = read_runs(out / "runs.csv", radii)
            todo = _todo(done, runs, controllers)
            series_dir = (out / "runs").resolve() if keep_timeseries else None

            def tasks() -> Iterator[RunTask]:
                for i, c in todo:
                    name = f"run_{i:05d}_{c}.csv" if compare_controller else f"run_{i:05d}.csv"
                    yield RunTask(scenario, i, run_seed(seed, i), c, window, radii,
                                  str(series_dir / name) if series_dir else None)

            if todo:
                _execute(tasks(), log, out, runs * len(controllers), runs * len(controllers) - len(todo),
                         progress, dask_client)
        finally:
            log.close()
    return summarize_campaign(out, settings, new_runs=len(todo))


def _todo(done_rows: list[dict], runs: int, controllers: Sequence[str]) -> list[tuple[int, str]]:
    """(run index, controller) pairs without a row yet, in run order."""
    done = {(r["run"], r["controller"]) for r in done_rows}
    return [(i, c) for i in range(runs) for c in controllers if (i, c) not in done]


@contextlib.contextmanager
def _dask_client(client, workers: int | None, scheduler: str | None, needed: bool):
    """The given client; a client of a new scheduler connection or LocalCluster (closed on exit);
    or None when dask is not needed."""
    if not needed or client is not None:
        yield client
        return
    if scheduler is not None:
        owned = [_connect(scheduler)]
    else:
        cluster, new_client = _local_cluster(workers or min(2, os.cpu_count() or 1))
        owned = [new_client, cluster]
    try:
        yield owned[0]
    finally:
        for thing in owned:
            thing.close()


def _execute(tasks: Iterator[RunTask], log: "_AppendLog", out: Path, total: int, initial: int,
             progress: bool, client) -> None:
    """Run the tasks (on dask if ``client`` is given, else here), appending rows as they finish."""
    from tqdm import tqdm

    timings = _AppendLog(out / "timings.csv", ["run", "controller", "wall_s"])
    # the rule of hosedrogue.progress: a terminal, and not HOSEDROGUE_PROGRESS=0
    enabled = progress and sys.stderr.isatty() and os.environ.get("HOSEDROGUE_PROGRESS", "1") != "0"
    bar = tqdm(total=total, initial=initial, unit="run", file=sys.stderr, desc="montecarlo", disable=not enabled)

    def on_result(row: dict) -> None:
        wall = row.pop("_wall_s", math.nan)
        log.append(row)
        timings.append({"run": row["run"], "controller": row["controller"], "wall_s": round(wall, 6)})
        bar.update(1)

    try:
        if client is None:
            _execute_synchronous(tasks, run_task, on_result)
        else:
            execute_dask(client, tasks, run_task, IN_FLIGHT_PER_WORKER * _total_threads(client), on_result)
    finally:
        bar.close()
        timings.close()


# --- statistics, summary files, figures ----------------------------------------------------------
def describe(values: np.ndarray, confidence: float = 0.95) -> dict:
    """Mean, sample standard deviation, Student-t confidence interval of the mean, median, 5th and
    95th percentiles and count of the finite values (None where undefined)."""
    from scipy import stats

    x = np.asarray(values, dtype=np.float64)
    x = x[np.isfinite(x)]
    n = int(x.size)
    out: dict[str, Any] = {"count": n, "mean": None, "std": None, "ci95_mean": [None, None],
                           "median": None, "p05": None, "p95": None}
    if n == 0:
        return out
    mean = float(np.mean(x))
    out.update(mean=mean, median=float(np.median(x)), p05=float(np.percentile(x, 5)),
               p95=float(np.percentile(x, 95)))
    if n >= 2:
        std = float(np.std(x, ddof=1))
        half = float(stats.t.ppf(0.5 + confidence / 2, n - 1)) * std / math.sqrt(n)
        out.update(std=std, ci95_mean=[mean - half, mean + half])
    return out


def summarize_campaign(out_dir: str | Path, settings: dict | None = None, new_runs: int = 0,
                       plots: bool = True) -> CampaignSummary:
    """Compute the statistics from ``out_dir/runs.csv`` (sorted by controller order and run index,
    so they do not depend on completion order) and write summary.json, summary.csv and figures."""
    import pandas as pd

    out = Path(out_dir)
    settings = settings if settings is not None else _read_settings(out)
    if settings is None:
        raise ParameterError(f"--out = {str(out)!r}: no campaign.json; not a campaign folder")
    radii = settings["capture_radii_m"]
    controllers = settings["controllers"]
    units = statistic_units(radii)
    rows = read_runs(out / "runs.csv", radii)
    order = {c: k for k, c in enumerate(controllers)}
    rows.sort(key=lambda r: (order.get(r["controller"], len(order)), r["run"]))
    rows = _first_row_per_run(rows)
    table = pd.DataFrame(rows, columns=run_columns(radii))

    statistics, completed = {}, {}
    csv_rows = []
    for c in controllers:
        sub = table[table["controller"] == c]
        ok = sub[sub["completed"].astype(bool)]
        completed[c] = float(len(ok) / len(sub)) if len(sub) else None
        statistics[c] = {}
        for col, unit in units.items():
            d = {"unit": unit, **describe(ok[col].to_numpy(dtype=np.float64))}
            statistics[c][col] = d
            csv_rows.append({"controller": c, "statistic": col, "unit": unit, "count": d["count"],
                             "mean": d["mean"], "std": d["std"], "ci95_low": d["ci95_mean"][0],
                             "ci95_high": d["ci95_mean"][1], "median": d["median"], "p05": d["p05"],
                             "p95": d["p95"], "completed_fraction": completed[c]})
    files = []
    summary = CampaignSummary(out, settings, table, statistics, completed, (), new_runs)
    _write_atomic(out / "summary.json", json.dumps(summary.to_dict(), indent=2) + "\n")
    files.append(out / "summary.json")
    columns = list(csv_rows[0]) if csv_rows else []
    text = _csv_line(columns) + "".join(
        _csv_line("" if r[k] is None else r[k] for k in columns) for r in csv_rows)
    _write_atomic(out / "summary.csv", text)
    files.append(out / "summary.csv")
    if plots and len(table):
        from .plotting.figures import save_figure

        files.append(save_figure(plot_histograms(table, controllers, radii), out / "histograms.png"))
        files.append(save_figure(plot_cdf(table, controllers, radii), out / "cdf.png"))
    return dataclasses.replace(summary, files=tuple(files))


def _first_row_per_run(rows: list[dict]) -> list[dict]:
    """Drop repeated (run, controller) rows, which only copying files by hand could create."""
    seen, unique = set(), []
    for r in rows:
        key = (r["run"], r["controller"])
        if key not in seen:
            seen.add(key)
            unique.append(r)
    return unique


_LABELS = {
    "peak_radial_m": "peak radial displacement [m]",
    "rms_radial_m": "RMS radial displacement [m]",
    "peak_dy_m": "peak lateral displacement |dy| [m]",
    "peak_dz_m": "peak vertical displacement |dz| [m]",
    "peak_u_n": "peak control force [N]",
}


def _completed_values(table, controller: str, column: str) -> np.ndarray:
    sub = table[(table["controller"] == controller) & table["completed"].astype(bool)]
    x = sub[column].to_numpy(dtype=np.float64)
    return x[np.isfinite(x)]


def plot_histograms(table, controllers: Sequence[str], capture_radii_m: Sequence[float]):
    """Histograms of the per-run statistics of completed runs, one colour per controller."""
    from .plotting.figures import new_figure

    panels = ["peak_radial_m", "rms_radial_m", "peak_dy_m", "peak_dz_m"]
    labels = dict(_LABELS)
    for r in capture_radii_m[:2]:
        panels.append(capture_column(r))
        labels[capture_column(r)] = f"time fraction within {r:g} m [-]"
    if any(c != "none" for c in controllers) or len(panels) < 6:
        panels = panels[:5] + ["peak_u_n"]  # without a controller the force is zero: not worth a panel
    fig, axes = new_figure(2, 3, size=(11.0, 6.0))
    for ax, col in zip(axes.flat, panels):
        data = [_completed_values(table, c, col) for c in controllers]
        allx = np.concatenate(data) if data else np.empty(0)
        bins = np.histogram_bin_edges(allx, bins="auto") if allx.size else 10
        for c, x in zip(controllers, data):
            ax.hist(x, bins=bins, alpha=0.6 if len(controllers) > 1 else 0.9, label=f"controller {c}")
        ax.set_xlabel(labels[col])
        ax.set_ylabel("runs [-]")
    axes.flat[0].legend(loc="upper right", fontsize="small")
    seeds = table["run"].nunique()
    fig.suptitle(f"Monte Carlo campaign: {seeds} turbulence seeds, controller " + " vs ".join(controllers))
    return fig


def plot_cdf(table, controllers: Sequence[str], capture_radii_m: Sequence[float]):
    """Empirical CDFs of peak and RMS radial displacement of completed runs, capture radii marked."""
    from .plotting.figures import new_figure

    fig, axes = new_figure(1, 2, size=(10.0, 4.0), sharey=True)
    for ax, col in zip(axes, ("peak_radial_m", "rms_radial_m")):
        for c in controllers:
            x = np.sort(_completed_values(table, c, col))
            if x.size:
                fraction = np.arange(0, x.size + 1) / x.size
                ax.step(np.r_[x[0], x], fraction, where="post", label=f"controller {c}")
        for r in capture_radii_m:
            ax.axvline(r, color="0.4", linestyle="--", linewidth=0.8)
        ax.set_xlabel(_LABELS[col])
    fig.suptitle("Empirical CDF over runs; dashed: capture radii " + ", ".join(f"{r:g} m" for r in capture_radii_m))
    axes[0].set_ylabel("fraction of runs [-]")
    axes[0].legend(loc="lower right", fontsize="small")
    return fig
