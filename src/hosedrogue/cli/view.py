"""``hosedrogue view``: one or more run folders in an interactive 3D page (one HTML file)."""

from __future__ import annotations

from pathlib import Path

from ..errors import ParameterError
from ..jsonio import dumps
from .options import finite_float, prepare_out_file
from .out_folder import note_written

NAME = "view"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(
        NAME, help="interactive 3D view of run folders (one self-contained HTML file)",
        description=(
            "Write FILE: one HTML page, with nothing to download, that shows the hose, drogue, tow point and "
            "probe of each RUN_DIR (a folder of 'hosedrogue simulate --out DIR': timeseries.csv, run.json, "
            "hose.npz) in 3D, with play, pause, scrub, speed and cameras from behind, the side, above and free "
            "orbit, and their drogue offset, exit tension and probe load against time, the charts' cursor linked "
            "to the 3D time. Several runs are overlaid in one scene or side by side."))
    s.add_argument("runs", metavar="RUN_DIR", nargs="+", help="run folders (hosedrogue simulate --out DIR)")
    s.add_argument("--out", metavar="FILE", default="out/view.html", help="HTML file to write (default out/view.html)")
    s.add_argument("--layout", choices=("overlay", "side"), default="overlay",
                   help="several runs in one scene ('overlay', default) or side by side ('side'); the page switches")
    s.add_argument("--frame-rate", metavar="HZ", type=finite_float("--frame-rate", 1e-3, 1e4, "1/s"),
                   help="3D frames kept per simulated second [1/s] (default: every output time); fewer make a "
                        "smaller file, and the page interpolates between frames")
    s.add_argument("--start", metavar="S", type=finite_float("--start", -1e9, 1e9, "s"),
                   help="show the runs from this time on [s] (default: their start)")
    s.add_argument("--end", metavar="S", type=finite_float("--end", -1e9, 1e9, "s"),
                   help="show the runs up to this time [s] (default: their end)")
    s.add_argument("--label", metavar="NAME", action="append", default=[],
                   help="name of a run on the page, once per RUN_DIR in order (default: the scenario's name, "
                        "or the folder's when two runs share one)")
    s.add_argument("--title", metavar="TEXT", help="the page's title")
    s.add_argument("--json", action="store_true", help="print what was written as JSON (file, size [bytes], runs)")
    s.set_defaults(func=run)


def labels(folders: list[str], given: list[str], runs) -> list[str]:
    """The runs' names: those given, else the scenarios' (the folders' where two runs share a name).

    Parameters
    ----------
    folders : list of str
        The RUN_DIR arguments.
    given : list of str
        The --label values (none, or one per folder).
    runs : list of hosedrogue.viewer.ViewRun
        The runs read with their default names.

    Returns
    -------
    list of str
    """
    if given:
        if len(given) != len(folders):
            raise ParameterError(f"--label given {len(given)} times for {len(folders)} RUN_DIR: give it once per RUN_DIR")
        return list(given)
    names = [r.label for r in runs]
    return [Path(f).resolve().name if names.count(n) > 1 else n for f, n in zip(folders, names)]


def run(args) -> int:
    """Read the run folders (one line and exit 2 if one is not a run) and write the page.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (see :mod:`hosedrogue.cli`).
    """
    import dataclasses

    from ..viewer import read_run, write_view

    out = prepare_out_file(args.out)  # a folder, or one that cannot be written: one line before the work
    if args.start is not None and args.end is not None and args.end <= args.start:
        raise ParameterError(f"--end = {args.end:g}: must be after --start = {args.start:g} [s]")
    runs = [read_run(folder) for folder in args.runs]
    runs = [dataclasses.replace(r, label=name) for r, name in zip(runs, labels(args.runs, args.label, runs))]
    runs = [r.between(args.start, args.end) for r in runs]
    path = write_view(runs, out, layout=args.layout, frame_rate_hz=args.frame_rate, title=args.title)
    note_written(path)  # written into a run folder: the next run written there removes it
    size = path.stat().st_size
    if args.json:
        print(dumps({"file": str(path), "bytes": size, "layout": args.layout, "frame_rate_hz": args.frame_rate,
                          "runs": [{"label": r.label, "folder": r.source, "output_times": int(r.t_s.size),
                                    "t_start_s": float(r.t_s[0]), "t_end_s": float(r.t_s[-1]), "max_links": int(r.joint_count.max()) - 1}
                                   for r in runs]}, indent=2))
    else:
        print(f"wrote {path} ({size / 1e6:.2f} MB, {len(runs)} run{'s' if len(runs) > 1 else ''})")
    return 0
