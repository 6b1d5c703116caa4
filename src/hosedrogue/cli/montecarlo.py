"""``hosedrogue montecarlo``: a campaign of many turbulence seeds on Dask."""

from __future__ import annotations

import sys

from ..studies.executor import SYNCHRONOUS
from .options import EXIT_INCOMPLETE, prepare_out

NAME = "montecarlo"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(
        NAME, help="Monte Carlo campaign: many turbulence seeds of one scenario, in parallel",
        description=(
            "Run SCENARIO (a shipped name or a TOML path) RUNS times with turbulence seeds derived from "
            "(--seed, run index), on a local dask cluster or a dask scheduler, and write DIR/runs.csv "
            "(one row per run: peak and RMS lateral/vertical/radial drogue displacement [m] from the balance "
            "position inside the turbulence window, time fraction inside each capture radius [-], peak control "
            "forces [N]), DIR/summary.json and DIR/summary.csv (mean, std, 95 % confidence interval of the "
            "mean, median, 5th/95th percentiles), DIR/histograms.png and DIR/cdf.png. An engagement scenario "
            "([reel]/[probe]) runs the engagement driver and adds the columns result, miss_distance_m, "
            "closure_speed_m_s, a \"capture\" block (rate, Wilson 95 % interval, by result) and DIR/miss_cdf.png. "
            "Running again with the same settings resumes an interrupted campaign; results do not depend on --workers."))
    s.add_argument("scenario", metavar="SCENARIO", help="scenario name or TOML file")
    s.add_argument("--runs", metavar="N", type=int, required=True, help="number of runs (seeds) [-], >= 1")
    s.add_argument("--workers", metavar="K", type=int,
                   help="worker processes of the local dask cluster [-], >= 1 (default min(2, CPU count))")
    s.add_argument("--scheduler", metavar="ADDRESS",
                   help="address of a running dask scheduler (tcp://host:8786) instead of a local cluster, "
                        f"or '{SYNCHRONOUS}' to run in this process without dask")
    s.add_argument("--out", metavar="DIR", default="out/montecarlo", help="output folder (default out/montecarlo)")
    s.add_argument("--seed", metavar="S", type=int, default=0, help="campaign seed [-], >= 0 (default 0)")
    s.add_argument("--duration", metavar="S", type=float, help="simulated time per run [s] (overrides the file)")
    s.add_argument("--capture-radii", metavar="M", type=float, nargs="+",
                   help="capture radii [m], each > 0, for the time-inside-radius statistics "
                        "(default 0.1 0.305: the paper's positioning requirement and the basket radius)")
    s.add_argument("--keep-timeseries", action="store_true",
                   help="also write each run's time series (SI units) to DIR/runs/run_XXXXX.csv")
    s.add_argument("--compare-controller", action="store_true",
                   help="run every seed with the scenario's controller and with none (column 'controller')")
    s.add_argument("--view", action="store_true",
                   help="also write DIR/view.html: per controller, the runs with the smallest, the median and the "
                        "largest miss distance (engagement) or peak radial drogue offset, run again from their seeds "
                        "and shown side by side in 3D (their folders in DIR/view/)")
    s.add_argument("--verify-sample", metavar="N", type=int, default=0,
                   help="after the campaign, run N of its runs (chosen by --seed, the same in every process) again and "
                        "on twice the links at the refined step, compare every headline figure, and write "
                        "DIR/verification.json and DIR/verification.csv; summary.json's \"verification\" says which "
                        "figures were checked and whether they converged (default 0: none, the summary says "
                        "unverified). Runs in this process, each about 5-10 times the cost of a run")
    s.add_argument("--tolerance", metavar="REL", type=float, default=0.03,
                   help="relative tolerance of --verify-sample's 'converged' [-] (default 0.03)")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    s.set_defaults(func=run)


def _fmt(x: float | None, unit: str) -> str:
    return "n/a" if x is None else f"{x:.4g} {unit}".rstrip()


def _percent(x: float | None) -> str:
    return "n/a" if x is None else f"{100 * x:.1f} %"


def _print_verification(doc: dict | None, sample: int) -> None:
    if not sample or doc is None:
        return
    off = [k for k, f in doc["figures"].items() if not f["converged"]]
    print(f"verified runs {', '.join(map(str, doc['runs']))} (tolerance {100 * doc['tolerance']:g} %): "
          f"{len(doc['figures']) - len(off)} of {len(doc['figures'])} figures converged in every verified run"
          + (f"; not converged: {', '.join(off)}" if off else ""))


def run(args) -> int:
    """Run the campaign; print a short summary and the files. Exit 3 if any run stopped early.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    # here, not at the top: the model's modules (numba) load only when a campaign runs
    from ..results.statistics import DEFAULT_CAPTURE_RADII_M, capture_column
    from ..studies.campaign import run_campaign

    prepare_out(args.out)  # exists or can be made, writable: one line before any run
    radii = DEFAULT_CAPTURE_RADII_M if args.capture_radii is None else args.capture_radii
    summary = run_campaign(
        args.scenario, args.runs, args.out, workers=args.workers, scheduler=args.scheduler, seed=args.seed,
        capture_radii_m=radii, keep_timeseries=args.keep_timeseries,
        compare_controller=args.compare_controller, duration_s=args.duration, progress=not args.quiet,
        verify_sample=args.verify_sample, tolerance=args.tolerance,
    )
    radii = summary.settings["capture_radii_m"]
    for c in summary.settings["controllers"]:
        st = summary.statistics[c]
        peak = st["peak_radial_m"]
        lo, hi = peak["ci95_mean"]
        print(f"controller {c}: {summary.completed_fraction[c]:.1%} of runs completed; peak radial displacement "
              f"mean {_fmt(peak['mean'], 'm')} (95 % CI {_fmt(lo, 'm')} to {_fmt(hi, 'm')})")
        inside = ", ".join(f"{r:g} m {_percent(st[capture_column(r)]['mean'])}" for r in radii)
        print(f"  time inside capture radius (mean over runs): {inside}")
    cap = summary.capture
    if cap is not None and cap["runs"]:
        lo, hi = cap["ci95"]
        by = ", ".join(f"{k} {v}" for k, v in cap["by_result"].items() if v)
        print(f"capture rate {cap['rate']:.3f} (Wilson 95 %: {lo:.3f}-{hi:.3f}) over {cap['runs']} runs: {by}")
    print(f"{summary.new_runs} runs simulated, {len(summary.runs) - summary.new_runs} resumed")
    files = [summary.out_dir / "runs.csv", summary.out_dir / "campaign.json", *summary.files]
    _print_verification(summary.verification, args.verify_sample)
    if args.verify_sample:
        files += [summary.out_dir / f for f in summary.verification["files"]]
    for p in files:
        print(f"wrote {p}")
    if args.view:
        from ..viewer.campaign import write_campaign_view

        page, picks = write_campaign_view(summary, summary.out_dir / "view.html", summary.out_dir / "view")
        shown = ", ".join(f"run {p['run']} {p['controller']} ({p['why']})" for p in picks)
        print(f"wrote {page} ({shown})")
    incomplete = int((~summary.runs["completed"].astype(bool)).sum())
    if incomplete:
        print(f"hosedrogue: {incomplete} runs stopped early (completed = false in runs.csv)", file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0
