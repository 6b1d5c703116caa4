"""What a new user waits for: ``make reproduce`` and ``make test`` in a fresh clone, as the README
runs them (its own ``.venv``, pip's cache as the machine has it, numba's cache empty: the clone's
own ``__pycache__``), the wall time of each beside the target, and the report's stage table.

Each command runs in a new clone of this repository's committed HEAD (``git clone``), so nothing
of the working tree or of an earlier build is reused. ``NUMBA_CACHE_DIR`` is removed from the
environment (a kept cache would hide the compile a fresh install pays). The figures are wall
seconds on the machine as it is: run it on a quiet machine, and compare before and after a
change in pairs measured together. Printed, never asserted.

Targets (the main-job issue, on the project's 2-core machine): each command at most 300 s.

Run:  .venv/bin/python benchmarks/fresh_clone.py [--reproduce] [--test] [--keep] [--json]
      (neither flag: both)
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

ROOT = Path(__file__).resolve().parents[1]
TARGET_S = 300.0


def _clone(parent: Path) -> Path:
    path = parent / "hosedrogue"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(path)], check=True)
    return path


def _make(clone: Path, target: str) -> dict:
    """``make TARGET`` in the clone: wall seconds of the set-up and of the whole, and the exit status."""
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "VIRTUAL_ENV", "PYTHONPATH")}
    t0 = time.perf_counter()
    setup = subprocess.run(["make", ".venv/.installed"], cwd=clone, env=env, capture_output=True, text=True)
    t1 = time.perf_counter()
    run = subprocess.run(["make", target], cwd=clone, env=env, capture_output=True, text=True)
    t2 = time.perf_counter()
    out = {"command": f"make {target}", "exit_status": run.returncode or setup.returncode,
           "setup_s": t1 - t0, "wall_s": t2 - t0, "target_s": TARGET_S}
    if out["exit_status"]:
        out["tail"] = (run.stdout + run.stderr)[-2000:]
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--reproduce", action="store_true", help="time make reproduce")
    p.add_argument("--test", action="store_true", help="time make test")
    p.add_argument("--keep", action="store_true", help="keep the clones (their paths are printed)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    args = p.parse_args(argv)
    targets = [t for t, on in (("reproduce", args.reproduce), ("test", args.test)) if on] or ["reproduce", "test"]
    results = []
    for target in targets:
        parent = Path(tempfile.mkdtemp(prefix=f"hosedrogue-fresh-{target}-"))
        try:
            clone = _clone(parent)
            r = _make(clone, target)
            report = clone / "out" / "report" / "report.json"
            if target == "reproduce" and report.exists():
                build = json.loads(report.read_text())["build"]
                r["build_s"], r["workers"] = build["elapsed_s"], build.get("workers")
                r["stage_times_s"] = build["stage_times_s"]
                r["cpu_s"], r["stage_cpu_s"] = build.get("cpu_s"), build.get("stage_cpu_s", {})
            if args.keep:
                r["clone"] = str(clone)
            results.append(r)
        finally:
            if not args.keep:
                shutil.rmtree(parent, ignore_errors=True)
    if args.json:
        print(json.dumps({"results": results}, indent=2))
        return 0
    for r in results:
        verdict = "met" if r["wall_s"] <= r["target_s"] else "not met"
        print(f"{r['command']}: {r['wall_s']:.0f} s wall (set-up {r['setup_s']:.0f} s), exit {r['exit_status']}; "
              f"target {r['target_s']:.0f} s: {verdict}")
        if r.get("cpu_s") is not None:
            print(f"  CPU {r['cpu_s']:.0f} s over every process of the build")
        cpu = r.get("stage_cpu_s", {})
        for label, s in sorted(r.get("stage_times_s", {}).items(), key=lambda kv: -kv[1]):
            print(f"  {s:7.1f} s  {label}" + (f" (CPU {cpu[label]:.1f} s)" if label in cpu else ""))
        if "tail" in r:
            print(r["tail"], file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
