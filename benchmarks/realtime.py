"""Speed of the compiled model, printed as figures (never asserted).

* real-time factor (simulated seconds per wall second) of the paper's 20-link turbulence case
  (the ``paper-turbulence`` scenario's settings: wake and turbulence on, gusts averaged over
  0.02 s and read as a cubic, RK4 at 0.02 s), compile time excluded and reported apart;
* the same as a user runs it: ``hosedrogue simulate paper-turbulence --duration 1620`` minus
  ``--duration 1020`` (wall clock of the whole command, files written), so start-up cancels; the
  short run is 1020 s, not 10 s: ``simulate`` refuses a paper-turbulence run that ends before its
  turbulence window (10-30 s), and draws the spectrum only for a run long enough to have one
  (``benchmarks/realtime_pairs.py``, the same choice); the difference is small beside the
  start-up, so it is also measured inside one process (simulation and files, no start-up);
* time per RK4 step against the number of links (20 ... 400) and its growth per doubling;
* the same 20-link case written as a user would without this package: a numpy right-hand side
  that forms and solves the dense mass matrix, integrated by scipy's solve_ivp (RK45).

Run:  .venv/bin/python benchmarks/realtime.py   (one core: NUMBA_NUM_THREADS=1 is set here)
"""

from __future__ import annotations

import os

import tempfile  # noqa: E402

# compile into an empty cache so the compile time printed below is a real compile
os.environ.setdefault("NUMBA_CACHE_DIR", tempfile.mkdtemp(prefix="hosedrogue-bench-"))
os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from hosedrogue.analysis.equilibrium import solve_equilibrium  # noqa: E402
from hosedrogue.controllers.linear import LinearController  # noqa: E402
from hosedrogue.model.integrate import rk4_run  # noqa: E402
from hosedrogue.model.system import HoseModel  # noqa: E402
from hosedrogue.spec.params import PAPER, Actuator  # noqa: E402
from hosedrogue.simulation.simulate import loop_arrays, output_arrays  # noqa: E402

TURBULENCE = {"enabled": True, "start_s": 0.0, "duration_s": 100.0}


def scenario_params():
    """The paper-turbulence scenario's parameters, with the gust window over the whole run."""
    from hosedrogue.scenarios import load_scenario

    return load_scenario("paper-turbulence").params.replace(turbulence=TURBULENCE)


#: the long and the short run [s] whose difference is timed (module docstring)
LONG_S, SHORT_S = 1620.0, 1020.0


def user_facing_rtf(repeats=5):
    """Real-time factor of the command line: LONG_S - SHORT_S over the difference of the fastest
    of ``repeats`` runs of each (start-up cancels; the minimum filters out the load of other jobs),
    and the same from the median walls."""
    import subprocess
    import sys

    def wall(duration):
        with tempfile.TemporaryDirectory() as out:
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "hosedrogue", "simulate", "paper-turbulence",
                            "--duration", f"{duration:g}", "--out", out], check=True, capture_output=True)
            return time.perf_counter() - t0

    wall(SHORT_S)  # fill the numba cache of this benchmark
    short, long_ = [], []
    for _ in range(repeats):  # interleaved, so a change of load hits both
        short.append(wall(SHORT_S))
        long_.append(wall(LONG_S))
    span = LONG_S - SHORT_S
    return span / (min(long_) - min(short)), span / (float(np.median(long_)) - float(np.median(short)))


def in_process_rtf(repeats=5):
    """The same marginal cost measured inside one process (no start-up noise): wall time of
    ``run`` + ``write`` (CSV, run.json, figures) for LONG_S minus SHORT_S, from the fastest and
    from the median of ``repeats`` interleaved runs of each."""
    from pathlib import Path

    from hosedrogue.scenarios import load_scenario
    from hosedrogue.scenarios.runner import run, write

    def wall(duration):
        scenario = load_scenario("paper-turbulence").with_overrides(duration_s=duration, seed=None)
        with tempfile.TemporaryDirectory() as out:
            t0 = time.perf_counter()
            write(run(scenario), Path(out))
            return time.perf_counter() - t0

    wall(SHORT_S)
    short, long_ = [], []
    for _ in range(repeats):  # interleaved, as for the command line
        short.append(wall(SHORT_S))
        long_.append(wall(LONG_S))
    span = LONG_S - SHORT_S
    return span / (min(long_) - min(short)), span / (float(np.median(long_)) - float(np.median(short)))


def rk4_wall_time(model, x0, duration_s, repeats=3):
    h = model.params.numerics.step_s
    nsteps = int(round(duration_s / h))
    every = nsteps  # keep only the end: measure the integrator, not the output copies
    ctrl = LinearController.static_zero()
    ts = np.empty(2)
    zs = np.empty((2, x0.size))
    us = np.empty((2, 2))
    loop = loop_arrays(ctrl, np.zeros(2), Actuator(), np.zeros((1, 2)), 1.0)
    args = (x0, h, nsteps, every, *model.kernel_args(), *loop, math.radians(85.0), ts, zs, us,
            *output_arrays(2, model.n))
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        status, _, _ = rk4_run(*args)
        best = min(best, time.perf_counter() - t0)
        assert status == 0
    return best, nsteps


def main():
    t0 = time.perf_counter()
    p = scenario_params()
    model = HoseModel(p)
    eq = solve_equilibrium(p, model=model)
    rk4_wall_time(model, eq.state, 0.01, repeats=1)
    print(f"compile time (first equilibrium and first RK4 call, empty numba cache): {time.perf_counter() - t0:.2f} s")

    duration = 60.0
    wall, nsteps = rk4_wall_time(model, eq.state, duration, repeats=5)
    print(f"paper turbulence case, 20 links, RK4 h = {p.numerics.step_s} s, {duration:g} s simulated:")
    print(f"  wall {wall * 1e3:.1f} ms, {wall / nsteps * 1e6:.2f} us/step, real-time factor {duration / wall:,.0f}")
    best, median = user_facing_rtf()
    print(f"as a user runs it (hosedrogue simulate paper-turbulence, {LONG_S:g} s minus {SHORT_S:g} s, files written): "
          f"real-time factor {best:,.0f} from the fastest runs, {median:,.0f} from the medians (target >= 2000)")
    best, median = in_process_rtf()
    print(f"  the same inside one process (simulate + files, {LONG_S:g} s minus {SHORT_S:g} s): real-time factor "
          f"{best:,.0f} best, {median:,.0f} median")

    print("time per RK4 step against links (turbulence and wake on):")
    prev = None
    for n in (20, 50, 100, 200, 400):
        pn = p.replace(hose={"links": n})
        mn = HoseModel(pn)
        eqn = solve_equilibrium(pn, model=mn)
        dur = 20.0 if n <= 100 else 8.0
        wall_n, steps_n = rk4_wall_time(mn, eqn.state, dur)
        per = wall_n / steps_n
        growth = "" if prev is None else f"  x{per / prev[1]:.2f} for x{n / prev[0]:.1f} links"
        target = "  (target >= 200)" if n == 200 else ""
        print(f"  n = {n:4d}: {per * 1e6:8.2f} us/step, real-time factor {dur / wall_n:10,.0f}{growth}{target}")
        prev = (n, per)

    from hosedrogue.simulation import simulate_batch
    from hosedrogue.simulation import simulate

    seeds = list(range(16))
    dur = 40.0
    pb = PAPER.replace(turbulence={"enabled": True})
    simulate_batch(pb, seeds[:1], 1.0)  # compile
    t0 = time.perf_counter()
    simulate_batch(pb, seeds, dur)
    t_batch = time.perf_counter() - t0
    t0 = time.perf_counter()
    for s_ in seeds:
        simulate(pb, dur, seed=s_)
    t_loop = time.perf_counter() - t0
    print(f"16 turbulence runs of {dur:g} s (20 links): one batch call {t_batch:.2f} s "
          f"({len(seeds) * dur / t_batch:,.0f} simulated s per wall s), a loop of simulate() {t_loop:.2f} s")

    from naive import naive_wall_time

    wall_naive, sim_naive = naive_wall_time(p, eq.state, 5.0)
    rtf_naive = sim_naive / wall_naive
    print(f"the same case in numpy + scipy.solve_ivp (dense solve, RK45, rtol 1e-6): real-time factor "
          f"{rtf_naive:.2f}; this package is {duration / wall / rtf_naive:,.0f} times faster")


if __name__ == "__main__":
    main()
