"""Shared fixtures. Tests compare independent formulations and invariants; every tolerance
states its physical reason where it is used."""

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from hosedrogue.spec.params import PAPER


@pytest.fixture
def rng():
    return np.random.default_rng(20180371)


def free_stream(params=PAPER, **sections):
    """Parameters with the tanker wake off (uniform free stream), plus overrides."""
    sections.setdefault("wake", {})
    sections["wake"] = {**sections["wake"], "enabled": False}
    return params.replace(**sections)


@pytest.fixture
def default_sigint():
    """Python's default SIGINT handler for the test, as the ``hosedrogue`` command's own process has
    it (a pytest-xdist worker ignores SIGINT): a test of how user code's KeyboardInterrupt is told
    from the user's Ctrl-C (hosedrogue.controllers.sampled.CtrlC) runs the command as it runs."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signal handlers can be set in the main thread only")
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


# --- the fast report, built once per session for every test of tests/report that reads it ---------
# The end-to-end test needs every section; the section tests (Table 3, the engagement, the
# manoeuvres, the receiver) each need one and those it declares in ``needs``. Building each again for
# its own test repeated about 30 s of the end-to-end build's CPU (2026-12-03), so one build serves
# them all: ``build_report(fast=True)`` itself, of every section when the end-to-end test runs in this
# session, else of the sections the selected tests read (``only``, as ``reproduce --only`` builds
# them). Each section is built by its own ``build`` with the same settings and the same earlier
# results either way (hosedrogue.report.plan.run_section); the fixture only watches those calls and
# keeps, per section, its result, the HTML it added and the report folder.

#: The tests (in tests/report) that read the shared build -> the sections they read (None: all).
FAST_REPORT_READERS = {
    "test_fast_report_end_to_end": None,
    "test_paper_pid_reproduces_table3_on_the_papers_models": ("controllers",),
    "test_table3_section_shows_the_loop_margins": ("controllers",),
    "test_papers_lqr_reproduces_table3_lateral_row_on_the_papers_models": ("controllers",),
    "test_engagement_section_alone_marks_the_fast_runs": ("engagement",),
    "test_manoeuvres_section_alone": ("manoeuvres",),
    "test_receiver_section_alone": ("receiver",),
}


def _reads_fast_report(nodeid: str) -> bool:
    return nodeid.startswith("tests/report/") and nodeid.split("::")[-1].split("[")[0] in FAST_REPORT_READERS


@pytest.hookimpl(optionalhook=True)  # a hook of pytest-xdist: no error without it (-p no:xdist)
def pytest_xdist_make_scheduler(config, log):
    """Under ``-n`` with xdist's default distribution (load): the same, but the readers of the shared
    fast report are one unit, run on one worker, so the report is built once. (xdist's own
    ``--dist loadgroup`` would do it from ``xdist_group`` marks, but with pytest 9.2 its node-id
    suffix no longer takes effect: pytest-xdist issue 1386; tests are then spread as by load.)"""
    if config.getoption("dist") != "load":  # a distribution the user chose: theirs
        return None
    from xdist.scheduler import LoadGroupScheduling

    class FastReportScheduling(LoadGroupScheduling):
        def _split_scope(self, nodeid):
            return "fast_report" if _reads_fast_report(nodeid) else super()._split_scope(nodeid)

    return FastReportScheduling(config, log)


@dataclass
class FastReport:
    """What one ``build_report(fast=True)`` wrote and what its sections' builds returned.

    Attributes
    ----------
    dir : Path
        The report folder.
    headline : dict
        ``build_report``'s return (report.json).
    folder : hosedrogue.report.writer.ReportFolder
        The build's folder object: ``headline`` and ``sections`` as the sections added them.
    results : dict
        Section key -> what its ``build`` returned.
    html : dict
        Section key -> the HTML of the page sections its ``build`` added, in order.
    """

    dir: Path
    headline: dict
    folder: object
    results: dict = field(default_factory=dict)
    html: dict = field(default_factory=dict)


def _sections_read(session):
    """The sections the selected tests read (None: all of them)."""
    wanted = [FAST_REPORT_READERS[item.originalname] for item in session.items
              if _reads_fast_report(item.nodeid.split("@")[0])]
    if not wanted or any(w is None for w in wanted):
        return None
    return sorted({key for keys in wanted for key in keys})


@pytest.fixture(scope="session")
def fast_report(request, tmp_path_factory) -> FastReport:
    import matplotlib.pyplot as plt

    from hosedrogue.report import build as build_module

    path = tmp_path_factory.mktemp("fast_report")
    seen = {"results": {}, "html": {}}
    original = build_module.run_section

    def watched(section, out, settings, results):
        before = len(out.sections)
        original(section, out, settings, results)
        seen["folder"] = out
        seen["results"][section.key] = results[section.key]
        seen["html"][section.key] = [s.html for s in out.sections[before:]]

    plt.close("all")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(build_module, "run_section", watched)
        headline = build_module.build_report(path, fast=True, progress=False, only=_sections_read(request.session))
    # tests/report/test_report.py's check that no pyplot figure is ever created, on the build itself
    # (it ran inside the end-to-end test before the build was shared)
    assert plt.get_fignums() == [], "the build created a pyplot figure"
    return FastReport(path, headline, seen["folder"], seen["results"], seen["html"])
