"""Issue 32's check of the locked reel as a distribution (figures printed, never asserted): the
median and the 95th percentile of each peak of ``engage-locked`` over N copies whose probe starts
displaced within a disc of 1 um (the copies of ``hosedrogue simulate engage-locked --ensemble N
--perturb probe-offset=1e-6 --verify``), on the shipped mesh (160 links, the SDIRK at 2 ms) and on
twice the links at half the step (320 links at 1 ms); the change of each from 160 to 320 links
against the issue's 5 %, with its bootstrap interval (95 %, percentile method, the two meshes'
copies resampled independently: a chaotic flail forgets its micrometre within the run, so copy
``i`` on one mesh says nothing of copy ``i`` on the other). The check holds for a quantile when
its change's interval lies within +-5 %; it fails when the interval lies outside; otherwise the
copies cannot tell (more copies narrow the interval as 1/sqrt(N)). Also printed: the two-sample
Kolmogorov-Smirnov test of the two meshes' copies (scipy.stats.ks_2samp: a small p says the
distributions differ as a whole) and how many fine-mesh copies lie above the coarse mesh's largest.

Each copy's figures are appended to ``--record`` (JSON lines) as it finishes and read back on the
next start: a long run can be stopped and resumed, and ``--copies`` raised later reuses the copies
already run (copy ``i`` is the same perturbation in every process: studies/ensemble.py).

Run:  PYTHONPATH=src .venv/bin/python benchmarks/locked_reel_distribution.py [--copies 64] [--workers 1]
      [--record locked_reel_distribution.jsonl]
(CPU: ~1.5 s per copy at 160 links, ~15-20 s at 320 links; 64 copies of each about 20 CPU-minutes)
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from hosedrogue.jsonio import dumps
from hosedrogue.scenarios import load_scenario
from hosedrogue.studies.ensemble import (BOOTSTRAP_RESAMPLES, BOOTSTRAP_SEED, CONFIDENCE, distribution,
                                         parse_perturbation, perturbed)
from hosedrogue.studies.verify import refined_scenario

PEAKS = ("peak_exit_tension_n", "peak_tension_rise_n", "peak_drogue_tension_n", "peak_probe_load_n", "peak_slack_m")
BOUND = 0.05  # the bound on the change of the median and the 95th percentile
QUANTILE = {"median": 0.5, "p95": 0.95}


def _copy(args):
    """One copy's headline figures and whether it completed (run in a process of its own if asked)."""
    from hosedrogue.results.convergence import headline_figures
    from hosedrogue.scenarios.runner import run

    sc, _ = args
    r = run(sc)
    return headline_figures(r), bool(r.completed)


def _load(path: str) -> dict:
    """(links, index) -> (figures, completed) of the copies already recorded."""
    done = {}
    try:
        with open(path, encoding="utf-8") as f:
            for line in f:
                if line.strip():
                    rec = json.loads(line)
                    done[(rec["links"], rec["index"])] = (rec["figures"], rec["completed"])
    except FileNotFoundError:
        pass
    return done


def _run_mesh(sc, kind, size, copies, workers, record, done) -> list:
    links = sc.params.hose.links
    todo = [i for i in range(copies) if (links, i) not in done]
    jobs = [(perturbed(sc, kind, size, i), i) for i in todo]
    pool = None
    if workers <= 1:
        results = map(_copy, jobs)
    else:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"))
        results = pool.map(_copy, jobs)
    for i, (figures, completed) in zip(todo, results):
        done[(links, i)] = (figures, completed)
        with open(record, "a", encoding="utf-8") as f:
            f.write(dumps({"links": links, "index": i, "figures": figures, "completed": completed}) + "\n")
    if pool is not None:
        pool.shutdown()
    return [done[(links, i)] for i in range(copies)]


def change_interval(a, b, q: float):
    """The relative change q(b)/q(a) - 1 of the q-quantile and its bootstrap interval (the module's rules).

    Parameters
    ----------
    a, b : sequence of float
        The figure's values on the coarse and on the fine mesh.
    q : float
        The quantile [-].

    Returns
    -------
    tuple of (float, list of float)
    """
    import scipy.stats

    a, b = np.asarray(a, float), np.asarray(b, float)

    def stat(x, y, axis=-1):
        return np.quantile(y, q, axis=axis) / np.quantile(x, q, axis=axis) - 1.0

    res = scipy.stats.bootstrap((a, b), stat, paired=False, confidence_level=CONFIDENCE,
                                n_resamples=BOOTSTRAP_RESAMPLES, method="percentile",
                                random_state=np.random.default_rng(BOOTSTRAP_SEED))
    return float(stat(a, b)), [float(res.confidence_interval.low), float(res.confidence_interval.high)]


def _verdict(ci) -> str:
    if -BOUND < ci[0] and ci[1] < BOUND:
        return "holds: the interval lies within +-5 %"
    if ci[0] >= BOUND or ci[1] <= -BOUND:
        return "FAILS: the interval lies beyond 5 %"
    return "undecided: the interval straddles 5 %"


def _ci(v) -> str:
    return "none" if v is None else f"[{v[0]:.5g}, {v[1]:.5g}]"


def _report(key, coarse, fine, links) -> None:
    a = [f[key] for f, _ in coarse if f[key] is not None]
    b = [f[key] for f, _ in fine if f[key] is not None]
    print(f"{key}:")
    for mesh, v in zip(links, (a, b)):
        d = distribution(v)
        print(f"    {mesh} links: median {d['median']:.5g} {_ci(d['median_interval'])}, 5 % {d['p05']:.5g}, "
              f"95 % {d['p95']:.5g} {_ci(d['p95_interval'])}, range [{d['min']:.5g}, {d['max']:.5g}]")
    import scipy.stats

    print(f"    the two meshes' distributions: Kolmogorov-Smirnov p = {scipy.stats.ks_2samp(a, b).pvalue:.3g}; "
          f"{sum(x > max(a) for x in b)} of {len(b)} copies on {links[1]} links above the largest on {links[0]}")
    for name, q in QUANTILE.items():
        change, ci = change_interval(a, b, q)
        print(f"    {name}: {100 * change:+.2f} % from {links[0]} to {links[1]} links, 95 % interval "
              f"[{100 * ci[0]:+.2f}, {100 * ci[1]:+.2f}] %: {_verdict(ci)}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--copies", type=int, default=64, help="perturbed copies per mesh (default 64)")
    ap.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    ap.add_argument("--size", type=float, default=1e-6, help="radius of the probe's offset disc [m] (default 1e-6)")
    ap.add_argument("--record", default="locked_reel_distribution.jsonl",
                    help="JSON-lines file of every copy's figures, read back on the next start")
    args = ap.parse_args(argv)
    kind, size = parse_perturbation(f"probe-offset={args.size!r}")
    sc = load_scenario("engage-locked")
    fine_sc = refined_scenario(sc)
    done = _load(args.record)
    t0 = time.perf_counter()
    coarse = _run_mesh(sc, kind, size, args.copies, args.workers, args.record, done)
    fine = _run_mesh(fine_sc, kind, size, args.copies, args.workers, args.record, done)
    links = (sc.params.hose.links, fine_sc.params.hose.links)
    print(f"engage-locked: {args.copies} copies per mesh, probe offset within {args.size:g} m; {links[0]} links at "
          f"{sc.params.numerics.step_s:g} s against {links[1]} links at {fine_sc.params.numerics.step_s:g} s; "
          f"incomplete runs {sum(not c for _, c in coarse + fine)}; wall of this start {time.perf_counter() - t0:.0f} s")
    for key in PEAKS:
        _report(key, coarse, fine, links)
    return 0


if __name__ == "__main__":
    main()
