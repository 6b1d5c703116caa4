"""Speed of the engagement driver, printed as figures (never asserted).

* real-time factor (simulated seconds per wall second) of the shipped ``engage-response``
  scenario (160 links, wake on, RK4 at 0.625 ms, 15 s with a capture and 19 remeshes), the whole
  driver timed (balance position, segments, remeshes, derived outputs), compile time excluded
  and reported apart;
* the same with twice the links at half the step (the link-doubling check, 320 links).

Run:  .venv/bin/python benchmarks/engagement.py   (one core: NUMBA_NUM_THREADS=1 is set here)
"""

from __future__ import annotations

import os
import tempfile

os.environ.setdefault("NUMBA_CACHE_DIR", tempfile.mkdtemp(prefix="hosedrogue-bench-"))
os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import time  # noqa: E402

from hosedrogue.engagement import simulate_engagement  # noqa: E402
from hosedrogue.scenarios import load_scenario  # noqa: E402


def timed(params, reel, probe, duration_s, repeats=3):
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = simulate_engagement(params, duration_s, reel=reel, probe=probe)
        best = min(best, time.perf_counter() - t0)
    return best, r


def main():
    sc = load_scenario("engage-response")
    reel, probe = sc.engagement.reel, sc.engagement.probe
    t0 = time.perf_counter()
    simulate_engagement(sc.params, 0.5, reel=reel, probe=probe)
    print(f"compile + first short run: {time.perf_counter() - t0:.1f} s")
    n, h = sc.params.hose.links, sc.params.numerics.step_s
    for links, step in ((n, h), (2 * n, h / 2)):
        p = sc.params.replace(hose={"links": links}, numerics={"step_s": step})
        wall, r = timed(p, reel, probe, sc.duration_s)
        steps = int(round(sc.duration_s / step))
        print(f"engage-response, {links} links, h = {step * 1e3:.3g} ms: {wall:.3f} s wall for {sc.duration_s:g} s "
              f"-> real-time factor {sc.duration_s / wall:.1f}; {wall / steps * 1e6:.1f} us per RK4 step "
              f"(driver total); {r.outcome['remesh_events']} remeshes, result {r.outcome['result']!r}")


if __name__ == "__main__":
    main()
