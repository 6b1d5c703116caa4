"""The paper's case as a user runs it, this code against another checkout's, alternately (issue 30's
speed check; figures printed, never asserted).

A user runs ``hosedrogue simulate paper-turbulence``: start-up, balance position, the run, files. The
real-time factor of the run alone is taken as the difference of two whole commands, ``--duration
LONG`` minus ``--duration SHORT`` (start-up, compile-cache loading and the balance position cancel):
``(LONG - SHORT) / (t_LONG - t_SHORT)``. SHORT is 1020 s, not the 10 s of the issue's first figures:
``simulate`` now refuses a paper-turbulence run that ends before its turbulence window (10-30 s) and
draws ``spectrum.png`` (the drogue offset's spectrum beside its linear prediction: a linearization and
a figure, about 1 s) only for a run long enough to have one, so a 20 s run would subtract less fixed
work than the long run does and the difference would charge that second to the integration, in CPU seconds of the child processes (``getrusage``: a shared
machine's other jobs stretch the wall time far more than the CPU time; ``cold_start.run_once``) and in wall seconds. The
two codes run alternately, old then new, ``--pairs`` times, each pair in the same minutes, since this
machine's speed drifts between hours; each code first runs once to fill its own numba cache.

Run:  .venv/bin/python benchmarks/realtime_pairs.py --old /path/to/other/checkout/src [--pairs 5]
      (e.g. ``git worktree add -f /tmp/old 65f7dbc`` then ``--old /tmp/old/src``)
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
from pathlib import Path

from cold_start import run_once  # benchmarks/ is this script's folder, first on sys.path

HERE = Path(__file__).resolve().parents[1] / "src"


def _command(src: Path, cache: str, duration: float, scenario: str) -> tuple[float, float]:
    """CPU and wall seconds of one ``hosedrogue simulate`` run with the package at ``src``
    (:func:`cold_start.run_once`, a fresh process)."""
    with tempfile.TemporaryDirectory(prefix="hosedrogue-rt-") as out:
        return run_once([sys.executable, "-m", "hosedrogue", "simulate", scenario, "--duration", f"{duration:g}",
                         "--out", "{out}/run"], cache, out, {"PYTHONPATH": str(src)})


def _factor(src: Path, cache: str, long_s: float, short_s: float, scenario: str) -> tuple[float, float]:
    """Real-time factor of the run alone (CPU, wall): the long command minus the short one."""
    c_long, w_long = _command(src, cache, long_s, scenario)
    c_short, w_short = _command(src, cache, short_s, scenario)
    span = long_s - short_s
    return span / (c_long - c_short), span / (w_long - w_short)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--old", required=True, type=Path, help="the other checkout's src folder")
    ap.add_argument("--pairs", type=int, default=5, help="old/new pairs (default 5)")
    ap.add_argument("--duration", type=float, default=6020.0, help="the long run's duration [s] (default 6020)")
    ap.add_argument("--short", type=float, default=1020.0,
                    help="the short run's duration [s] (default 1020: it writes the same files as the long run)")
    ap.add_argument("--scenario", default="paper-turbulence", help="shipped scenario (default paper-turbulence)")
    args = ap.parse_args(argv)
    if not (args.old / "hosedrogue" / "__init__.py").is_file():
        # else PYTHONPATH would name nothing and the installed package, this code, would be timed as the old
        ap.error(f"--old {args.old}: not a src folder holding the hosedrogue package")
    codes = {"old": args.old.resolve(), "new": HERE}
    caches = {k: tempfile.mkdtemp(prefix=f"hosedrogue-rt-{k}-") for k in codes}
    for k, src in codes.items():  # fill each code's cache (compile excluded from the figures)
        _command(src, caches[k], args.short, args.scenario)
    got = {k: [] for k in codes}
    for i in range(args.pairs):
        for k, src in codes.items():
            got[k].append(_factor(src, caches[k], args.duration, args.short, args.scenario))
            cpu, wall = got[k][-1]
            print(f"pair {i + 1} {k}: real-time factor {cpu:.0f} (CPU), {wall:.0f} (wall)", flush=True)
    med = {k: (statistics.median(c for c, _ in v), statistics.median(w for _, w in v)) for k, v in got.items()}
    for k in codes:
        print(f"{k} ({codes[k]}): median real-time factor {med[k][0]:.0f} (CPU), {med[k][1]:.0f} (wall)")
    # CPU: the work done (robust to the machine's other jobs); wall: the user's real-time factor,
    # which also counts what runs beside the work (the files written on a thread of their own)
    for j, what in ((0, "CPU"), (1, "wall")):
        ratio = [n[j] / o[j] for o, n in zip(got["old"], got["new"])]
        print(f"new / old per pair ({what}): {', '.join(f'{r:.3f}' for r in ratio)}; median "
              f"{statistics.median(ratio):.3f} (issue 30: within 3 % of the old, i.e. >= 0.970)")
    print(f"load average {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
