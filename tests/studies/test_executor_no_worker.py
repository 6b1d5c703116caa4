"""A campaign on a cluster whose workers are all gone (dead, not restarted) stops in one line with
its finished runs kept, instead of waiting for ever (hosedrogue.studies.executor)."""

import pytest

from hosedrogue.errors import IncompleteError
from hosedrogue.studies import executor


#: The no-worker timeout set in these tests [s]: the watch's poll (_NoWorkerWatchdog, every 2 s), so
#: with no worker alive it fires 2 to 4 s after the last one died.
NO_WORKER_S = 2.0


def _double(x):
    return 2 * x


@pytest.mark.dask
def test_no_worker_alive_stops_the_execution(monkeypatch):
    distributed = pytest.importorskip("distributed")
    # 2 s, the watch's poll: it fires on the second poll that sees no worker (a timeout of 3 s needs a
    # third poll, 2 s of idle wall time more, for the same one-line stop)
    monkeypatch.setattr(executor, "NO_WORKER_TIMEOUT_S", NO_WORKER_S)
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        done = []
        with pytest.raises(IncompleteError, match=f"no dask worker was alive for {NO_WORKER_S:g} s"):
            executor.execute_dask(client, iter(range(5)), _double, 2, done.append, on_lost=lambda t, r: None)
        assert done == []  # nothing ran, nothing invented


def _kill_first(path):
    """A task that ends its worker's process the first time any task runs (``path`` records it),
    then returns 1: user code that killed its worker, once."""
    import os

    if not os.path.exists(path):
        open(path, "w").close()
        os._exit(1)
    return 1


#: Imported by each worker process before it registers with the scheduler (a dask preload; dask may
#: import it more than once in a process): its first process starts normally, a restart sleeps (a slow start on a loaded machine) or fails (a worker
#: that cannot come back), as the environment says.
PRELOAD = '''import os, time
started = os.environ["HOSEDROGUE_TEST_STARTED"]
if os.path.exists(started) and open(started).read() != str(os.getpid()):  # another process started first
    if os.environ["HOSEDROGUE_TEST_RESTART"] == "fail":
        raise RuntimeError("this worker cannot start again")
    time.sleep(float(os.environ["HOSEDROGUE_TEST_RESTART"]))
else:
    open(started, "w").write(str(os.getpid()))
'''


def _one_nanny_cluster(monkeypatch, tmp_path, restart):
    """The package's local cluster of one worker process (executor.local_cluster), its worker
    importing :data:`PRELOAD` as it starts."""
    import dask

    preload = tmp_path / "slow_restart.py"
    preload.write_text(PRELOAD)
    monkeypatch.setitem(executor.WORKER_ENVIRON, "HOSEDROGUE_TEST_STARTED", str(tmp_path / "started"))
    monkeypatch.setitem(executor.WORKER_ENVIRON, "HOSEDROGUE_TEST_RESTART", restart)
    with dask.config.set({"distributed.worker.preload": [str(preload)]}):  # the nannies pass it to their workers
        return executor.local_cluster(1)


@pytest.mark.dask
def test_a_worker_restarting_slower_than_the_timeout_is_waited_for(monkeypatch, tmp_path):
    """The nanny restarts the worker a task killed; the new worker takes over 6 s to register (its
    preload sleeps 6 s), longer than the at most 4 s after which the watch (2 s timeout, 2 s poll)
    would stop a campaign that had no worker: its process is alive, so the campaign waits and
    every task runs (each of the three once, the killer again after the restart)."""
    pytest.importorskip("distributed")
    monkeypatch.setattr(executor, "NO_WORKER_TIMEOUT_S", NO_WORKER_S)
    cluster, client = _one_nanny_cluster(monkeypatch, tmp_path, "6")
    with cluster, client:
        done = []
        tasks = iter([str(tmp_path / "killed")] * 3)
        executor.execute_dask(client, tasks, _kill_first, 1, done.append, on_lost=lambda t, r: done.append(r))
        assert done == [1, 1, 1]
        assert (tmp_path / "killed").exists()  # the worker was killed and restarted


@pytest.mark.dask
def test_a_worker_that_cannot_come_back_still_stops_the_execution(monkeypatch, tmp_path):
    """The same kill with a restart that fails: no worker process is left, so after the timeout
    the execution stops in one line."""
    pytest.importorskip("distributed")
    monkeypatch.setattr(executor, "NO_WORKER_TIMEOUT_S", NO_WORKER_S)
    cluster, client = _one_nanny_cluster(monkeypatch, tmp_path, "fail")
    with cluster, client:
        done = []
        with pytest.raises(IncompleteError, match=f"no dask worker was alive for {NO_WORKER_S:g} s"):
            executor.execute_dask(client, iter([str(tmp_path / "killed")] * 3), _kill_first, 1, done.append,
                                  on_lost=lambda t, r: done.append(r))
        assert done == [] and not executor.workers_alive(client)
