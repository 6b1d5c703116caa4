"""``hosedrogue reproduce``: the paper's results as an HTML report."""

from __future__ import annotations

import os
from pathlib import Path

from .options import bounded_int, prepare_out
from .out_folder import output_folder

NAME = "reproduce"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="regenerate the paper's results as an HTML report",
                       description="Regenerate every result of the paper's Sections 2.3 and 3 from this model and "
                                   "write DIR/index.html with figures (PNG), data (CSV), report.json and an animation.")
    s.add_argument("--out", metavar="DIR", default="out/report", help="output folder (default out/report)")
    s.add_argument("--fast", action="store_true", help="coarser grids and shorter runs (< 1 min); marked as such")
    s.add_argument("--only", metavar="SECTION", nargs="+",
                   help="build only these sections (e.g. docking whip_loads; a wrong name lists them all) "
                        "and those they need; the page says it is partial; a wrong key gets the list")
    s.add_argument("--workers", metavar="K", type=bounded_int("--workers", 1, 256), default=os.cpu_count() or 1,
                   help="processes building independent sections side by side [-] (default: one per core, "
                        f"{os.cpu_count() or 1} here; 1: all in this process); the report is the same either way")
    s.set_defaults(func=run)


def run(args) -> int:
    """Build the report.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    from ..report import build_report
    from ..report.build import sections_for

    sections_for(args.only)  # a wrong key: one line, exit 2, before anything is written
    out = Path(args.out)
    prepare_out(out)
    with output_folder(out, "reproduce", ("index.html", "report.json"), scan=True):  # none of an earlier report's
        build_report(out, fast=args.fast, only=args.only, workers=args.workers)
    print(f"wrote {out / 'index.html'}")
    return 0
