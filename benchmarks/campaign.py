"""Speed and memory of Monte Carlo campaigns (issue 13), printed as figures (never asserted).

* wall time, runs per second and CPU time per run of a 1000-run campaign of each approach
  scenario (``approach-light``, ``approach-moderate``, ``approach-severe``: engagement runs of
  4.5 s, 20 links, RK4 at 5 ms), run as a user runs it: ``hosedrogue montecarlo SCENARIO --runs
  1000 --out TMP --quiet`` (the default execution: a local dask cluster of min(2, CPU count)
  single-threaded worker processes), the whole command timed (start-up, cluster, runs, summary
  and figures); target < 300 s each;
* the resident memory (RSS) of the campaign's client process during a 10 000-run campaign of
  ``approach-moderate``: that process is the ``hosedrogue montecarlo`` command itself, and it
  hosts the dask scheduler (a LocalCluster's scheduler runs in the process that creates it, on a
  thread of its own); the workers and their nannies are child processes. RSS is sampled every
  0.5 s from a thread of this script (psutil), the peak reported with the RSS when 1000, 5000 and
  10 000 rows were in runs.csv and its growth per 1000 runs; target < 500 MB. The workers' peak
  RSS is reported for context.

CPU time per run is the CPU time (user + system) of the worker processes over the campaign
divided by the runs: it includes their start-up and numba's cache loading, a few seconds in all.
The first campaign is preceded by a 4-run warm-up that fills numba's cache (compile time).

Run:  .venv/bin/python benchmarks/campaign.py                 (~6 min on 2 cores, idle)
      .venv/bin/python benchmarks/campaign.py --runs 100 --memory-runs 1000   (a smaller version)
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import psutil

APPROACH = ("approach-light", "approach-moderate", "approach-severe")
SPEED_TARGET_S = 300.0  # 1000 runs per scenario
MEMORY_TARGET_MB = 500.0  # client RSS for 10 000 runs
MB = 1e6
JSON = False  # --json: figures go to stderr as they come, the JSON document to stdout


class Sampler(threading.Thread):
    """Samples a process and its descendants every ``interval`` s: RSS of the process, its rows in
    ``runs.csv``, per-descendant peak RSS and last CPU times."""

    def __init__(self, pid: int, runs_csv: Path, checkpoints, interval: float = 0.5):
        super().__init__(daemon=True)
        self.proc = psutil.Process(pid)
        self.runs_csv = runs_csv
        self.interval = interval
        self.checkpoints = sorted(checkpoints)
        self.stop = threading.Event()
        self.samples = []  # (t [s], client RSS [B], rows)
        self.at_rows = {}  # checkpoint -> client RSS [B] at the first sample with >= that many rows
        self.peak = 0
        self.peak_during_runs = 0  # before the last row was written (summary and figures excluded)
        self.children_peak = {}  # pid -> (name, peak RSS [B])
        self.children_cpu = {}  # pid -> last user + system CPU [s]
        self.children_sum_peak = 0
        self._offset = 0
        self._rows = -1  # the header line
        self.t0 = time.perf_counter()

    def rows(self) -> int:
        try:
            with self.runs_csv.open("rb") as fh:
                fh.seek(self._offset)
                data = fh.read()
        except FileNotFoundError:
            return 0
        self._offset += len(data)
        self._rows += data.count(b"\n")
        return max(self._rows, 0)

    def sample(self) -> None:
        try:
            rss = self.proc.memory_info().rss
            children = self.proc.children(recursive=True)
        except psutil.NoSuchProcess:
            return
        rows = self.rows()
        self.samples.append((time.perf_counter() - self.t0, rss, rows))
        self.peak = max(self.peak, rss)
        if rows < self.checkpoints[-1]:
            self.peak_during_runs = max(self.peak_during_runs, rss)
        for c in self.checkpoints:
            if rows >= c and c not in self.at_rows:
                self.at_rows[c] = rss
        total = 0
        for child in children:
            try:
                with child.oneshot():
                    crss = child.memory_info().rss
                    cpu = child.cpu_times()
                    name = " ".join(child.cmdline()[1:4])[:60]
            except psutil.Error:
                continue
            total += crss
            old = self.children_peak.get(child.pid, (name, 0))
            self.children_peak[child.pid] = (old[0], max(old[1], crss))
            self.children_cpu[child.pid] = cpu.user + cpu.system
        self.children_sum_peak = max(self.children_sum_peak, total)

    def run(self) -> None:
        while not self.stop.is_set():
            self.sample()
            self.stop.wait(self.interval)


def campaign(scenario: str, runs: int, workers: int | None, checkpoints=(), interval: float = 0.5) -> dict:
    """Run ``hosedrogue montecarlo`` in a child process into a temporary folder, sampled by a
    :class:`Sampler`; its figures."""
    with tempfile.TemporaryDirectory(prefix="hosedrogue-bench-campaign-") as tmp:
        out = Path(tmp) / "out"
        cmd = [sys.executable, "-m", "hosedrogue", "montecarlo", scenario, "--runs", str(runs), "--out", str(out),
               "--quiet"]
        if workers is not None:
            cmd += ["--workers", str(workers)]
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        sampler = Sampler(proc.pid, out / "runs.csv", sorted({*checkpoints, runs}), interval)
        sampler.start()
        stdout, stderr = proc.communicate()
        wall = time.perf_counter() - t0
        sampler.stop.set()
        sampler.join()
        if proc.returncode != 0:
            raise SystemExit(f"{' '.join(cmd)} failed ({proc.returncode}):\n{stderr}")
        rows = sampler.rows()
        walls = [float(line.split(",")[2]) for line in (out / "timings.csv").read_text().splitlines()[1:]]
        summary = json.loads((out / "summary.json").read_text())
    worker_cpu = sum(sampler.children_cpu.values())
    children = sorted(sampler.children_peak.values(), key=lambda c: -c[1])
    return {
        "scenario": scenario,
        "runs": runs,
        "rows": rows,
        "workers": workers,
        "command": " ".join(["hosedrogue", *cmd[3:]]),
        "wall_s": wall,
        "runs_per_s": runs / wall,
        "worker_cpu_per_run_s": worker_cpu / runs,
        "run_wall_mean_s": sum(walls) / len(walls),  # timings.csv: each run's wall on its worker
        "capture_rate": (summary.get("capture") or {}).get("rate"),
        "client_peak_rss_mb": sampler.peak / MB,
        "client_peak_rss_during_runs_mb": sampler.peak_during_runs / MB,
        "client_rss_at_rows_mb": {str(k): v / MB for k, v in sorted(sampler.at_rows.items())},
        "child_processes": len(sampler.children_peak),
        "child_peak_rss_mb": [p / MB for _, p in children],
        "child_commands": [name for name, _ in children],
        "children_sum_peak_rss_mb": sampler.children_sum_peak / MB,
        "samples": len(sampler.samples),
        # (time [s], client RSS [MB], rows) about every 30 s
        "client_rss_trace": [(round(t, 1), round(rss / MB, 1), rows) for t, rss, rows in
                             sampler.samples[::max(1, round(30 / interval))]],
    }


def growth_per_1000(result: dict) -> float | None:
    """Client RSS growth per 1000 runs between the first and last checkpoint [MB]."""
    at = {int(k): v for k, v in result["client_rss_at_rows_mb"].items()}
    if len(at) < 2:
        return None
    lo, hi = min(at), max(at)
    return (at[hi] - at[lo]) / (hi - lo) * 1000


def say(*args) -> None:
    """Print a figure now (to stderr with --json, whose document goes to stdout at the end)."""
    print(*args, file=sys.stderr if JSON else sys.stdout, flush=True)


def print_speed(r: dict) -> None:
    """The speed figures of one campaign, with the target."""
    verdict = "met" if r["wall_s"] < SPEED_TARGET_S * r["runs"] / 1000 else "MISSED"
    say(f"{r['scenario']}: {r['runs']} runs in {r['wall_s']:.1f} s wall ({r['runs_per_s']:.2f} runs/s); "
          f"CPU per run {r['worker_cpu_per_run_s'] * 1e3:.0f} ms (workers), each run's wall on its worker "
          f"{r['run_wall_mean_s'] * 1e3:.0f} ms; capture rate {r['capture_rate']}; client peak RSS "
          f"{r['client_peak_rss_mb']:.0f} MB  [target < {SPEED_TARGET_S * r['runs'] / 1000:.0f} s for "
          f"{r['runs']} runs: {verdict}]")


def print_memory(r: dict) -> None:
    """The memory figures of one campaign, with the target."""
    verdict = "met" if r["client_peak_rss_mb"] < MEMORY_TARGET_MB else "MISSED"
    at = ", ".join(f"{int(k)} runs {v:.0f} MB" for k, v in r["client_rss_at_rows_mb"].items())
    g = growth_per_1000(r)
    say(f"{r['scenario']}, {r['runs']} runs in {r['wall_s']:.0f} s: client (the montecarlo command, scheduler "
          f"in-process) peak RSS {r['client_peak_rss_mb']:.0f} MB ({r['client_peak_rss_during_runs_mb']:.0f} MB "
          f"while runs were written, the rest in the summary and figures); RSS at {at}; growth "
          f"{'-' if g is None else f'{g:+.1f} MB'} per 1000 runs  [target < {MEMORY_TARGET_MB:.0f} MB: {verdict}]")
    say(f"  child processes ({r['child_processes']}: the dask workers, multiprocessing's resource tracker): peak RSS "
          f"{', '.join(f'{p:.0f}' for p in r['child_peak_rss_mb'])} MB, together at most "
          f"{r['children_sum_peak_rss_mb']:.0f} MB; {r['samples']} samples")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenarios", nargs="+", default=list(APPROACH), metavar="NAME",
                    help="scenarios of the speed check (default: the three approach scenarios)")
    ap.add_argument("--runs", type=int, default=1000, help="runs per scenario of the speed check (0: skip it)")
    ap.add_argument("--memory-scenario", default="approach-moderate", metavar="NAME",
                    help="scenario of the memory check (default approach-moderate)")
    ap.add_argument("--memory-runs", type=int, default=10000,
                    help="runs of the memory check (0: skip it; default 10000)")
    ap.add_argument("--workers", type=int, default=None,
                    help="worker processes (default: the command's own, min(2, CPU count))")
    ap.add_argument("--interval", type=float, default=0.5, help="RSS sampling interval [s]")
    ap.add_argument("--no-warmup", action="store_true", help="skip the 4-run warm-up (numba cache)")
    ap.add_argument("--json", action="store_true", help="print one JSON document instead of text")
    args = ap.parse_args(argv)
    global JSON
    JSON = args.json

    report = {"machine": {"cpus": os.cpu_count(), "memory_gb": psutil.virtual_memory().total / 1e9,
                          "load_average_start": os.getloadavg()},
              "date": time.strftime("%Y-%m-%d"), "speed": [], "memory": None}
    if not args.no_warmup:
        t0 = time.perf_counter()
        campaign(args.memory_scenario, 4, args.workers)
        report["warmup_s"] = time.perf_counter() - t0
        say(f"warm-up (4 runs, fills numba's cache): {report['warmup_s']:.1f} s")
    if args.runs > 0:
        for name in args.scenarios:
            r = campaign(name, args.runs, args.workers, interval=args.interval)
            report["speed"].append(r)
            print_speed(r)
    if args.memory_runs > 0:
        n = args.memory_runs
        checkpoints = [c for c in (1000, n // 2, n) if c <= n] if n >= 2000 else [n // 10 or 1, n // 2 or 1, n]
        r = campaign(args.memory_scenario, n, args.workers, checkpoints=checkpoints, interval=args.interval)
        r["client_rss_growth_per_1000_runs_mb"] = growth_per_1000(r)
        report["memory"] = r
        print_memory(r)
    report["machine"]["load_average_end"] = os.getloadavg()
    say(f"load average at start {report['machine']['load_average_start'][0]:.1f}, "
              f"at end {report['machine']['load_average_end'][0]:.1f} ({os.cpu_count()} CPUs)")
    if args.json:
        print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
