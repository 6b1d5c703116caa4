"""What a first run waits for: the main commands in fresh processes, CPU seconds with an empty numba
cache (cold, as a fresh clone, a CI run or a wheel install pays it) and again with the cache that
run filled (warm), printed beside the targets (never asserted).

Each case runs twice in a new process of its own (``python -c`` or the ``hosedrogue`` CLI) with
``NUMBA_CACHE_DIR`` pointing to a new, empty folder: the first run compiles and fills it, the
second loads it. The figure is the child's CPU time (user + system, from ``os.wait4``), which a
shared machine's other jobs stretch much less than the wall time, printed with the wall time.
``NUMBA_NUM_THREADS=1`` (the figures are one core's).

Targets (the compiled-core issue, on the project's 2-core machine): cold ``steady`` at most 4 s
of CPU; cold ``simulate engage-response --duration 0.5``, the cold first Gymnasium transition and
the cold ``export-fmu`` at most 15 s each. The other cases have no target and are printed for
the record (the paper's case, the approach).

Run:  .venv/bin/python benchmarks/cold_start.py [--only NAME ...] [--json]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HOSEDROGUE = [sys.executable, "-m", "hosedrogue"]

GYM_FIRST_STEP = (
    "import gymnasium, hosedrogue.envs\n"
    "env = gymnasium.make('hosedrogue/Docking-v0')\n"
    "env.reset(seed=0)\n"
    "env.step(env.action_space.sample())\n"
)

#: (name, argv after the interpreter or CLI (``{out}`` is a fresh folder), CPU-second target or None)
CASES = (
    ("steady", HOSEDROGUE + ["steady"], 4.0),
    ("simulate engage-response 0.5 s",
     HOSEDROGUE + ["simulate", "engage-response", "--duration", "0.5", "--out", "{out}/engage"], 15.0),
    ("gym first transition", [sys.executable, "-c", GYM_FIRST_STEP], 15.0),
    ("export-fmu engage-response", HOSEDROGUE + ["export-fmu", "--engagement", "engage-response", "--out", "{out}/engage.fmu"], 15.0),
    ("export-fmu", HOSEDROGUE + ["export-fmu", "--out", "{out}/hose.fmu"], None),
    # 11 s: the scenario's turbulence starts at 10 s, and a run its statistics window misses is refused
    ("simulate paper-turbulence 11 s",
     HOSEDROGUE + ["simulate", "paper-turbulence", "--duration", "11", "--out", "{out}/paper"], None),
    ("simulate approach-moderate",
     HOSEDROGUE + ["simulate", "approach-moderate", "--out", "{out}/approach"], None),
)


def run_once(argv, cache_dir, out_dir, extra_env=None):
    """One fresh process: (CPU seconds of the child, wall seconds); ``extra_env`` is added to its
    environment (``benchmarks/realtime_pairs.py``: the PYTHONPATH of the code it times)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir), NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1",
               OPENBLAS_NUM_THREADS="1", MPLBACKEND="Agg", **(extra_env or {}))
    argv = [a.replace("{out}", str(out_dir)) for a in argv]
    t0 = time.perf_counter()
    proc = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    err = proc.stderr.read().decode(errors="replace")
    proc.stderr.close()
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(argv)}: exit {proc.returncode}\n{err[-2000:]}")
    return usage.ru_utime + usage.ru_stime, wall


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="+", metavar="NAME", help="only the cases whose name starts with NAME")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args(argv)
    cases = [c for c in CASES if not args.only or any(c[0].startswith(o) for o in args.only)]
    if not cases:
        parser.error(f"--only {' '.join(args.only)}: no case starts with that; the cases: "
                     + ", ".join(repr(c[0]) for c in CASES))
    rows = []
    for name, command, target in cases:
        cache = Path(tempfile.mkdtemp(prefix="hosedrogue-cold-cache-"))
        out = Path(tempfile.mkdtemp(prefix="hosedrogue-cold-out-"))
        try:
            cold_cpu, cold_wall = run_once(command, cache, out)
            warm_cpu, warm_wall = run_once(command, cache, out)
        finally:
            shutil.rmtree(cache, ignore_errors=True)
            shutil.rmtree(out, ignore_errors=True)
        row = dict(case=name, cold_cpu_s=round(cold_cpu, 2), cold_wall_s=round(cold_wall, 2),
                   warm_cpu_s=round(warm_cpu, 2), warm_wall_s=round(warm_wall, 2), target_cold_cpu_s=target,
                   met=None if target is None else cold_cpu <= target)
        rows.append(row)
        if not args.json:
            verdict = "" if target is None else f"  target {target:g} s: {'met' if row['met'] else 'NOT met'}"
            print(f"{name:34s} cold {cold_cpu:7.2f} s CPU ({cold_wall:6.2f} s wall)   "
                  f"warm {warm_cpu:6.2f} s CPU ({warm_wall:6.2f} s wall){verdict}", flush=True)
    if args.json:
        print(json.dumps(dict(python=sys.version.split()[0], cases=rows), indent=2))


if __name__ == "__main__":
    main()
