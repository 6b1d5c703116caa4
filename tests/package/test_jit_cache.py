"""The compiled functions' disk cache cannot run stale code (hosedrogue.jit): editing a callee in
another module recompiles its cached callers.

numba keys a cached function on its own file's source, but the cached machine code holds every
callee: the hazard is real (the control below shows numba's own locator running the old callee)
and the package's source stamp removes it. The test works on a copy of the package with two small
compiled modules added to it (a callee and its caller in another file, compiled with the
package's options), so that it compiles in seconds and does not depend on where the physics
kernels live.
"""

import ast
import os
import shutil
import subprocess
import sys
import textwrap

import pytest
from numba.core import config as numba_config

from hosedrogue.jit import PACKAGE_DIR, compiled_modules, source_stamp

CALLEE = textwrap.dedent("""\
    from numba import njit

    from ..jit import JIT

    @njit(**JIT)
    def gain(x):
        return {factor} * x
""")

CALLER = textwrap.dedent("""\
    from numba import njit

    from ..jit import JIT
    from ._stamp_callee import gain

    @njit(**JIT)
    def twice_gain(x):
        return 2.0 * gain(x)
""")

SCRIPT = textwrap.dedent("""\
    from hosedrogue.model._stamp_caller import twice_gain
    value = twice_gain(1.5)
    print(value, sum(twice_gain.stats.cache_hits.values()), sum(twice_gain.stats.cache_misses.values()))
""")


def _copy(tmp_path):
    src = tmp_path / "src"
    pkg = src / "hosedrogue"
    shutil.copytree(PACKAGE_DIR, pkg, ignore=shutil.ignore_patterns("__pycache__"))
    (pkg / "model" / "_stamp_callee.py").write_text(CALLEE.format(factor="3.0"))
    (pkg / "model" / "_stamp_caller.py").write_text(CALLER)
    return src, pkg


def _run(src, cache, **extra_env):
    """One fresh process on the copy: (value, cache hits, cache misses) of the caller."""
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache), **extra_env)
    env.pop("NUMBA_DISABLE_JIT", None)
    out = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, cwd=src,
                         timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    value, hits, misses = out.stdout.split()
    return float(value), int(hits), int(misses)


@pytest.mark.subprocess
def test_editing_a_callee_recompiles_its_cached_caller(tmp_path):
    src, pkg = _copy(tmp_path)
    cache = tmp_path / "cache"
    assert _run(src, cache) == (9.0, 0, 1)       # compiled: 2 * 3 * 1.5
    assert _run(src, cache) == (9.0, 1, 0)       # the cache is used when nothing changed
    (pkg / "model" / "_stamp_callee.py").write_text(CALLEE.format(factor="5.0"))
    assert _run(src, cache) == (15.0, 0, 1)      # the edited callee: recompiled, 2 * 5 * 1.5
    assert _run(src, cache) == (15.0, 1, 0)


@pytest.mark.subprocess
def test_another_checkout_of_the_same_source_uses_the_cache(tmp_path):
    """One cache folder, two copies of the package at different paths: the second finds what the
    first compiled; a third with an edited callee compiles its own, and the first, back again,
    finds the stamp is not its own and compiles (never the other's code)."""
    first, _ = _copy(tmp_path / "a")
    second, _ = _copy(tmp_path / "b")
    third, pkg3 = _copy(tmp_path / "c")
    (pkg3 / "model" / "_stamp_callee.py").write_text(CALLEE.format(factor="5.0"))
    cache = tmp_path / "cache"
    assert _run(first, cache) == (9.0, 0, 1)
    assert _run(second, cache) == (9.0, 1, 0)
    assert _run(third, cache) == (15.0, 0, 1)
    assert _run(first, cache) == (9.0, 0, 1)


@pytest.mark.subprocess
@pytest.mark.skipif(not hasattr(numba_config, "CACHE_LOCATOR_CLASSES"),
                    reason="this numba has no NUMBA_CACHE_LOCATOR_CLASSES to select its own locator")
def test_numbas_own_locator_runs_the_stale_callee(tmp_path):
    """The control: with numba's own locator alone the caller's cache survives the callee's edit
    and the old callee runs (the hazard the package's stamp removes; if a numba release fixes it,
    this fails and says so)."""
    src, pkg = _copy(tmp_path)
    cache = tmp_path / "cache"
    numba_only = dict(NUMBA_CACHE_LOCATOR_CLASSES="UserProvidedCacheLocator")
    assert _run(src, cache, **numba_only) == (9.0, 0, 1)
    (pkg / "model" / "_stamp_callee.py").write_text(CALLEE.format(factor="5.0"))
    assert _run(src, cache, **numba_only) == (9.0, 1, 0)


def _defines_compiled_functions(path):
    """Whether a module decorates a function with numba's ``njit``/``jit`` (read from its syntax)."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.FunctionDef):
            for dec in node.decorator_list:
                target = dec.func if isinstance(dec, ast.Call) else dec
                name = getattr(target, "id", getattr(target, "attr", ""))
                if name in ("njit", "jit", "vectorize", "guvectorize", "generated_jit"):
                    return True
    return False


def test_the_stamp_covers_every_module_that_compiles():
    """Every module with a jitted function is in the stamp (read from the syntax, not the rule
    the stamp uses)."""
    compiling = {p for p in PACKAGE_DIR.rglob("*.py") if "__pycache__" not in p.parts
                 and _defines_compiled_functions(p)}
    assert compiling, "no compiled module found: the syntax check is broken"
    assert compiling <= set(compiled_modules())


def test_the_stamp_is_the_compiled_sources_content(tmp_path):
    """The stamp of a copy of the package is the package's (content, not place); an edit of a
    compiled module changes it, an edit of a module that compiles nothing does not."""
    src, pkg = _copy(tmp_path)
    for extra in ("_stamp_callee.py", "_stamp_caller.py"):
        (pkg / "model" / extra).unlink()
    assert source_stamp(pkg) == source_stamp()
    cli = pkg / "cli" / "steady.py"
    cli.write_text(cli.read_text() + "\n# an edit outside the compiled code\n")
    assert source_stamp.__wrapped__(pkg) == source_stamp()
    wake = pkg / "environment" / "wake.py"
    wake.write_text(wake.read_text() + "\n# an edit of a compiled module\n")
    assert source_stamp.__wrapped__(pkg) != source_stamp()
