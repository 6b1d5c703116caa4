"""``hosedrogue sweep``: the balance position over a grid of flight conditions (paper Fig. 3)."""

from __future__ import annotations

import sys
from pathlib import Path

from .out_folder import output_folder
from .options import EXIT_INCOMPLETE, add_flight_options, finite_float, params_from_args, prepare_out

NAME = "sweep"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="balance position over a grid of altitudes and airspeeds (paper Fig. 3)",
                       description="Solve the balance position at every altitude [m] x airspeed [m/s] and write "
                                   "DIR/sweep.csv (drogue position [m], drag [N], tow force [N], V_D/L_H) and "
                                   "DIR/sweep.png (drogue drag and V_D/L_H against airspeed, one curve per altitude).")
    s.add_argument("--altitudes", metavar="M", type=finite_float("--altitudes", 0, 20000, "m"), nargs="+",
                   help="altitudes [m] (default 2000 4000 6000 8000 10000)")
    s.add_argument("--airspeeds", metavar="M_PER_S", type=finite_float("--airspeeds", 1e-9, 400, "m/s"), nargs="+",
                   help="airspeeds [m/s] (default 100 to 250 in steps of 10)")
    add_flight_options(s, condition=False)
    s.add_argument("--out", metavar="DIR", default="out/sweep", help="output folder (default out/sweep)")
    s.set_defaults(func=run)


def run(args) -> int:
    """Solve the grid, write CSV and figure; exit 3 if a grid point did not converge.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..analysis.sweep import DEFAULT_AIRSPEEDS_M_S, DEFAULT_ALTITUDES_M, steady_sweep
    from ..plotting.figures import plot_sweep, save_figure
    from ..studies.progress import progress_bar

    params = params_from_args(args)
    alts = args.altitudes or DEFAULT_ALTITUDES_M
    vels = args.airspeeds or DEFAULT_AIRSPEEDS_M_S
    out = Path(args.out)
    prepare_out(out)
    with progress_bar(total=len(alts) * len(vels), desc="equilibria") as bar:
        result = steady_sweep(params, alts, vels, progress=lambda: bar.update(1))
    with output_folder(out, "sweep", ("sweep.csv", "sweep.png")) as written:  # no file of an earlier sweep stays
        written.add(out / "sweep.csv", out / "sweep.png")
        result.to_csv(out / "sweep.csv")
        save_figure(plot_sweep(result), out / "sweep.png")
    failed = sum(not r["converged"] for r in result.rows)
    print(f"wrote {out / 'sweep.csv'}\nwrote {out / 'sweep.png'}")
    if failed:
        print(f"hosedrogue: {failed} grid points did not converge (NaN in sweep.csv)", file=sys.stderr)
        return EXIT_INCOMPLETE
    return 0
