"""``hosedrogue simulate``: run a scenario and write its time series."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

from .options import EXIT_INCOMPLETE, bounded_int, finite_float, prepare_out, remove_earlier_run

NAME = "simulate"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="run a scenario file (time simulation)",
                       description="Run SCENARIO (a shipped name such as 'swing-release' or "
                                   "'paper-turbulence', or a TOML path) and write DIR/timeseries.csv "
                                   "(SI units), DIR/run.json, DIR/hose.npz (the hose's joints at every output time) "
                                   "and DIR/displacement.png (DIR/engagement.png for an engagement).")
    s.add_argument("scenario", metavar="SCENARIO", help="scenario name or TOML file")
    s.add_argument("--duration", metavar="S", type=finite_float("--duration", 1e-9, 86400, "s"),
                   help="simulated time [s] (overrides the file)")
    s.add_argument("--seed", metavar="N", type=bounded_int("--seed", 0, 2**63 - 1),
                   help="turbulence seed [-] (overrides the file)")
    s.add_argument("--out", metavar="DIR", default="out/simulate", help="output folder (default out/simulate)")
    s.add_argument("--format", choices=("csv", "mat"), default="csv",
                   help="'mat': also write DIR/timeseries.mat (MATLAB, full precision, named signals with SI "
                        "units, the state [rad, rad/s]); default 'csv' only")
    s.add_argument("--view", action="store_true",
                   help="also write DIR/view.html: the run in 3D with its time series, one self-contained page "
                        "(hosedrogue view DIR writes the same)")
    s.set_defaults(func=run)


def run(args) -> int:
    """Simulate, write the files; exit 3 if the run stopped early (what it computed is kept).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..scenarios import load_scenario
    from ..scenarios.runner import run as run_scenario, write

    scenario = load_scenario(args.scenario).with_overrides(duration_s=args.duration, seed=args.seed)
    out = Path(args.out)
    prepare_out(out)
    result = run_scenario(scenario)
    created = not out.exists()
    try:
        remove_earlier_run(out)  # no file of an earlier run stays beside this one
        paths = write(result, out, formats=("csv", args.format))
        if args.view:
            from ..viewer import ViewRun, write_view

            paths.append(write_view([ViewRun.from_result(result)], out / "view.html"))
    except BaseException:  # leave no half-written output folder behind
        if created and out.exists():
            shutil.rmtree(out, ignore_errors=True)
        raise
    for p in paths:
        print(f"wrote {p}")
    print(result.headline())
    if not result.completed:
        print(f"hosedrogue: run incomplete: {result.message}", file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0
