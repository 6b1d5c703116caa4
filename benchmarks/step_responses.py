"""The closed loops' unit steps (Table 3, Figs. 10-11, the PID tuning, ``design pid``): the compiled
step response against python-control's, bit for bit, and the commands' CPU time against another
checkout's (figures printed, never asserted).

``--check`` runs, in this process, ``reproduce --fast --only controllers pid_tuning`` and the
``design`` commands of the tests with :func:`hosedrogue.analysis.responses.step_outputs` wrapped:
every call is computed again by ``control.step_response`` and the two arrays compared byte for
byte (the sign of a zero included); it prints the calls by model order, inputs and time points,
and the calls that were not identical (none expected). It also counts the calls that repeat one
before them (same matrices, times and input).

``--old SRC`` times each command in fresh processes (CPU seconds of the child,
``cold_start.run_once``; the warm numba cache of each code filled by a first run), the other
checkout's code and this one alternately, ``--pairs`` times.

Run:  .venv/bin/python benchmarks/step_responses.py --check
      .venv/bin/python benchmarks/step_responses.py --old /path/to/other/checkout/src [--pairs 3] [--full]
"""

from __future__ import annotations

import argparse
import collections
import hashlib
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from cold_start import run_once  # benchmarks/ is this script's folder, first on sys.path

HERE = Path(__file__).resolve().parents[1] / "src"
SECTIONS = ["controllers", "pid_tuning"]
#: ``design`` commands as the tests call them (tests/cli/test_cli_design_rms.py, tests/cli/test_cli.py,
#: tests/controllers/test_pid_tuning.py).
DESIGNS = {
    "design pid --rms-target": ["design", "pid", "--altitude", "6100", "--airspeed", "128", "--rms-target", "0.1",
                                "0.1", "--json"],
    "design pid --plant paper": ["design", "pid", "--plant", "paper", "--json"],
    "design pid --gains paper": ["design", "pid", "--plant", "paper", "--gains", "paper", "--json"],
    "design pid (this model)": ["design", "pid", "--json"],
    "design lqr": ["design", "lqr", "--json"],
}


def _reproduce(out: str, fast: bool = True) -> list[str]:
    return ["reproduce", *(["--fast"] if fast else []), "--only", *SECTIONS, "--workers", "1", "--out", out]


def check() -> int:
    """Every step of the sections and commands computed both ways; prints the census, returns the
    number of calls that differ."""
    import contextlib
    import io

    import numpy as np
    import control

    from hosedrogue.analysis import responses

    fast = responses.step_outputs
    seen, rows, bad = set(), collections.Counter(), []
    cpu = collections.Counter()

    def checked(sys_, t, input_index=0):
        t0 = time.process_time()
        y = fast(sys_, t, input_index)
        t1 = time.process_time()
        ref = control.step_response(sys_, t, input=input_index, squeeze=False).outputs[:, 0, :]
        t2 = time.process_time()
        key = hashlib.sha256(b"".join(np.ascontiguousarray(a, dtype=float).tobytes() + str(np.shape(a)).encode()
                                      for a in (sys_.A, sys_.B, sys_.C, sys_.D, t)) + bytes([input_index])).hexdigest()
        row = (sys_.nstates, sys_.ninputs, sys_.noutputs, np.size(t))
        rows[row + (key in seen,)] += 1
        seen.add(key)
        cpu["compiled"] += t1 - t0
        cpu["python-control"] += t2 - t1
        if y.dtype != ref.dtype or y.shape != ref.shape or y.tobytes() != ref.tobytes():
            bad.append((row, float(np.max(np.abs(y - ref)))))
        return y

    responses.step_outputs = checked
    from hosedrogue.cli import main  # imports the call sites after the wrapper is in place

    with tempfile.TemporaryDirectory(prefix="hosedrogue-steps-") as out:
        commands = {"reproduce --fast --only " + " ".join(SECTIONS): _reproduce(out), **DESIGNS}
        for name, argv in commands.items():
            before = sum(rows.values())
            with contextlib.redirect_stdout(io.StringIO()):
                code = main(argv)
            print(f"{name}: exit {code}, {sum(rows.values()) - before} step responses")
    print("states inputs outputs points repeat calls")
    for (n, m, p, pts, rep), k in sorted(rows.items()):
        print(f"{n:6d} {m:6d} {p:7d} {pts:6d} {'yes' if rep else 'no':>6s} {k:5d}")
    print(f"calls {sum(rows.values())}, repeats {sum(k for r, k in rows.items() if r[-1])}, "
          f"CPU compiled {cpu['compiled']:.2f} s, python-control {cpu['python-control']:.2f} s")
    print(f"not bit-identical: {len(bad)}" + "".join(f"\n  {r}: max |difference| {d:.3g}" for r, d in bad))
    return len(bad)


def pairs(old: Path, n_pairs: int, full: bool) -> None:
    """Old and new code alternately on each command; prints the CPU seconds and their medians."""
    cache = {"old": os.environ.get("OLD_NUMBA_CACHE_DIR") or tempfile.mkdtemp(prefix="hosedrogue-steps-old-"),
             "new": os.environ.get("NUMBA_CACHE_DIR") or tempfile.mkdtemp(prefix="hosedrogue-steps-new-")}
    src = {"old": old, "new": HERE}
    commands = {"reproduce --fast --only " + " ".join(SECTIONS): _reproduce("{out}/r"), **DESIGNS}
    if full:
        commands["reproduce --only " + " ".join(SECTIONS)] = _reproduce("{out}/r", fast=False)
    for name, argv in commands.items():
        times = {"old": [], "new": []}
        for k in range(n_pairs + 1):  # the first pair fills the caches and is not counted
            for code in ("old", "new"):
                with tempfile.TemporaryDirectory(prefix="hosedrogue-steps-") as out:
                    cpu, _ = run_once([sys.executable, "-m", "hosedrogue", *argv], cache[code], out,
                                      {"PYTHONPATH": str(src[code])})
                if k:
                    times[code].append(cpu)
        o, n = statistics.median(times["old"]), statistics.median(times["new"])
        print(f"{name}: CPU s old {[round(x, 2) for x in times['old']]}, new {[round(x, 2) for x in times['new']]}; "
              f"medians {o:.2f} -> {n:.2f} ({n - o:+.2f} s)", flush=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true", help="compare every step with python-control's, bit for bit")
    ap.add_argument("--old", type=Path, help="the other checkout's src folder, to time against")
    ap.add_argument("--pairs", type=int, default=3, help="old/new pairs (default 3)")
    ap.add_argument("--full", action="store_true", help="also time the two sections at full settings")
    args = ap.parse_args(argv)
    if args.check:
        return 1 if check() else 0
    if args.old is None:
        ap.error("give --check or --old SRC")
    if not (args.old / "hosedrogue" / "__init__.py").is_file():
        ap.error(f"--old {args.old}: no hosedrogue package there")
    pairs(args.old, args.pairs, args.full)
    return 0


if __name__ == "__main__":
    sys.exit(main())
