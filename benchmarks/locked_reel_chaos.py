"""Why the locked reel's whip has no converged peak: its peaks against micrometres of the probe's
path, printed as figures (never asserted; docs/engagement.md, "Link-count convergence").

``engage-locked`` (and, for comparison, ``engage-response``) is run with the probe's lateral
offset ``probe.offset_y_m`` moved by 0, 1, 2, 3, 10 um, 0.1 and 1 mm - changes far below any
tolerance of a real probe's path - on the shipped mesh (160 links, the SDIRK at 2 ms for the
locked reel, 5 ms for the responsive one) and, with ``--doubled``, on the link-doubling mesh (320
links at half the step). For each peak the smallest,
median and largest value over the offsets and the spread (largest minus smallest over the
median) are printed. A peak whose spread under such a perturbation exceeds the 3 % link-doubling
bound cannot converge to it with the mesh: the run is chaotic, and a mesh change acts as one more
perturbation. The responsive reel's peaks, made by one snap of a hose that is then taut, move
by a few hundredths of a per cent.

Run:  .venv/bin/python benchmarks/locked_reel_chaos.py [--doubled]
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from hosedrogue.scenarios import load_scenario
from hosedrogue.scenarios.runner import run
from hosedrogue.studies.convergence import with_links

OFFSETS_M = (0.0, 1e-6, 2e-6, 3e-6, 1e-5, 1e-4, 1e-3)
PEAKS = ("peak_exit_tension_n", "peak_tension_rise_n", "peak_drogue_tension_n", "peak_probe_load_n", "peak_slack_m")


def offset(scenario, dy):
    """The scenario with the probe's lateral offset ``dy`` [m]."""
    probe = dataclasses.replace(scenario.engagement.probe, offset_y_m=dy)
    return dataclasses.replace(scenario, engagement=dataclasses.replace(scenario.engagement, probe=probe))


def spread(name, scenario):
    """Print each peak's range over the offsets."""
    rows = [run(offset(scenario, dy)).summary() for dy in OFFSETS_M]
    p = scenario.params
    print(f"{name}: {p.hose.links} links, h = {p.numerics.step_s * 1e3:g} ms, probe offsets "
          f"{', '.join(f'{dy:g}' for dy in OFFSETS_M)} m")
    for key in PEAKS:
        v = np.array([r[key] for r in rows])
        med = float(np.median(v))
        print(f"    {key}: min {v.min():.5g}, median {med:.5g}, max {v.max():.5g}; "
              f"spread {100 * (v.max() - v.min()) / med:.2f} % of the median")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--doubled", action="store_true", help="also the 320-link mesh (about 10 s per run)")
    args = ap.parse_args(argv)
    for name in ("engage-locked", "engage-response"):
        sc = load_scenario(name)
        spread(name, sc)
        if args.doubled:
            spread(f"{name} (doubled)", with_links(sc, 2 * sc.params.hose.links))


if __name__ == "__main__":
    main()
