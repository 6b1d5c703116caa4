"""Where a campaign's runs execute: a dask cluster (local or remote) or this process.

Work is submitted lazily with a bound on the tasks in flight (:func:`execute_dask`), so a campaign
of any length needs the memory of a few hundred runs: each task returns small results, passed to
``on_result`` at once and forgotten. A dask task carries a batch of the caller's tasks, as many as
run in about :data:`BATCH_S` (measured on those that finished), so dask's own cost per task is a
few per cent of the work however short each run is.
"""

from __future__ import annotations

import contextlib
import os
from typing import Callable, Iterator

from ..errors import IncompleteError, ParameterError

#: The scheduler value that runs every simulation in this process, without dask.
SYNCHRONOUS = "synchronous"

#: Tasks in flight per worker thread: enough to keep workers busy while the client writes results.
IN_FLIGHT_PER_WORKER = 4

#: Work per dask task [s] that :func:`execute_dask` aims at. Dask's own cost is about 13 ms of CPU
#: per task over client, scheduler and worker (measured 2026-12-03 with 2 local workers: 23 ms
#: docking runs took 36 ms each one per task), so 0.25 s of runs per task keeps it near 5 %; short
#: enough that a campaign's last tasks end within a quarter of a second of each other.
BATCH_S = 0.25

#: Largest number of the caller's tasks in one dask task (it bounds the results held in flight).
MAX_BATCH = 16


def run_batch(fn: Callable, tasks: list) -> tuple[list, float, Exception | None]:
    """Run ``fn`` on each task in order (on a worker): the results, the wall time [s] and the error
    that stopped the batch (None: every task ran; the results are those before it).

    Parameters
    ----------
    fn : callable
        The work of one task (a campaign's run).
    tasks : list
        The batch's tasks, run in this order.
    """
    import time

    t0 = time.perf_counter()
    results = []
    try:
        for task in tasks:
            results.append(fn(task))
    except Exception as exc:  # passed back with the results before it, raised by the caller
        return results, time.perf_counter() - t0, exc
    return results, time.perf_counter() - t0, None


def execute_dask(client, tasks: Iterator, fn: Callable, max_in_flight: int, on_result: Callable,
                 on_lost: Callable | None = None) -> int:
    """Run ``fn(task)`` for every task on a dask client, at most ``max_in_flight`` dask tasks at a
    time, calling ``on_result(result)`` in completion order.

    Each dask task runs a batch of consecutive tasks (:func:`run_batch`): one at first, then as many
    as ran in :data:`BATCH_S` on average so far (at most :data:`MAX_BATCH`). What each task
    computes does not depend on the batching, only when its result arrives.

    A task whose worker died under it on every try (dask's ``KilledWorker``: user code that ended
    its process, ``os._exit`` or a crash; every task of its batch) is tried once more alone at the
    end (a task queued on the worker of one that killed it is innocent), and if its worker dies
    again goes to ``on_lost(task, reason)``; the others go on. Without ``on_lost`` it ends the execution as any
    other error does.

    A lost scheduler raises :class:`~hosedrogue.errors.IncompleteError` (one line; exit 3 on the
    command line) after the results already passed to ``on_result`` are kept.
    On any other error (including KeyboardInterrupt) the outstanding tasks are cancelled and the error
    propagates; results already passed to ``on_result`` stay (those of the failing task's batch
    before it among them).

    Parameters
    ----------
    client : distributed.Client
        Where the tasks run.
    tasks : iterator
        The tasks, consumed lazily.
    fn : callable
        ``fn(task) -> result``, picklable.
    max_in_flight : int
        Largest number of submitted, unfinished dask tasks (batches).
    on_result : callable
        Called with each result in this process.
    on_lost : callable, optional
        ``on_lost(task, reason)``: called in this process for a task whose worker died (``reason``
        one line).

    Returns
    -------
    int
        The largest number of dask tasks that were in flight at once.
    """
    from concurrent.futures import CancelledError

    from distributed import KilledWorker, as_completed
    from distributed.comm.core import CommClosedError

    pending = iter(tasks)
    outstanding: dict = {}  # future -> its batch of tasks
    suspects: list = []  # tasks whose worker died while they ran or waited on it
    queue = as_completed()
    peak = 0
    ran = [0, 0.0]  # tasks finished in batches, their wall time [s]

    def submit_next() -> None:
        nonlocal peak
        size = 1 if ran[0] == 0 else max(1, min(MAX_BATCH, int(BATCH_S * ran[0] / max(ran[1], 1e-9))))
        batch = [task for _, task in zip(range(size), pending)]
        if batch:
            future = client.submit(run_batch, fn, batch, pure=False)
            outstanding[future] = batch
            queue.add(future)
            peak = max(peak, len(outstanding))

    for _ in range(max_in_flight):
        submit_next()
    watchdog = _NoWorkerWatchdog(client, outstanding)
    try:
        for future in queue:
            batch = outstanding.pop(future)
            try:
                results, wall_s, error = future.result()
            except KilledWorker:
                if on_lost is None:
                    raise
                suspects.extend(batch)  # or a task beside it killed the worker: each tried again alone below
            else:
                for result in results:
                    on_result(result)
                if error is not None:
                    raise error
                ran[0], ran[1] = ran[0] + len(batch), ran[1] + wall_s
            future.release()
            submit_next()
        for task in suspects:  # one at a time: a worker that dies now died of this task
            future = client.submit(fn, task, pure=False)
            outstanding[future] = task
            try:
                result = future.result()
            except KilledWorker:
                on_lost(task, "the worker process running it died on every try (dask KilledWorker)")
            else:
                on_result(result)
            del outstanding[future]
            future.release()
    except (CancelledError, CommClosedError) as exc:
        if watchdog.fired:
            raise IncompleteError(f"no dask worker was alive for {NO_WORKER_TIMEOUT_S:g} s (they died and were not "
                                  "restarted); the finished runs are kept: run the same command again to resume") from None
        # a lost scheduler shows up as cancelled futures or, while a result is fetched, as a
        # closed connection; anything else cancelled is not ours to explain
        if isinstance(exc, CancelledError) and getattr(exc, "reason", None) != "scheduler-connection-lost":
            client.cancel(list(outstanding))
            raise
        _close_quietly(client)
        raise IncompleteError("the dask scheduler went away (connection lost); the finished runs are kept: "
                              "run the same command again with a reachable scheduler to resume") from None
    except BaseException:
        client.cancel(list(outstanding))
        raise
    finally:
        watchdog.stop()
    return peak


#: How long a campaign waits with no dask worker alive before it stops, its finished runs kept [s].
#: On a cluster this process made, a worker process that its nanny restarted counts as alive while
#: it starts (:func:`workers_alive`), up to :data:`LOST_WORKER_TIMEOUT_S`; on a remote scheduler only
#: registered workers are seen, and a worker restarted there must register within it.
NO_WORKER_TIMEOUT_S = 120.0


def workers_alive(client) -> bool:
    """Whether the client's cluster has a worker: one registered with the scheduler or, on a
    cluster of this process (``client.cluster``, a LocalCluster: its nannies), a worker process
    alive that has not registered yet (its nanny restarting it after user code killed the last
    one: a restart took more than 15 s under a load of 14 on two cores).

    Parameters
    ----------
    client : distributed.Client
        The client.

    Returns
    -------
    bool
    """
    if client.nthreads():
        return True
    cluster = getattr(client, "cluster", None)
    for nanny in list(getattr(cluster, "workers", {}).values()):  # LocalCluster: name -> Nanny (or Worker)
        try:
            if getattr(nanny, "is_alive", lambda: False)():  # Nanny.is_alive: its worker process runs
                return True
        except AttributeError:  # the process was released between the nanny's two reads: not alive
            continue
    return False


class _NoWorkerWatchdog:
    """Cancels the outstanding futures when the cluster has had no worker for
    :data:`NO_WORKER_TIMEOUT_S` (every worker died and none is being restarted:
    :func:`workers_alive`), so a campaign waiting on them stops instead of waiting for ever;
    :attr:`fired` tells why they were cancelled."""

    def __init__(self, client, outstanding: dict, poll_s: float = 2.0):
        import threading

        self.fired = False
        self._client, self._outstanding, self._poll_s = client, outstanding, poll_s
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._watch, name="hosedrogue-no-worker-watchdog", daemon=True)
        self._thread.start()

    def _watch(self) -> None:
        import time

        since = None
        while not self._stop.wait(self._poll_s):
            try:
                alive = workers_alive(self._client)
            except Exception:  # a lost scheduler: the main loop says so
                return
            now = time.monotonic()
            since = None if alive else (now if since is None else since)
            if since is not None and now - since >= NO_WORKER_TIMEOUT_S:
                self.fired = True
                self._client.cancel(list(self._outstanding))
                return

    def stop(self) -> None:
        """End the watch (the execution finished or failed)."""
        self._stop.set()


def _close_quietly(client) -> None:
    """Close a client whose scheduler is gone without its reconnection attempts printing
    tracebacks (the error must stay one line)."""
    import logging

    quiet = logging.getLogger("distributed.client")
    level = quiet.level
    quiet.setLevel(logging.CRITICAL)
    try:
        client.close()
    finally:
        quiet.setLevel(level)


def execute_synchronous(tasks: Iterator, fn: Callable, on_result: Callable) -> None:
    """Run ``fn(task)`` for every task in this process, calling ``on_result(result)`` in order.

    Parameters
    ----------
    tasks : iterator
        The tasks.
    fn : callable
        ``fn(task) -> result``.
    on_result : callable
        Called with each result.
    """
    for task in tasks:
        on_result(fn(task))


def dask_available() -> bool:
    """Whether dask.distributed can be imported."""
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


def local_cluster(workers: int):
    """A LocalCluster of single-threaded worker processes (environment :data:`WORKER_ENVIRON`).

    A worker that dies (user code that ended its process) is restarted by its nanny; the cluster
    waits :data:`LOST_WORKER_TIMEOUT_S` for it to register again before closing the nanny: this
    raises dask's ``distributed.deploy.lost-worker-timeout`` (15 s, read when a worker is lost) to
    that for the rest of the process, since a restarted worker importing the package on a loaded
    machine took longer than 15 s and the campaign then lost its last worker.

    Parameters
    ----------
    workers : int
        Number of worker processes, >= 1.

    Returns
    -------
    (distributed.LocalCluster, distributed.Client)
        The cluster and a client of it; the caller closes both.
    """
    import logging

    import dask
    from distributed import Client, LocalCluster

    # logs at CRITICAL only: a task's error reaches the client, which ends in one line or records the
    # run's failure (a worker's "Compute Failed" traceback or the scheduler's report of a worker that
    # died would only repeat it on the terminal)
    key = "distributed.deploy.lost-worker-timeout"
    if dask.utils.parse_timedelta(dask.config.get(key, "15s")) < LOST_WORKER_TIMEOUT_S:
        dask.config.set({key: f"{LOST_WORKER_TIMEOUT_S:g}s"})  # for the cluster's life: read at each loss
    with dask.config.set({**LOCAL_SCHEDULER_CONFIG, **LOCAL_QUIET_CONFIG}):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               silence_logs=logging.CRITICAL, env=dict(WORKER_ENVIRON), **_NO_DASHBOARD)
    return cluster, Client(cluster)


#: A local cluster's scheduler gives a task whose worker died one more try (a passing fault), not
#: dask's three: its workers are alike, and a run whose user code ends its process would end each.
LOCAL_SCHEDULER_CONFIG = {"distributed.scheduler.allowed-failures": 1}

#: A local cluster's processes do no bookkeeping nobody reads: no statistical profiler sampling the
#: workers every 10 ms (it serves the dashboard, which is off), the event loops' health tick and the
#: memory and system monitors at 1-2 s instead of 20-500 ms. Measured 2026-12-03 on 150 docking runs
#: (2 workers): 2.2 s less CPU, about 1.5 ms per run.
LOCAL_QUIET_CONFIG = {"distributed.worker.profile.enabled": False, "distributed.admin.tick.interval": "1s",
                      "distributed.worker.memory.monitor-interval": "1s",
                      "distributed.admin.system-monitor.interval": "2s"}

#: How long a local cluster waits for a lost worker's nanny to bring it back before closing the
#: nanny [s] (dask's default, 15 s, is less than a worker's start under a load of 14 on two cores).
#: While it waits, the restart counts as a worker alive (:func:`workers_alive`).
LOST_WORKER_TIMEOUT_S = 600.0



def connect(scheduler: str):
    """A client of a running dask scheduler.

    Parameters
    ----------
    scheduler : str
        Its address, e.g. ``tcp://host:8786``; waits at most :data:`CONNECT_TIMEOUT_S` [s].

    Returns
    -------
    distributed.Client
        ParameterError when the scheduler cannot be reached.
    """
    from distributed import Client

    try:
        return Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S}s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise ParameterError(f"scheduler = {scheduler!r}: cannot connect ({exc})") from None


def total_threads(client) -> int:
    """Worker threads of a dask client's cluster.

    Parameters
    ----------
    client : distributed.Client
        The client.

    Returns
    -------
    int
        Total threads over the workers, at least 1.
    """
    return max(1, sum(client.nthreads().values()))


@contextlib.contextmanager
def dask_client(client, workers: int | None, scheduler: str | None, needed: bool):
    """Context manager giving the dask client to run on.

    Parameters
    ----------
    client : distributed.Client or None
        A client to use as is (not closed here).
    workers : int, optional
        Worker processes of a new LocalCluster (default ``min(2, os.cpu_count())``).
    scheduler : str, optional
        Address of a running scheduler to connect to instead.
    needed : bool
        False: yield None (nothing to run on dask).

    Yields
    ------
    distributed.Client or None
        ``client``; else a new client (closed, with its cluster, on exit); None when not needed.
    """
    if not needed or client is not None:
        yield client
        return
    if scheduler is not None:
        owned = [connect(scheduler)]
    else:
        cluster, new_client = local_cluster(workers or min(2, os.cpu_count() or 1))
        owned = [new_client, cluster]
    try:
        yield owned[0]
    finally:
        for thing in owned:
            thing.close()


