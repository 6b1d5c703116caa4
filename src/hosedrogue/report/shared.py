"""What the sections of one report build share: one dask cluster on which every section's campaign
runs execute, and a register of the docking campaigns run so far (a campaign two sections hold,
such as the ideal-force cells of the docking grid and of the actuated drogue, runs once:
:func:`hosedrogue.studies.docking.run_grid`'s ``share``).

The build (:mod:`.build`) opens them in its own process with :func:`shared_resources` before any
section starts and closes them once the last section has ended, however the build ends (an error,
Ctrl-C): the cluster's worker processes do not outlive it. Each process that builds sections (the
build's own, or those of :mod:`.parallel`) enters :func:`attached` with them; a section then asks
:func:`campaign_execution` where its campaigns run and :func:`campaign_share` for the register.
Outside a build (a section's ``build`` called from Python) both answer as before: campaigns on a
local cluster of the section's own, per its settings, and no register.

One cluster instead of one per section: a cluster's start cost 7-8 s of CPU (six per build), and
two sections each with their own two workers put four workers on two cores.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass

__all__ = ["Shared", "cluster_workers", "shared_resources", "attached", "campaign_execution", "campaign_share",
           "children_ignore_interrupts"]


@dataclass(frozen=True)
class Shared:
    """The build's shared resources, as passed to the processes that build sections (picklable).

    Parameters
    ----------
    scheduler : str or None
        Address of the build's dask scheduler; None: no section of the build runs on dask.
    share_dir : str
        The campaign register: a folder that lives as long as the build.
    """

    scheduler: str | None
    share_dir: str


#: This process's attachment: "shared" (Shared) and "client" (its client of the cluster, made on
#: first use), set inside :func:`attached` only.
_ATTACHED: dict = {}


def cluster_workers(chosen, settings) -> int | None:
    """Worker processes of the build's cluster: the most any chosen section's settings ask for
    (``Section.dask``, e.g. ``docking_workers``); None when no chosen section runs on dask.

    Parameters
    ----------
    chosen : sequence of hosedrogue.report.plan.Section
        The sections of the build.
    settings : hosedrogue.report.settings.ReportSettings
        The build's settings.

    Returns
    -------
    int or None
    """
    asked = [getattr(settings, s.dask) for s in chosen if s.dask is not None]
    asked = [w for w in asked if w is not None]
    return max(asked) if asked else None


@contextlib.contextmanager
def children_ignore_interrupts():
    """Processes started inside it ignore Ctrl-C (SIGINT) for their life: a terminal sends it to
    every process of the build, and the build's process alone must act on it (it ends the others),
    or each would print its own traceback. An ignored signal stays ignored in a started program, and
    Python then installs no handler of its own. In this process SIGINT is ignored too while inside
    (the processes start within a few seconds); elsewhere than in the main thread nothing changes.
    """
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, before)


@contextlib.contextmanager
def shared_resources(workers: int | None):
    """The build's cluster (``workers`` single-threaded worker processes; none for None) and campaign
    register, closed and removed on exit, also on an error or KeyboardInterrupt.

    Parameters
    ----------
    workers : int or None
        Worker processes (:func:`cluster_workers`).

    Yields
    ------
    Shared
    """
    import os
    import shutil
    import tempfile

    from ..studies import executor

    share = tempfile.mkdtemp(prefix="hosedrogue-report-campaigns-")
    owned = []
    try:
        if workers is not None:
            environ = dict(os.environ)
            try:
                with children_ignore_interrupts():
                    cluster, client = executor.local_cluster(workers)
            finally:
                # dask's nannies put their workers' environment into this process's (OMP_NUM_THREADS=1
                # and the other thread counts, PYTHONHASHSEED): the section processes started after
                # it must not inherit it (single-threaded BLAS changed the last digit of an eigenvalue
                # of the actuated drogue's servo margins)
                os.environ.clear()
                os.environ.update(environ)
            owned = [client, cluster]
        yield Shared(owned[1].scheduler_address if owned else None, share)
    finally:
        try:
            for thing in owned:
                thing.close()
        finally:
            shutil.rmtree(share, ignore_errors=True)


@contextlib.contextmanager
def attached(shared: Shared | None):
    """Inside it, this process's sections run their campaigns on ``shared``'s cluster and register
    them in its folder; the client made for it is closed on exit.

    Parameters
    ----------
    shared : Shared or None
        What the build opened (None: nothing shared; the sections run as outside a build).
    """
    if shared is None:
        yield
        return
    _ATTACHED.clear()
    _ATTACHED["shared"] = shared
    try:
        yield
    finally:
        client = _ATTACHED.pop("client", None)
        _ATTACHED.clear()
        if client is not None:
            client.close()


def campaign_execution(workers: int | None) -> dict:
    """Where a section's campaigns run, as keyword arguments of the study that runs them: the build's
    cluster (``{"client": ...}``) when the section's settings ask for dask workers and this process
    is attached to a build that has one; else ``{"workers": workers}`` (None: in this process).

    Parameters
    ----------
    workers : int or None
        The section's setting (e.g. ``ReportSettings.docking_workers``).

    Returns
    -------
    dict
    """
    shared = _ATTACHED.get("shared")
    if workers is None or shared is None or shared.scheduler is None:
        return {"workers": workers}
    if _ATTACHED.get("client") is None:
        from ..studies.executor import connect

        _ATTACHED["client"] = connect(shared.scheduler)
    return {"client": _ATTACHED["client"]}


def campaign_share() -> str | None:
    """The build's campaign register (a folder), or None outside a build."""
    shared = _ATTACHED.get("shared")
    return None if shared is None else shared.share_dir
