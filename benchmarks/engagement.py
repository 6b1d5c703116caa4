"""Speed of the engagement driver, printed as figures (never asserted).

* real-time factor (simulated seconds per wall second) of the shipped ``engage-response``
  scenario (40 links, wake on, RK4 at 2.5 ms, 15 s with a capture and five remeshes), the whole
  driver timed (balance position, segments, remeshes, derived outputs), compile time excluded
  and reported apart;
* the same with 80 links at half the step (the link-doubling check).

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
        r = simulate_engagement(params, reel, probe, duration_s)
        best = min(best, time.perf_counter() - t0)
    return best, r


def main():
    sc = load_scenario("engage-response")
    reel, probe = sc.extra["reel"], sc.extra["probe"]
    t0 = time.perf_counter()
    simulate_engagement(sc.params, reel, probe, 0.5)
    print(f"compile + first short run: {time.perf_counter() - t0:.1f} s")
    for links, step in ((40, sc.params.numerics.step_s), (80, sc.params.numerics.step_s / 2)):
        p = sc.params.replace(hose={"links": links}, numerics={"step_s": step})
        wall, r = timed(p, reel, probe, sc.duration_s)
        steps = int(round(sc.duration_s / step))
        print(f"engage-response, {links} links, h = {step * 1e3:.3g} ms: {wall:.3f} s wall for {sc.duration_s:g} s "
              f"-> real-time factor {sc.duration_s / wall:.1f}; {wall / steps * 1e6:.1f} us per RK4 step "
              f"(driver total); {r.outcome['remesh_events']} remeshes, result {r.outcome['result']!r}")


if __name__ == "__main__":
    main()
