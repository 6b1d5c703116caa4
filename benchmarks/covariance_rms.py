"""The covariance analysis's predicted RMS drogue offset in moderate turbulence against the
nonlinear model's (the mean RMS of many seeds), printed as figures (docs/loop-analysis.md).

Cases (:data:`hosedrogue.studies.covariance_check.CASES`, the converged preset): the paper's and a
wing pod's, each open loop and with the paper's PID: continuous, sampled at 10 ms, and sampled at
5 ms with a sensor delay of one sample (:data:`LOOPS`). Each line: predicted RMS, the mean RMS of
``--runs`` seeds of ``--duration`` s, their difference, and the standard error of that mean
(computed from the predicted autocovariance). The issue's check: within 10 %.

Run:  .venv/bin/python benchmarks/covariance_rms.py              (20 seeds of 300 s: ~15 min on a core)
      .venv/bin/python benchmarks/covariance_rms.py --runs 4 --duration 60
"""

from __future__ import annotations

import argparse
import time

from hosedrogue.studies.covariance_check import CASES, case_params, compare_rms

#: The loops compared: label, closed, the PID's sample time [s], the sensor's delay [s].
LOOPS = (("open", False, 0.0, 0.0), ("PID", True, 0.0, 0.0), ("PID 10 ms", True, 0.01, 0.0),
         ("PID 5 ms + 5 ms", True, 0.005, 0.005))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=20, help="seeds per case [-] (default 20)")
    ap.add_argument("--duration", type=float, default=300.0, help="simulated time per run [s] (default 300)")
    ap.add_argument("--level", default="moderate", choices=("light", "moderate", "severe"))
    args = ap.parse_args()
    print(f"{args.level} turbulence, {args.runs} seeds of {args.duration:g} s each, converged preset")
    print(f"{'case':9s} {'loop':16s} {'axis':8s} {'predicted m':>12s} {'simulated m':>12s} {'diff %':>7s} "
          f"{'std err %':>9s}")
    for case in CASES:
        params = case_params(case, args.level)
        for loop, closed, T, delay in LOOPS:
            t0 = time.perf_counter()
            c = compare_rms(params, range(1, args.runs + 1), args.duration, closed, T, delay)
            for i, axis in enumerate(("lateral", "vertical")):
                print(f"{case:9s} {loop:16s} {axis:8s} {c.predicted_m[i]:12.5g} "
                      f"{c.simulated_m[i]:12.5g} {100 * c.difference[i]:7.2f} "
                      f"{100 * c.standard_error_m[i] / c.predicted_m[i]:9.2f}")
            print(f"  ({c.runs} runs completed, {time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
