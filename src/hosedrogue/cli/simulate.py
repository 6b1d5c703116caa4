"""``hosedrogue simulate``: run a scenario and write its time series."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

from .options import EXIT_INCOMPLETE, bounded_int, finite_float, prepare_out

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
                                   "(SI units), DIR/run.json and DIR/displacement.png.")
    s.add_argument("scenario", metavar="SCENARIO", help="scenario name or TOML file")
    s.add_argument("--duration", metavar="S", type=finite_float("--duration", 1e-9, 86400, "s"),
                   help="simulated time [s] (overrides the file)")
    s.add_argument("--seed", metavar="N", type=bounded_int("--seed", 0, 2**63 - 1),
                   help="turbulence seed [-] (overrides the file)")
    s.add_argument("--out", metavar="DIR", default="out/simulate", help="output folder (default out/simulate)")
    s.add_argument("--format", choices=("csv", "mat"), default="csv",
                   help="'mat': also write DIR/timeseries.mat (MATLAB, full precision, named signals with SI "
                        "units, the state [rad, rad/s]); default 'csv' only")
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
        paths = write(result, out, formats=("csv", args.format))
    except BaseException:  # leave no half-written output folder behind
        if created and out.exists():
            shutil.rmtree(out, ignore_errors=True)
        raise
    for p in paths:
        print(f"wrote {p}")
    print(headline(result))
    if not result.completed:
        print(f"hosedrogue: run incomplete: {result.message}", file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0


def headline(result) -> str:
    """The run's headline statistics in a few lines: over the statistics window, the peak and
    RMS radial drogue offset [m] and the peak control force [N]; for a drogue with control
    surfaces, their largest deflection [deg] and rate [deg/s] and the time at their limits [%];
    for an engagement, the outcome, the miss [m], the peak probe load [N] and the peak exit
    tension [N].

    Parameters
    ----------
    result : hosedrogue.results.RunResult
        The run.

    Returns
    -------
    str
    """
    st = result.statistics()
    start, end = result.statistics_window_s
    window = "the whole run" if end == float("inf") else f"{start:g}-{end:g} s"
    text = (f"drogue offset over {window}: peak {st['peak_radial_m']:.4g} m, RMS {st['rms_radial_m']:.4g} m; "
            f"peak control force {st['peak_u_n']:.4g} N")
    if "peak_deflection_deg" in st:
        text += (f"\ncontrol surfaces: largest deflection {st['peak_deflection_deg']:.3g} deg, rate "
                 f"{st['peak_deflection_rate_deg_s']:.3g} deg/s; at the deflection limit "
                 f"{100 * st['deflection_saturated_frac']:.3g} % and at the rate limit "
                 f"{100 * st['rate_saturated_frac']:.3g} % of the window")
    if hasattr(result, "summary"):
        s = result.summary()
        miss = "none" if s["miss_distance_m"] is None else f"{s['miss_distance_m']:.3f} m"
        text += (f"\nengagement: {s['result']}; miss {miss}; peak probe load {s['peak_probe_load_n']:.4g} N; "
                 f"peak exit tension {s['peak_exit_tension_n']:.4g} N")
    return text
