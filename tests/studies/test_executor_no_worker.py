"""A campaign on a cluster whose workers are all gone (dead, not restarted) stops in one line with
its finished runs kept, instead of waiting for ever (hosedrogue.studies.executor)."""

import pytest

from hosedrogue.errors import IncompleteError
from hosedrogue.studies import executor


def _double(x):
    return 2 * x


@pytest.mark.dask
def test_no_worker_alive_stops_the_execution(monkeypatch):
    distributed = pytest.importorskip("distributed")
    monkeypatch.setattr(executor, "NO_WORKER_TIMEOUT_S", 3.0)  # the watch polls every 2 s
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        done = []
        with pytest.raises(IncompleteError, match="no dask worker was alive for 3 s"):
            executor.execute_dask(client, iter(range(5)), _double, 2, done.append, on_lost=lambda t, r: None)
        assert done == []  # nothing ran, nothing invented
