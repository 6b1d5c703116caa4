"""Issue 32's check of ``--verify`` on a case of a user's own (never asserted here; figures printed):
every figure that the verification of ``benchmarks/scenarios/wing-pod-response.toml`` (a 22.9 m,
3.6 kg/m wing-pod hose at 128 m/s and 6100 m, closing at 2.0 m/s, responsive reel; 229 links at 5
ms) flags converged must agree within the tolerance with independent runs:

* ``x2``: the user's file with ``[hose] links`` and ``[numerics] step_s`` written by hand at twice
  the links and half the step (458 links, 2.5 ms; built from TOML text, not by the verification's
  own refinement): it must give the refined figures, so every converged figure agrees;
* ``x4``: four times the links at a quarter of the step (916 links at 1.25 ms; ``--x4``, about
  80 s): a finer reference, against which the run's converged figures are checked too.

Prints per figure: the run's value, the refined value (458 links, 2.5 ms) and the verdict, each
independent run's value, the change from the run's value to it and whether a converged figure
agrees; then the count of converged figures that do not agree.

Run:  PYTHONPATH=src .venv/bin/python benchmarks/verify_user_case.py [--duration S] [--tolerance REL]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from hosedrogue.results.convergence import DEFAULT_TOLERANCE, absolute_floor, headline_figures
from hosedrogue.scenarios import load_scenario
from hosedrogue.scenarios.runner import run
from hosedrogue.studies.convergence import with_links
from hosedrogue.studies.verify import verify_run

CASE = Path(__file__).parent / "scenarios" / "wing-pod-response.toml"


def by_hand(duration_s: float | None):
    """The user's file at twice its links and half its step, written as TOML text (independent of
    the verification's refinement)."""
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "wing-pod-x2.toml"
        path.write_text(f'[scenario]\nextends = "{CASE}"\nname = "wing-pod-x2"\n'
                        '[hose]\nlinks = 458\n[numerics]\nstep_s = 0.0025\noutput_every = 4\n')
        return load_scenario(str(path)).with_overrides(duration_s=duration_s)


def agreement(key: str, a, c, tolerance: float):
    """(relative change, agrees) of the run's value a and an independent value c."""
    if a is None or c is None:
        return None, None
    scale = max(abs(a), abs(c))
    rel = abs(c - a) / scale if scale else 0.0
    return rel, bool(abs(c - a) <= tolerance * scale or abs(c - a) <= absolute_floor(key))


def check(scenario, independents: dict, tolerance: float = DEFAULT_TOLERANCE) -> tuple[dict, dict, dict]:
    """The verification's figures and each independent run's: (figures, {name: figures}, timings [s])."""
    t0 = time.perf_counter()
    verified = verify_run(scenario, tolerance)
    times = {"verify": time.perf_counter() - t0}
    out = {}
    for name, sc in independents.items():
        t0 = time.perf_counter()
        out[name] = headline_figures(run(sc))
        times[name] = time.perf_counter() - t0
    return verified.verification["figures"], out, times


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=None, help="simulated time [s] (default the file's 12 s)")
    ap.add_argument("--tolerance", type=float, default=DEFAULT_TOLERANCE, help="relative tolerance [-]")
    ap.add_argument("--x4", action="store_true", help="also the run on four times the links (about 80 s)")
    args = ap.parse_args(argv)
    sc = load_scenario(str(CASE)).with_overrides(duration_s=args.duration)
    independents = {"x2": by_hand(args.duration)}
    if args.x4:
        independents["x4"] = with_links(sc, 4 * sc.params.hose.links)
    figures, ind, times = check(sc, independents, args.tolerance)
    p = sc.params
    print(f"{sc.name}: {p.hose.links} links at {p.numerics.step_s:g} s, verified against {2 * p.hose.links} links; "
          + "; ".join(f"{k}: {s.params.hose.links} links at {s.params.numerics.step_s:g} s" for k, s in independents.items())
          + f"; tolerance {100 * args.tolerance:g} %; {sc.duration_s:g} s simulated")
    print(f"{'figure':30s} {'run':>10s} {'refined':>10s} {'verdict':>13s}"
          + "".join(f" {k:>10s} {'change':>8s} agrees" for k in independents))
    bad = dict.fromkeys(independents, 0)
    for key, f in figures.items():
        line = (f"{key:30s} {_g(f['value']):>10s} {_g(f['refined_value']):>10s} "
                f"{'converged' if f['converged'] else 'NOT conv.':>13s}")
        for name in independents:
            c = ind[name].get(key)
            rel, agrees = agreement(key, f["value"], c, args.tolerance)
            bad[name] += bool(f["converged"] and agrees is False)
            line += (f" {_g(c):>10s} {'' if rel is None else f'{100 * rel:.2f} %':>8s} "
                     f"{'-' if agrees is None else ('yes' if agrees else 'no'):>6s}")
        print(line)
    for name in independents:
        print(f"converged figures that do not agree with {name}: {bad[name]}")
    print("cost (wall clock): " + ", ".join(f"{k} {v:.1f} s" for k, v in times.items()))
    return 0


def _g(v) -> str:
    return "none" if v is None else f"{v:.5g}"


if __name__ == "__main__":
    main()
