"""Two campaigns started together on one folder, REPEATS times: does exactly one run each time?

Each repetition starts ``hosedrogue montecarlo paper-turbulence --duration 11 --seed 0`` (the
shipped case, 1 s of its turbulence, 20 links) and the same with ``--seed 5``
as two processes at once on one empty ``--out`` folder (run in this machine's processes, without
dask), waits for both and checks: one exits 0, the other exits 2 with one line on stderr ("another
campaign ... is using it" or "different settings"), and the folder's campaign.json, runs.csv,
summary.json and summary.csv are byte for byte those of an uninterrupted campaign of the winner's
seed, run first in a folder of its own. Prints one line per repetition and the count.

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


def main(repeats: int = 20, runs: int = 40) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        refs = {}
        for seed in SEEDS:
            refs[seed] = tmp / f"ref{seed}"
            subprocess.run(command(runs, seed, refs[seed]), check=True, capture_output=True)
        good = 0
        for k in range(repeats):
            out = tmp / f"race{k}"
            procs = {s: subprocess.Popen(command(runs, s, out), stdout=subprocess.PIPE,
                                         stderr=subprocess.PIPE, text=True) for s in SEEDS}
            done = {s: (p.wait(), p.stdout.read(), p.stderr.read()) for s, p in procs.items()}
            winners = [s for s, (code, _, _) in done.items() if code == 0]
            verdict = "bad"
            if len(winners) == 1:
                winner, loser = winners[0], SEEDS[1 - SEEDS.index(winners[0])]
                code, _, err = done[loser]
                same = all((out / f).read_bytes() == (refs[winner] / f).read_bytes() for f in FILES)
                one_line = code == 2 and err.count("\n") == 1
                if same and one_line:
                    good += 1
                    verdict = "ok"
                why = err.strip()
            else:
                why = f"exit statuses {[d[0] for d in done.values()]}"
            print(f"{k + 1:2d}: {verdict}: seed {winners} ran; refused: {why}", flush=True)
        print(f"{good} of {repeats}: one campaign ran, the other was refused in one line, and the folder equals "
              f"an uninterrupted campaign of the winner's seed ({runs} runs)")
    return 0 if good == repeats else 1


if __name__ == "__main__":
    sys.exit(main(*(int(a) for a in sys.argv[1:3])))
