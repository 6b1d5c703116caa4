"""Command line: parse, call, print. One module per sub-command (each with ``NAME``,
``add_parser(sub)`` and ``run(args) -> int``), the shared options in :mod:`.options`.

Exit status: 0 success, 2 bad input (one line on stderr, nothing written), 3 a run that stopped
early (its partial output is written and marked ``completed: false``) or an equilibrium that could
not be found, 130 interrupted, 1 anything unexpected.
"""

from __future__ import annotations

import argparse
import sys

from ..errors import EquilibriumError, IncompleteError, ParameterError
from . import (bow_wave, design, export_fmu, fly, gym, gym_task, linearize, margins, montecarlo, reference, reproduce,
               simulate, steady, study, sweep, trim_receiver, view)
from .options import EXIT_BAD_INPUT, EXIT_INCOMPLETE, EXIT_SYSTEM, Parser

#: The sub-commands, in the order ``--help`` lists them. A new command is a module here plus a line.
COMMANDS = (steady, simulate, view, fly, sweep, linearize, margins, design, reproduce, montecarlo, study, bow_wave, gym,
            gym_task, export_fmu, trim_receiver, reference)

__all__ = ["main", "build_parser", "COMMANDS", "EXIT_BAD_INPUT", "EXIT_INCOMPLETE"]


def build_parser() -> argparse.ArgumentParser:
    """The ``hosedrogue`` argument parser with every sub-command of :data:`COMMANDS`."""
    from ..version import __version__

    p = Parser(prog="hosedrogue", description=(
        "Probe-and-drogue aerial refuelling hose: Kane-equation rigid-link model (Wu et al., 2018). "
        "Frame S_p: origin at the tow point, x forward, y right, z down; SI units."))
    p.add_argument("--version", action="version", version=f"hosedrogue {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=Parser)
    for command in COMMANDS:
        command.add_parser(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); return the exit status.

    Parameters
    ----------
    argv : list of str, optional
        Arguments after the program name.

    Returns
    -------
    int
        Exit status (0, 1 a file the system refused, 2 bad input, 3 incomplete, 130 interrupted).
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except ParameterError as exc:
        print(f"hosedrogue: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except (EquilibriumError, IncompleteError) as exc:
        print(f"hosedrogue: {exc}", file=sys.stderr)
        return EXIT_INCOMPLETE
    except KeyboardInterrupt:
        print("hosedrogue: interrupted", file=sys.stderr)
        return 130
    except OSError as exc:  # the system refused a file (a folder where a file goes, a full disk, a port in use)
        print(f"hosedrogue: error: {exc}", file=sys.stderr)
        return EXIT_SYSTEM


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
