"""``hosedrogue reference``: the scenario reference page (every table and key of a scenario file)."""

from __future__ import annotations

from .options import prepare_out_file

NAME = "reference"


def add_parser(sub) -> None:
    """Register the sub-command on ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The subparsers object of the ``hosedrogue`` parser.
    """
    s = sub.add_parser(NAME, help="print the scenario reference: every table and key of a scenario file",
                       description="Print the scenario reference page (Markdown): every table and key a scenario "
                                   "file may hold, with its unit, default, allowed values and meaning, generated "
                                   "from the code (the same page as docs/scenario-reference.md).")
    s.add_argument("--out", metavar="FILE", help="write the page to FILE instead of printing it")
    s.set_defaults(func=run)


def run(args) -> int:
    """Print or write the page; exit status 0 (2 when --out names a folder).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
    """
    from ..scenarios.reference import scenario_reference_page

    if args.out is None:
        print(scenario_reference_page(), end="")
        return 0
    out = prepare_out_file(args.out)  # a folder, or one that cannot be written: one line before the work
    text = scenario_reference_page()
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text, encoding="utf-8")
    print(f"wrote {out}")
    return 0
