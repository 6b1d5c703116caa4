"""The one set of compilation options of every numba function in the package, and a cache that
cannot run stale code.

numba compiles a jitted function that another one calls on first use, and a callee compiled
inside a caller takes the caller's floating-point flags: a kernel shared by two loops compiled
with different options would run the arithmetic of whichever loop compiled it first, and a run's
last bits would depend on what the process (or the cache) compiled before (measured: 2e-14 m on
the paper's PID run after an engagement had run first). With one set of options everywhere the
order does not matter.

* ``error_model="numpy"`` drops Python's zero-division checks from the inner loops;
* the fast-math flags allow fused multiply-adds (``contract``) and ignore the sign of zero
  (``nsz``), but neither reassociation (vectorized reductions whose order depends on array
  alignment would make results differ in the last bits between processes) nor "no NaNs/infs"
  (divergence must still be detected);
* ``no_cfunc_wrapper``: numba builds, beside each function's Python entry, a C-callable wrapper
  for ``cfunc`` and first-class function values; the package uses neither, and the wrapper costs
  compile time for every one of its 160-odd compiled signatures (docs/develop.md, "Compile time");
* :data:`JIT_INLINE` is :data:`JIT` inlined into its compiled callers;
* :data:`JIT_NO_ALLOC` is :data:`JIT` without numba's runtime (``_nrt=False``) for the kernels of
  the time loop, which allocate nothing: taking an array out of the workspace tuple or slicing
  the state then costs no atomic reference-count update (those were ~1.5 us of a 3 us
  evaluation at 20 links). Such a kernel cannot allocate (``np.empty`` in one fails to compile).
  ``_nrt`` is an underscore option of numba's jit (numba 0.59-0.68 at least).

**The cache.** numba's on-disk cache (``cache=True``) keys each function's entries on the source
of the file that defines it alone, but a cached function holds the machine code of every
function it calls: with the callee in another file, editing the callee leaves the caller's cache
valid, and the next process runs the old callee (numba's documentation, "Notes on caching"). Here
every compiled function of the package is stamped instead with :func:`source_stamp`, the hash
of the source of every module of the package that compiles code (any module that imports numba)
and of numba's version: any change in any of them recompiles every cached function of the
package, whatever it calls, and nothing else does. The stamp is taken once per process; since it
is the source's content, not its place, a cache folder of one's own (``NUMBA_CACHE_DIR``) serves
every checkout of the same source (CI keeps one between runs). The locators that apply it (:class:`PackageCacheLocator` and its kin) come before numba's own for the
package's files only; other packages' functions are cached as numba does.
"""

from __future__ import annotations

import functools
import hashlib
import os
import re
from pathlib import Path

import numba
from numba.core import caching, event
from numba.core import dispatcher as numba_dispatcher

try:
    import fcntl
except ImportError:  # Windows: numba's cache as it is
    fcntl = None

#: Options of every compiled function that may allocate.
JIT = dict(cache=True, error_model="numpy", fastmath={"nsz", "contract"}, no_cfunc_wrapper=True)
#: :data:`JIT` for functions that allocate nothing (no reference counting).
JIT_NO_ALLOC = dict(JIT, _nrt=False)
#: :data:`JIT` for a function whose code numba puts into each compiled caller (numba's
#: ``inline="always"``) instead of compiling it as a function of its own: the time steps of
#: :mod:`hosedrogue.model.steppers` (docs/develop.md, "Compile time"). Called from Python it
#: compiles as any other.
JIT_INLINE = dict(JIT, inline="always")
#: :data:`JIT_NO_ALLOC` inlined into its compiled callers: a small function of the chain's
#: evaluation with few callers (docs/develop.md, "The compiled core"). Inlined into a caller
#: with numba's runtime it takes the caller's runtime.
JIT_NO_ALLOC_INLINE = dict(JIT_NO_ALLOC, inline="always")

#: The package's folder: the functions defined under it take :func:`source_stamp`.
PACKAGE_DIR = Path(__file__).resolve().parent
_IMPORTS_NUMBA = re.compile(rb"^\s*(?:from\s+numba\b|import\s+numba\b)", re.MULTILINE)


def compiled_modules(package_dir: Path = PACKAGE_DIR) -> list[Path]:
    """The package's modules that compile code, sorted.

    Parameters
    ----------
    package_dir : pathlib.Path
        The package's folder (default: this package's).

    Returns
    -------
    list of pathlib.Path
        Every ``.py`` file under ``package_dir`` that imports numba (``import numba`` or
        ``from numba ...`` at the start of a line).
    """
    return sorted(p for p in package_dir.rglob("*.py")
                  if "__pycache__" not in p.parts and _IMPORTS_NUMBA.search(p.read_bytes()))


@functools.lru_cache(maxsize=None)
def source_stamp(package_dir: Path = PACKAGE_DIR) -> str:
    """What a cached compiled function of the package is valid for.

    Parameters
    ----------
    package_dir : pathlib.Path
        The package's folder (default: this package's).

    Returns
    -------
    str
        SHA-256 (hex) of numba's version and of the path (relative to the package) and bytes of
        every module :func:`compiled_modules` lists.
    """
    h = hashlib.sha256(f"numba {numba.__version__}\n".encode())
    for path in compiled_modules(package_dir):
        data = path.read_bytes()
        h.update(f"{path.relative_to(package_dir).as_posix()} {len(data)}\n".encode())
        h.update(data)
    return h.hexdigest()


def _in_package(py_file) -> bool:
    try:
        Path(py_file).resolve().relative_to(PACKAGE_DIR)
    except (OSError, ValueError):
        return False
    return True


class _PackageStamp:
    """Mixin of the package's cache locators: the package's source stamp, not the file's, and
    only for the package's own files (numba's locators handle every other). In a cache folder of
    its own (``NUMBA_CACHE_DIR``, or the user-wide one of a read-only install) a module's entries
    are filed under its place in the package, not under the checkout's path: every copy of the
    same source (a fresh clone, another virtual environment) finds what another compiled, and a
    copy of other source finds a stamp that is not its own and compiles."""

    def get_source_stamp(self):
        return source_stamp()

    @classmethod
    def get_suitable_cache_subpath(cls, py_file):
        folder = Path(py_file).resolve().parent.relative_to(PACKAGE_DIR).as_posix()
        return "hosedrogue_" + hashlib.sha1(folder.encode()).hexdigest()

    @classmethod
    def from_function(cls, py_func, py_file):
        if not _in_package(py_file):
            return None
        return super().from_function(py_func, py_file)


def _numba_name(name):
    """A class of numba's caching module by its public name (numba >= 0.61) or its former,
    underscored one (0.59-0.60)."""
    return getattr(caching, name, None) or getattr(caching, "_" + name)


class PackageCacheLocator(_PackageStamp, _numba_name("UserProvidedCacheLocator")):
    """numba's ``NUMBA_CACHE_DIR`` locator, stamped with :func:`source_stamp`."""


class PackageInTreeCacheLocator(_PackageStamp, _numba_name("InTreeCacheLocator")):
    """numba's ``__pycache__`` locator, stamped with :func:`source_stamp`."""


class PackageUserWideCacheLocator(_PackageStamp, _numba_name("UserWideCacheLocator")):
    """numba's user-wide locator (a read-only install), stamped with :func:`source_stamp`."""


class CompileOnceCache(caching.FunctionCache):
    """numba's per-function disk cache that compiles each of the package's signatures once per
    machine, not once per process.

    Processes that start together on a cold cache (a campaign's Dask workers, pytest's workers,
    two commands at once) would each compile the same functions, since numba looks in the cache
    only before it compiles. Here a miss on a package function takes an exclusive lock on a file
    beside the cache entry (``fcntl.flock``, one per signature and machine) and looks again: a
    process that finds the lock taken waits for the one compiling, then loads what it saved. The
    lock is released when the entry is saved, when its compilation fails (numba's
    ``numba:compile`` end event, :class:`_ReleaseOnFailure`) or when the process ends, so a
    crashed compiler leaves nothing stuck. Call graphs have no cycles, so locks taken in call order
    cannot deadlock. Without ``fcntl`` (Windows) or a writable cache folder, it is numba's cache.

    Parameters
    ----------
    py_func : function
        The Python function numba compiles (numba's dispatcher makes the cache).
    """

    def __init__(self, py_func):
        super().__init__(py_func)
        self._held = {}  # index key -> open, locked lock file

    def _lock_path(self, key) -> str:
        digest = hashlib.sha1(repr(key).encode()).hexdigest()[:16]
        return os.path.join(self.cache_path, f"{self._impl.filename_base}.{digest}.lock")

    def load_overload(self, sig, target_context):
        data = super().load_overload(sig, target_context)
        if (data is not None or fcntl is None or not self._enabled
                or not isinstance(self._impl.locator, _PackageStamp)):
            return data
        key = self._index_key(sig, target_context.codegen())
        if key in self._held:  # this process is compiling it already
            return None
        try:
            self._impl.locator.ensure_cache_path()
            lock = open(self._lock_path(key), "a")  # held until the entry is saved
        except OSError:
            return None
        fcntl.flock(lock, fcntl.LOCK_EX)  # waits while another process compiles this signature
        data = super().load_overload(sig, target_context)
        if data is not None:
            lock.close()  # closing the file releases the lock
            return data
        self._held[key] = lock
        return None

    def save_overload(self, sig, data):
        try:
            super().save_overload(sig, data)
        finally:
            self.release(self._index_key(sig, data.codegen))

    def release(self, key=None) -> None:
        """Release the lock of ``key`` (every lock this cache holds: None)."""
        for k in ([key] if key is not None else list(self._held)):
            lock = self._held.pop(k, None)
            if lock is not None:
                lock.close()


class _ReleaseOnFailure(event.Listener):
    """Releases a function's compile locks when its compilation raises (a typing error and the
    like), so that another process compiles it (and fails the same way) instead of waiting."""

    def on_start(self, ev):
        pass

    def on_end(self, ev):
        # failed: the end of the compile event came without the overload (numba adds it inside
        # the event on success; its Event.is_failed reads the other way round in 0.59-0.68)
        dispatcher = (ev.data or {}).get("dispatcher")
        cache = getattr(dispatcher, "_cache", None)
        if isinstance(cache, CompileOnceCache) and tuple(ev.data.get("args", ())) not in dispatcher.overloads:
            cache.release()


def _install_locators() -> None:
    """Put the package's locators first in numba's list (once; before any function of the
    package is decorated, since a dispatcher picks its locator when it is created)."""
    classes = _numba_name("CacheImpl")._locator_classes
    ours = [PackageCacheLocator, PackageInTreeCacheLocator, PackageUserWideCacheLocator]
    if classes[:len(ours)] != ours:
        classes[:0] = ours


_install_locators()
# numba's dispatcher makes each function's cache from this name when caching is enabled
# (``Dispatcher.enable_caching``): every function decorated after this line gets the lock
if getattr(numba_dispatcher, "FunctionCache", None) is caching.FunctionCache:
    numba_dispatcher.FunctionCache = CompileOnceCache
    event.register("numba:compile", _ReleaseOnFailure())
