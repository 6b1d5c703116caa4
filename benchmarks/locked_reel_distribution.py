"""Issue 32's check of the locked reel as a distribution (figures printed, never asserted): the
median and the 95th percentile of each peak of ``engage-locked`` over at least 32 copies whose
probe starts displaced within a disc of 1 um (``hosedrogue simulate engage-locked --ensemble 32
--perturb probe-offset=1e-6 --verify``), on the shipped mesh (160 links, the SDIRK at 2 ms) and on
twice the links at half the step (320 links at 1 ms); the change of each from 160 to 320 links
against the issue's 5 %, with the bootstrap intervals (95 %) that say how much of a change the 32
samples can resolve.

Run:  PYTHONPATH=src .venv/bin/python benchmarks/locked_reel_distribution.py [--copies 32] [--workers 2]
(about 40 CPU-minutes: 32 runs of ~1.5 s and 32 of ~15-20 s CPU, on both cores by default)
"""

from __future__ import annotations

import argparse
import time

from hosedrogue.scenarios import load_scenario
from hosedrogue.studies.ensemble import run_ensemble

PEAKS = ("peak_exit_tension_n", "peak_tension_rise_n", "peak_drogue_tension_n", "peak_probe_load_n", "peak_slack_m")
BOUND = 0.05  # the bound on the change of the median and the 95th percentile


def _ci(v) -> str:
    return "none" if v is None else f"[{v[0]:.5g}, {v[1]:.5g}]"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--copies", type=int, default=32, help="perturbed copies per mesh (default 32)")
    ap.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    ap.add_argument("--size", type=float, default=1e-6, help="radius of the probe's offset disc [m] (default 1e-6)")
    args = ap.parse_args(argv)
    sc = load_scenario("engage-locked")
    t0 = time.perf_counter()
    ens = run_ensemble(sc, args.copies, f"probe-offset={args.size:g}", verify=True, workers=args.workers)
    wall = time.perf_counter() - t0
    v = ens.verification
    fine = v["refined_distributions"]
    print(f"engage-locked: {args.copies} copies, probe offset within {args.size:g} m; {ens.links} links at "
          f"{ens.step_s:g} s against {v['refined']['links']} links at {v['refined']['step_s']:g} s; "
          f"incomplete runs {sum(not c for c in ens.completed)}; wall {wall:.0f} s")
    for key in PEAKS:
        a, b = ens.distributions[key], fine[key]
        print(f"{key}:")
        for mesh, d in ((ens.links, a), (v["refined"]["links"], b)):
            print(f"    {mesh} links: median {d['median']:.5g} {_ci(d['median_interval'])}, 5 % {d['p05']:.5g}, "
                  f"95 % {d['p95']:.5g} {_ci(d['p95_interval'])}, range [{d['min']:.5g}, {d['max']:.5g}]")
        for q in ("median", "p95"):
            change = (b[q] - a[q]) / abs(a[q])
            print(f"    {q}: {100 * change:+.2f} % from {ens.links} to {v['refined']['links']} links "
                  f"({'within' if abs(change) < BOUND else 'BEYOND'} 5 %)")
    return 0


if __name__ == "__main__":
    main()
