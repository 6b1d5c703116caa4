"""Processes that start together on a cold cache compile each of the package's functions once
(hosedrogue.jit.CompileOnceCache): the one that takes a signature's lock compiles it, the other
waits and loads what the first saved.

Two fresh processes import a small compiled module added to a copy of the package, wait at a
barrier (a file) and call its function at the same moment with an empty ``NUMBA_CACHE_DIR``. Each
prints its cache misses (compiled here) and hits (loaded from disk). The control runs the same
with numba's own cache put back (``numba.core.dispatcher.FunctionCache``): there both compile,
which shows the two calls really overlap and the test can fail.
"""

import shutil
import subprocess
import sys
import textwrap
import time

import pytest

from hosedrogue.jit import PACKAGE_DIR

pytestmark = pytest.mark.subprocess

MODULE = textwrap.dedent("""\
    from numba import njit

    from ..jit import JIT

    @njit(**JIT)
    def work(n):
        acc = 0.0
        for i in range(n):
            acc += (i % 7) * 0.5 - (i % 3) * 0.25
        return acc

    @njit(**JIT)
    def broken(x):
        return x.no_such_attribute  # a typing error: numba refuses to compile it
""")

SCRIPT = textwrap.dedent("""\
    import os, sys, time
    if sys.argv[2] == "numba":  # the control: numba's own cache, no lock
        import numba.core.caching, numba.core.dispatcher
        import hosedrogue.jit
        numba.core.dispatcher.FunctionCache = numba.core.caching.FunctionCache
    from hosedrogue.model._compile_once import broken, work
    open(sys.argv[1] + "." + str(os.getpid()), "w").close()  # ready
    while not os.path.exists(sys.argv[1]):
        time.sleep(0.001)
    if sys.argv[3] == "broken":
        for attempt in range(2):  # the lock of a failed compile is released: the second attempt compiles again
            try:
                broken(1.0)
            except Exception as exc:
                print(type(exc).__name__, end=" ")
        sys.exit(0)
    work(10)
    print(sum(work.stats.cache_misses.values()), sum(work.stats.cache_hits.values()))
""")


def _race(tmp_path, kind, function="work", tag=""):
    """Two processes calling ``function`` together on an empty cache: each one's output."""
    src = tmp_path / "src"
    if not src.exists():
        shutil.copytree(PACKAGE_DIR, src / "hosedrogue", ignore=shutil.ignore_patterns("__pycache__"))
        (src / "hosedrogue" / "model" / "_compile_once.py").write_text(MODULE)
    cache = tmp_path / f"cache-{kind}{tag}"
    go = tmp_path / f"go-{kind}{tag}"
    env = {"PATH": "/usr/bin:/bin", "PYTHONPATH": str(src), "NUMBA_CACHE_DIR": str(cache)}
    procs = [subprocess.Popen([sys.executable, "-c", SCRIPT, str(go), kind, function], env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(2)]
    deadline = time.monotonic() + 120.0
    while len(list(tmp_path.glob(f"{go.name}.*"))) < 2 and time.monotonic() < deadline:
        time.sleep(0.01)  # both imported and polling the barrier
    go.touch()
    out = [p.communicate(timeout=120) for p in procs]
    for p, (so, se) in zip(procs, out):
        assert p.returncode == 0, se
    return [so.split() for so, _ in out]


def test_processes_started_together_compile_a_function_once(tmp_path):
    counts = _race(tmp_path, "package")
    assert sorted(counts) == [["0", "1"], ["1", "0"]]  # one compiled (a miss), the other loaded it (a hit)


def test_control_numba_cache_alone_compiles_in_both(tmp_path):
    # on a loaded machine one process can be scheduled after the other has saved its entry (then
    # it loads it, as with the lock): up to three races, one of which must show both compiling
    races = []
    for i in range(3):
        races.append(_race(tmp_path, "numba", tag=str(i)))
        if races[-1] == [["1", "0"], ["1", "0"]]:
            break
    assert races[-1] == [["1", "0"], ["1", "0"]], races


def test_a_failed_compile_leaves_no_lock_behind(tmp_path):
    # each process fails twice and ends: neither waits for a lock the failure left taken
    assert _race(tmp_path, "package", "broken") == [["TypingError", "TypingError"]] * 2
