"""Two campaigns started together on one folder, REPEATS times: does exactly one run each time?

Each repetition starts ``hosedrogue montecarlo paper-turbulence --duration 11 --seed 0`` (the
shipped case, 1 s of its turbulence, 20 links) and the same with ``--seed 5`` as two processes at
once on one empty ``--out`` folder (run in this machine's processes, without dask), waits for both
and checks: exactly one ran all its runs, the other exited 2 with one line on stderr ("another
campaign ... is using it" or "different settings"), and the folder's campaign.json, runs.csv,
summary.json and summary.csv are byte for byte those of an uninterrupted campaign of the winner's
seed, run first in a folder of its own. Then the same with both at seed 0, where the loser is
refused by the lock alone (or, started after the winner ended, resumes with nothing to do).
Prints one line per repetition and the counts.

Run:  PYTHONPATH=src .venv/bin/python tools/campaign_race.py [REPEATS] [RUNS]   (default 20, 40)
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

FILES = ("campaign.json", "runs.csv", "summary.json", "summary.csv")
SEEDS = (0, 5)


def command(runs: int, seed: int, out: Path) -> list[str]:
    return [sys.executable, "-m", "hosedrogue", "montecarlo", "paper-turbulence", "--duration", "11", "--runs",
            str(runs), "--seed", str(seed), "--scheduler", "synchronous", "--quiet", "--out", str(out)]


def race(out: Path, seeds: tuple[int, int], runs: int, refs: dict) -> tuple[str, str]:
    """Start two campaigns of ``seeds`` together on ``out``; return (verdict, why)."""
    procs = [subprocess.Popen(command(runs, s, out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for s in seeds]
    done = [(p.wait(), p.stdout.read(), p.stderr.read()) for p in procs]
    ran = [k for k, (code, out_text, _) in enumerate(done) if code == 0 and f"{runs} runs simulated" in out_text]
    if len(ran) != 1:
        return "bad", f"exit statuses {[d[0] for d in done]}, {len(ran)} ran all {runs} runs"
    code, out_text, err = done[1 - ran[0]]
    same = all((out / f).read_bytes() == (refs[seeds[ran[0]]] / f).read_bytes() for f in FILES)
    if not same:
        return "bad", "the folder differs from an uninterrupted campaign"
    if code == 2 and err.count("\n") == 1:
        return ("locked" if "another campaign" in err else "settings"), err.strip()
    if code == 0 and f"0 runs simulated, {runs} resumed" in out_text:  # same seed, started after the first ended
        return "resumed", "the second found every run done"
    return "bad", f"the other: exit {code}, {err.strip()}"


def main(repeats: int = 20, runs: int = 40) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        refs = {}
        for seed in SEEDS:
            refs[seed] = tmp / f"ref{seed}"
            subprocess.run(command(runs, seed, refs[seed]), check=True, capture_output=True)
        bad = 0
        for pair in (SEEDS, (SEEDS[0], SEEDS[0])):
            counts: dict = {}
            for k in range(repeats):
                verdict, why = race(tmp / f"race{pair[1]}-{k}", pair, runs, refs)
                counts[verdict] = counts.get(verdict, 0) + 1
                print(f"seeds {pair} {k + 1:2d}: {verdict}: {why}", flush=True)
            bad += counts.get("bad", 0)
            print(f"seeds {pair}: {repeats - counts.get('bad', 0)} of {repeats} good: exactly one campaign ran all "
                  f"{runs} runs and the folder equals an uninterrupted campaign of its seed; the other was refused "
                  f"by the lock {counts.get('locked', 0)} times, for other settings {counts.get('settings', 0)} "
                  f"times, resumed a finished campaign {counts.get('resumed', 0)} times", flush=True)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(*(int(a) for a in sys.argv[1:3])))
