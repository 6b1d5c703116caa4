"""Speed of the engagement driver, printed as figures next to their targets (never asserted).

* real-time factor (simulated seconds per CPU second) of each shipped engagement scenario at its
  converged settings (elastic links, 160 links, the stiff SDIRK at 5 ms; the locked reel at 2 ms;
  15 s with a capture; docs/engagement.md, "Link-count convergence"), twice: of the integration
  (the time inside the compiled segments, ``eng_segment``: the steps, their remeshes and events;
  the measure of the issue's 7.6, 82.5 us per RK4 step) with the target 50, and of the whole
  driver (plus the balance position, solved afresh for every run as in a user's first run of a
  flight condition: its per-process cache is cleared; 0.011-0.013 s at 160 elastic links, 0.24 s with
  ``--minpack``, the former solver; and the assembly of the result; both printed), compile time excluded,
  against the target 50 too (issue 32);
* the same scenario with rigid links on the settings it shipped with before (RK4 at 0.625 ms,
  two O(n) solves per evaluation), and the link-doubling mesh (320 links at half the step),
  with the change of every peak from the shipped mesh to it and the 3 % verdict (what
  ``hosedrogue simulate --verify`` measures; docs/convergence.md);
* one run of ``approach-moderate`` (the docking campaigns' unit: rigid links, 20 links, RK4 at
  5 ms, 4.5 s), whose speed the elastic chain must not change.

Each figure is the best of ``--repeats`` runs of the CPU time of this process (``time.process_time``:
a shared machine's other jobs stretch the wall time, much less the CPU time) and of the wall time.

Run:  .venv/bin/python benchmarks/engagement.py   (one core: NUMBA_NUM_THREADS=1 is set here)
"""

from __future__ import annotations

import os
import tempfile

os.environ.setdefault("NUMBA_CACHE_DIR", tempfile.mkdtemp(prefix="hosedrogue-bench-"))
os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

from hosedrogue.analysis import equilibrium as EQ  # noqa: E402
from hosedrogue.engagement import balance as BAL  # noqa: E402
from hosedrogue.model.engagement import steps as ES  # noqa: E402
from hosedrogue.scenarios import load_scenario  # noqa: E402
from hosedrogue.scenarios.runner import run  # noqa: E402
from hosedrogue.studies.convergence import with_links  # noqa: E402

from hosedrogue.engagement import driver as DR  # noqa: E402

_segment_kernel = ES.eng_segment
_in_segments = [0.0]
_equilibrium, _assemble = BAL.engagement_equilibrium, DR.assemble_result
_events = DR.segment_event  # the driver's one dispatch of a segment's event (engagement.events)
_parts = {"balance": 0.0, "assembly": 0.0, "events": 0.0}


def _timed_segment(*args):
    """The driver's compiled segment, its CPU time added up (the integration's share of a run)."""
    c0 = time.process_time()
    try:
        return _segment_kernel(*args)
    finally:
        _in_segments[0] += time.process_time() - c0


def _timed(function, part):
    """``function`` with its CPU time added to ``_parts[part]``."""
    def timed_function(*args, **kwargs):
        c0 = time.process_time()
        try:
            return function(*args, **kwargs)
        finally:
            _parts[part] += time.process_time() - c0
    return timed_function

SCENARIOS = ("engage-locked", "engage-constant-tension", "engage-response")
TARGET_RTF = 50.0
DOUBLING_BOUND = 0.03  # the brief's bound on a converged peak's change when the links are doubled


def timed(scenario, repeats):
    """Best CPU and wall time [s] of ``repeats`` runs, the best CPU time inside the compiled
    segments [s], and the last result; the best CPU times of the balance position, of the
    result's assembly (the output kernel on every saved state and the columns) and of the events
    between the segments (their kinematics and energies before and after) go to ``best_parts``."""
    cpu = wall = seg = math.inf
    best_parts.update(dict.fromkeys(_parts, math.inf))
    ES.eng_segment = _timed_segment
    BAL.engagement_equilibrium, DR.assemble_result = _timed(_equilibrium, "balance"), _timed(_assemble, "assembly")
    DR.segment_event = _timed(_events, "events")
    try:
        for _ in range(repeats):
            _in_segments[0] = 0.0
            _parts.update(dict.fromkeys(_parts, 0.0))
            BAL._STEADY.clear()  # the balance position is part of the whole run
            c0, w0 = time.process_time(), time.perf_counter()
            r = run(scenario)
            cpu = min(cpu, time.process_time() - c0)
            wall = min(wall, time.perf_counter() - w0)
            seg = min(seg, _in_segments[0])
            best_parts.update({k: min(best_parts[k], v) for k, v in _parts.items()})
    finally:
        ES.eng_segment = _segment_kernel
        BAL.engagement_equilibrium, DR.assemble_result = _equilibrium, _assemble
        DR.segment_event = _events
    return cpu, wall, seg, r


best_parts: dict = {}


def rigid(scenario):
    """The scenario with rigid links on its former settings: RK4 at 0.625 ms, output every 10 ms."""
    p = scenario.params.replace(hose={"axial_stiffness_n": math.inf, "axial_damping_n_s": 0.0},
                                numerics={"integrator": "rk4", "step_s": 0.000625, "output_every": 16})
    return dataclasses.replace(scenario, params=p)


def line(label, scenario, cpu, wall, seg, r, target=None):
    steps = int(round(scenario.duration_s / scenario.params.numerics.step_s))
    rtf = scenario.duration_s / seg
    goal = f" (target {target:g}: {'met' if rtf >= target else 'NOT met'})" if target else ""
    print(f"{label}: {scenario.params.hose.links} links, h = {scenario.params.numerics.step_s * 1e3:g} ms "
          f"({scenario.params.numerics.integrator}), {scenario.duration_s:g} s: integration CPU {seg:.3f} s -> "
          f"real-time factor {rtf:.1f}{goal}, {seg / steps * 1e6:.1f} us per step; whole run CPU {cpu:.3f} s, "
          f"wall {wall:.3f} s -> {scenario.duration_s / cpu:.1f}{_goal(scenario.duration_s / cpu, target)} "
          f"(wall {scenario.duration_s / wall:.1f}); of which balance position {best_parts['balance']:.4f} s, "
          f"assembly {best_parts['assembly']:.4f} s, events (remesh, chart, contact) {best_parts['events']:.4f} s; "
          f"result {r.outcome['result']!r}{'' if r.completed else ', INCOMPLETE: ' + r.message}")


def _goal(rtf, target) -> str:
    return f" (target {target:g}: {'met' if rtf >= target else 'NOT met'})" if target else ""


def doubling(a: dict, b: dict) -> None:
    """Print the link-doubling change of each peak and the 3 % verdict (what ``--verify`` measures)."""
    for key in a["converged"]:
        change = (b[key] - a[key]) / abs(a[key]) if a[key] else math.nan
        verdict = ("within" if abs(change) < DOUBLING_BOUND else "BEYOND") + " 3 %"
        print(f"    {key}: {a[key]:.5g} -> {b[key]:.5g} ({100 * change:+.2f} %, {verdict})")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=3, help="runs per figure (the best is reported)")
    ap.add_argument("--no-doubled", action="store_true", help="skip the 320-link meshes")
    ap.add_argument("--no-rigid", action="store_true",
                    help="skip the rigid links on their former settings (RK4 at 0.625 ms: most of this script's time)")
    ap.add_argument("--only", nargs="+", choices=SCENARIOS, metavar="NAME",
                    help=f"time only these engagement scenarios (of {', '.join(SCENARIOS)}); approach-moderate is always timed")
    ap.add_argument("--minpack", action="store_true",
                    help="the elastic balance position by the former solver (MINPACK, difference Jacobian): 'before'")
    args = ap.parse_args(argv)
    if args.minpack:
        former = EQ._elastic_newton
        EQ._elastic_newton = lambda model, env, q, scale, rigid=None: former(model, env, q, scale, None)
    names = args.only or SCENARIOS
    t0 = time.perf_counter()
    for name in names:
        sc = load_scenario(name)
        run(dataclasses.replace(sc, duration_s=0.05))
        if not args.no_rigid:
            run(dataclasses.replace(rigid(sc), duration_s=0.05))
    print(f"compile + first short runs: {time.perf_counter() - t0:.1f} s; load average {os.getloadavg()[0]:.1f}")
    for name in names:
        sc = load_scenario(name)
        line(f"{name} (elastic, shipped)", sc, *timed(sc, args.repeats), target=TARGET_RTF)
        if not args.no_rigid:
            line(f"{name} (rigid, former settings)", rigid(sc), *timed(rigid(sc), args.repeats))
        if not args.no_doubled:
            d = with_links(sc, 2 * sc.params.hose.links)
            cpu, wall, seg, rd = timed(d, 1)
            line(f"{name} (elastic, doubled)", d, cpu, wall, seg, rd)
            doubling(run(sc).summary(), rd.summary())
    sc = load_scenario("approach-moderate")
    run(sc)
    line("approach-moderate (the campaigns' run)", sc, *timed(sc, 5 * args.repeats))
    print(f"load average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
