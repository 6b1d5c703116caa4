"""The report build's one dask cluster and campaign register (hosedrogue.report.shared): which
builds start a cluster, where a section's campaigns run inside and outside a build, and that the
cluster's processes and the register end with the build however it ends (an error, Ctrl-C)."""

from __future__ import annotations

import os
import time
from pathlib import Path

import pytest

from hosedrogue.report import shared
from hosedrogue.report.plan import Section, sections_for
from hosedrogue.report.settings import FAST, FULL


def test_a_cluster_only_for_builds_whose_sections_run_campaigns_on_dask():
    assert shared.cluster_workers(sections_for(None), FULL) == FULL.docking_workers == 2
    assert shared.cluster_workers(sections_for(["manoeuvres"]), FULL) == FULL.manoeuvre_workers
    assert shared.cluster_workers(sections_for(None), FAST) is None  # the fast build runs its campaigns in-process
    assert shared.cluster_workers(sections_for(["parameters", "sweep"]), FULL) is None


def test_outside_a_build_a_section_runs_its_campaigns_as_its_settings_say():
    assert shared.campaign_execution(2) == {"workers": 2}
    assert shared.campaign_execution(None) == {"workers": None}
    assert shared.campaign_share() is None
    with shared.attached(shared.Shared(None, "/nowhere")):  # a build without a cluster
        assert shared.campaign_execution(2) == {"workers": 2}
        assert shared.campaign_share() == "/nowhere"
    assert shared.campaign_share() is None


def _children() -> list:
    """This process's descendants but multiprocessing's resource tracker (started by the first
    process spawned, it lives as long as this process, whatever else ends)."""
    import psutil

    found = []
    for p in psutil.Process().children(recursive=True):
        try:
            if "resource_tracker" not in " ".join(p.cmdline()):
                found.append(p)
        except psutil.NoSuchProcess:  # ended between the listing and the look
            continue
    return found


@pytest.mark.dask
@pytest.mark.parametrize("error", [RuntimeError, KeyboardInterrupt])
def test_the_builds_cluster_ends_with_the_build_however_it_ends(tmp_path, monkeypatch, error):
    """A section of a build (one process) finds the build's cluster of two workers and its register;
    when it fails, or the user presses Ctrl-C, the error reaches the caller and no process of the
    cluster is left, nor the register."""
    pytest.importorskip("distributed")
    import hosedrogue.report.build as build

    seen = {}
    before = {p.pid for p in _children()}
    environ = dict(os.environ)

    def section(out, settings):
        # dask's nannies write their workers' thread counts into the environment of the process that
        # starts them: processes spawned after (the sections') must not get single-threaded BLAS
        seen["environ"] = dict(os.environ) == environ
        client = shared.campaign_execution(settings.docking_workers)["client"]
        seen["threads"] = sum(client.nthreads().values())
        seen["share"] = Path(shared.campaign_share())
        seen["alive"] = seen["share"].is_dir() and len(_children()) > len(before)
        raise error("stopped")

    monkeypatch.setattr(build, "sections_for", lambda only: (Section("docking", "a campaign", section,
                                                                     dask="docking_workers"),))
    with pytest.raises(error, match="stopped"):
        build.build_report(tmp_path / "r", progress=False, workers=1)
    assert seen["threads"] == FULL.docking_workers and seen["alive"] and seen["environ"]
    deadline = time.monotonic() + 30.0  # a worker process may take a moment to be reaped after its nanny closed it
    while {p.pid for p in _children()} - before and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not [p.cmdline() for p in _children() if p.pid not in before]
    assert not seen["share"].exists()


@pytest.mark.dask
@pytest.mark.subprocess
def test_ctrl_c_ends_every_process_of_a_build_on_two_processes(tmp_path):
    """``hosedrogue reproduce`` on two processes, interrupted as a terminal does (SIGINT to its
    process group) once its cluster's workers and its section processes run: exit 130 with one line
    on stderr and no traceback, and none of the processes it started is left running. The command
    starts with SIGINT as a shell gives it, neither ignored nor blocked: a child inherits both from the
    test's process, and in a full ``make test`` the build once ran to its end, untouched by the signal."""
    import signal
    import subprocess
    import sys
    import threading

    psutil = pytest.importorskip("psutil")
    pytest.importorskip("distributed")
    import hosedrogue

    src = str(Path(hosedrogue.__file__).parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [src, os.environ.get("PYTHONPATH")]))}
    argv = [sys.executable, "-m", "hosedrogue", "reproduce", "--only", "receiver", "manoeuvres", "--workers", "2",
            "--out", str(tmp_path / "r")]

    def as_a_shell_starts_it():
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
        signal.signal(signal.SIGINT, signal.SIG_DFL)

    proc = subprocess.Popen(argv, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                            preexec_fn=as_a_shell_starts_it)
    # stderr read as it comes: the build says "groups of sections on 2 processes" once its cluster runs
    # and it starts the section processes; before that (the cluster's start, seconds; longer on a cold
    # numba cache) Ctrl-C is ignored by design (report/shared.py, children_ignore_interrupts)
    chunks: list = []
    reader = threading.Thread(target=lambda: chunks.extend(iter(lambda: proc.stderr.read1(4096), b"")), daemon=True)
    reader.start()
    seen: dict = {}
    deadline = time.monotonic() + 300.0  # the cluster and two section processes start: seconds when idle
    try:
        while time.monotonic() < deadline and proc.poll() is None and b"groups of sections" not in b"".join(chunks):
            for p in psutil.Process(proc.pid).children(recursive=True):
                seen.setdefault(p.pid, p)
            time.sleep(0.2)
        assert b"groups of sections" in b"".join(chunks), b"".join(chunks).decode()
        settle = time.monotonic() + 2.0  # the section processes under way
        while time.monotonic() < settle:
            for p in psutil.Process(proc.pid).children(recursive=True):
                seen.setdefault(p.pid, p)
            time.sleep(0.2)
        # two dask workers, two section processes and multiprocessing's resource tracker
        assert len(seen) >= 5, [p.pid for p in seen.values()]
        with open(f"/proc/{proc.pid}/status") as f:  # the build's own SIGINT: caught, not ignored or blocked
            status = dict(line.split(":\t", 1) for line in f.read().splitlines() if ":\t" in line)
        mask = 1 << (signal.SIGINT - 1)
        assert int(status["SigCgt"], 16) & mask and not int(status["SigIgn"], 16) & mask, status
        assert not int(status["SigBlk"], 16) & mask, status
        os.killpg(proc.pid, signal.SIGINT)
        proc.wait(timeout=120.0)
        reader.join(timeout=10.0)
    finally:
        if proc.poll() is None:
            proc.kill()
    err = b"".join(chunks)
    assert proc.returncode == 130, err.decode()
    assert err.decode().rstrip().endswith("hosedrogue: interrupted") and b"Traceback" not in err
    gone = time.monotonic() + 30.0  # the resource tracker ends when it sees its parent gone
    while any(p.is_running() for p in seen.values()) and time.monotonic() < gone:
        time.sleep(0.2)
    assert not [p.cmdline() for p in seen.values() if p.is_running()]
