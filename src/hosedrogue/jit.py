"""The one set of compilation options of every numba function in the package.

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
* :data:`JIT_NO_ALLOC` is :data:`JIT` without numba's runtime (``_nrt=False``) for the kernels of
  the time loop, which allocate nothing: taking an array out of the workspace tuple or slicing
  the state then costs no atomic reference-count update (those were ~1.5 us of a 3 us
  evaluation at 20 links). Such a kernel cannot allocate (``np.empty`` in one fails to compile).
  ``_nrt`` is an underscore option of numba's jit (numba 0.59-0.68 at least).
"""

#: Options of every compiled function that may allocate.
JIT = dict(cache=True, error_model="numpy", fastmath={"nsz", "contract"})
#: :data:`JIT` for functions that allocate nothing (no reference counting).
JIT_NO_ALLOC = dict(JIT, _nrt=False)
