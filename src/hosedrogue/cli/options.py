"""Options and helpers shared by the sub-commands: the one-line-error parser, validated number
types, the flight-condition options and the parameter set they select, exit codes."""

from __future__ import annotations

import argparse
import math
import os
import tempfile
from pathlib import Path

from ..errors import ParameterError
from ..spec.config import resolve_configs
from ..spec.manoeuvres import MAX_BANK_DEG, MAX_FLIGHT_PATH_DEG
from ..spec.params import Params

#: Exit status of a file operation the system refused (one line on stderr naming the file).
EXIT_SYSTEM = 1
#: Exit status of bad input (one line on stderr, nothing written).
EXIT_BAD_INPUT = 2
#: Exit status of a run that stopped early (partial output written, marked incomplete) or of an
#: equilibrium that could not be found.
EXIT_INCOMPLETE = 3
#: Largest number of runs (or seeds) per cell, campaign or case a study's command line accepts [-].
MAX_RUNS = 1_000_000


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors (no usage dump) and exit status 2."""

    def error(self, message):  # noqa: D401 - argparse API
        self.exit(EXIT_BAD_INPUT, f"hosedrogue: error: {message} (see '{self.prog} --help')\n")


def finite_float(name: str, lo: float, hi: float, unit: str):
    """An argparse type: a finite number in [lo, hi] [unit], else a one-line error naming ``name``.

    Parameters
    ----------
    name : str
        The option, e.g. ``--airspeed``.
    lo, hi : float
        Allowed range, inclusive [unit].
    unit : str
        Unit shown in the error message.

    Returns
    -------
    callable
        ``parse(text) -> float``.
    """

    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be a number in [{lo:g}, {hi:g}] {unit}")
        if not (math.isfinite(v) and lo <= v <= hi):
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be a number in [{lo:g}, {hi:g}] {unit}")
        return v

    return parse


def bounded_int(name: str, lo: int, hi: int):
    """An argparse type: an integer in [lo, hi], else a one-line error naming ``name``.

    Parameters
    ----------
    name : str
        The option, e.g. ``--links``.
    lo, hi : int
        Allowed range, inclusive.

    Returns
    -------
    callable
        ``parse(text) -> int``.
    """

    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be an integer in [{lo}, {hi}]")
        if not lo <= v <= hi:
            raise argparse.ArgumentTypeError(f"{name} = {text!r}: must be an integer in [{lo}, {hi}]")
        return v

    return parse


def add_flight_options(sp: argparse.ArgumentParser, links: bool = True, condition: bool = True) -> None:
    """Add (--altitude, --airspeed, --bank-deg, --climb-deg), (--links), --config, --no-wake.

    Parameters
    ----------
    sp : argparse.ArgumentParser
        The sub-command's parser.
    links : bool
        Also add --links.
    condition : bool
        Also add --altitude and --airspeed (a command that takes grids of them does not).
    """
    if condition:
        sp.add_argument("--altitude", metavar="M", type=finite_float("--altitude", 0, 20000, "m"),
                        help="flight altitude [m], 0-20000 (default: paper, 8000 m)")
        sp.add_argument("--airspeed", metavar="M_PER_S", type=finite_float("--airspeed", 1e-9, 400, "m/s"),
                        help="true airspeed [m/s], > 0 (default: paper, 150 m/s)")
        sp.add_argument("--bank-deg", metavar="DEG",
                        type=finite_float("--bank-deg", -MAX_BANK_DEG, MAX_BANK_DEG, "deg"),
                        help="a steady coordinated turn at this bank angle [deg] (> 0 right wing down, turning "
                             f"right at g tan(bank) / V), within +-{MAX_BANK_DEG:g} (default: wings level)")
        sp.add_argument("--climb-deg", metavar="DEG",
                        type=finite_float("--climb-deg", -MAX_FLIGHT_PATH_DEG, MAX_FLIGHT_PATH_DEG, "deg"),
                        help="a steady climb at this flight-path angle [deg] (< 0: a descent), within "
                             f"+-{MAX_FLIGHT_PATH_DEG:g} (default: level)")
    if links:
        sp.add_argument("--links", metavar="N", type=bounded_int("--links", 1, 1000),
                        help="number of rigid links of the hose [-], >= 1 (default 20)")
    sp.add_argument("--config", metavar="PRESET|FILE", action="append", default=[],
                    help="a shipped model preset (e.g. 'converged') or a TOML file of parameter overrides "
                         "([hose], [flight], ...; [model] preset = 'NAME' starts from a preset); may be given "
                         "several times, applied in order")
    sp.add_argument("--no-wake", action="store_true", help="switch the tanker wake off (free stream only)")


def flight_overrides(args) -> dict:
    """Parameter overrides from --altitude, --airspeed, --bank-deg, --climb-deg, --links, --no-wake
    (validated later).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    dict
        ``{section: {field: value}}`` for :meth:`hosedrogue.spec.params.Params.replace`.
    """
    over: dict = {}
    if getattr(args, "altitude", None) is not None:
        over.setdefault("flight", {})["altitude_m"] = args.altitude
    if getattr(args, "airspeed", None) is not None:
        over.setdefault("flight", {})["airspeed_m_s"] = args.airspeed
    if getattr(args, "links", None) is not None:
        over.setdefault("hose", {})["links"] = args.links
    if getattr(args, "no_wake", False):
        over.setdefault("wake", {})["enabled"] = False
    if getattr(args, "bank_deg", None) is not None:
        over.setdefault("tanker_motion", {})["bank_deg"] = args.bank_deg
    if getattr(args, "climb_deg", None) is not None:
        over.setdefault("tanker_motion", {})["flight_path_deg"] = args.climb_deg
    return over


def params_from_args(args) -> Params:
    """The parameter set selected by --config and the flight options (the paper's case by default).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    Params
    """
    configs = getattr(args, "config", None) or []
    base = resolve_configs([configs] if isinstance(configs, str) else configs)
    over = flight_overrides(args)
    return base.replace(**over) if over else base


def steady_flight_text(params: Params) -> str:
    """The tanker's initial steady flight for a headline: ``", in a 25 deg coordinated turn to the
    right, climbing at 3 deg"`` (empty in level flight).

    Parameters
    ----------
    params : Params
        Its ``tanker_motion.bank_deg`` and ``flight_path_deg`` [deg].

    Returns
    -------
    str
    """
    bank, path = params.tanker_motion.bank_deg, params.tanker_motion.flight_path_deg
    parts = []
    if bank:
        parts.append(f"in a {abs(bank):g} deg coordinated turn to the {'right' if bank > 0 else 'left'}")
    if path:
        parts.append(f"{'climbing' if path > 0 else 'descending'} at {abs(path):g} deg")
    return "".join(", " + p for p in parts)


def _writable_folder(folder: Path, shown: Path, name: str) -> None:
    """ParameterError unless ``folder`` exists or can be made, and a file can be made in it."""
    existing = folder
    while not existing.exists():  # the nearest folder that exists is where the first one is made
        if existing.parent == existing:
            break
        existing = existing.parent
    if not existing.is_dir():
        raise ParameterError(f"{name} = {str(shown)!r}: cannot be made ({str(existing)!r} is a file, not a folder)")
    try:
        with tempfile.TemporaryFile(dir=existing):  # what a write will meet: permissions, a read-only disk
            pass
    except OSError as exc:
        raise ParameterError(f"{name} = {str(shown)!r}: cannot be written ({exc.strerror or exc} in "
                             f"{str(existing)!r})") from None


def prepare_out(out: Path, name: str = "--out") -> None:
    """Check an output folder before anything is computed: it exists or can be made, and can be
    written; a file of that name is refused. Nothing is created.

    Parameters
    ----------
    out : Path
        The --out folder.
    name : str
        The option, for the message.

    Raises
    ------
    ParameterError
        One line naming the option, the path and why.
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ParameterError(f"{name} = {str(out)!r}: exists and is not a directory")
    _writable_folder(out, out, name)


def prepare_out_file(path: str | Path, name: str = "--out") -> Path:
    """Check an output file before anything is computed: not a folder, its folder exists or can be
    made and can be written, and the file itself, if it exists, can be replaced. Nothing is created.

    Parameters
    ----------
    path : str or Path
        The file to write.
    name : str
        The option, for the message.

    Returns
    -------
    Path

    Raises
    ------
    ParameterError
        One line naming the option, the path and why.
    """
    path = Path(path)
    if path.is_dir():
        raise ParameterError(f"{name} = {str(path)!r}: is a folder; give the file to write")
    _writable_folder(path.parent, path, name)
    if path.exists() and not os.access(path, os.W_OK):
        raise ParameterError(f"{name} = {str(path)!r}: cannot be written (the file is read-only)")
    return path


#: The files ``simulate`` (and ``view`` of a run folder) may write into a run folder: removed before
#: a new run is written into a reused folder written before its files were listed in it
#: (:func:`hosedrogue.cli.out_folder.clear_earlier_output`).
RUN_FOLDER_FILES = ("timeseries.csv", "run.json", "hose.npz", "displacement.png", "engagement.png",
                    "timeseries.mat", "view.html", "spectrum.png")


def parse_order(text: str) -> int | None:
    """--order: 'full' (None) or an integer >= 1.

    Parameters
    ----------
    text : str
        The --order value.

    Returns
    -------
    int or None
        The reduced order per channel, None for full order.
    """
    if text == "full":
        return None
    try:
        order = int(text)
    except ValueError:
        order = 0
    if order < 1:
        raise ParameterError(f"--order = {text!r}: must be 'full' or an integer >= 1")
    return order
