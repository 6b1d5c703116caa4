"""A campaign's files: ``campaign.json`` (the settings) and ``runs.csv`` (one row per finished run).

A campaign owns its folder for its whole life (:class:`hosedrogue.studies.folder.FolderLock`: ``fcntl.flock`` on
``DIR/.lock``, which the kernel releases when the owner ends, however it ends, so a crashed
campaign never leaves the folder stuck); a second campaign on the folder is refused in one line.
``runs.csv`` is appended one flushed line per finished run (:class:`AppendLog`), so an interrupted
campaign loses at most the runs in flight and at most one partial last line, which reopening
drops; :func:`read_runs` reads the rows back, :func:`check_rows` refuses a row that is not this
campaign's (run index outside the campaign, another controller, a seed that is not the run's, a
run twice), :func:`todo` lists what a resumed campaign still has to run. campaign.json and the
summary are strict JSON (:mod:`hosedrogue.jsonio`): an infinite value of the scenario (``inf``: no
limit, rigid links) is written ``null``, which the scenario's sections read back as ``inf``.
Summary files are replaced atomically (:func:`write_atomic`). Floats are written as the shortest
string that reads back to the same double.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from pathlib import Path
from typing import Any, Iterable, Sequence

from .. import jsonio
from ..version import __version__
from ..errors import ParameterError
from ..results.statistics import DEFAULT_CAPTURE_RADII_M, statistic_units
from ..results.surfaces import SURFACE_STATISTICS
from .seeds import SEED_RULE, run_seed

#: Format tag of campaign.json (2: the typed scenario, with its hose "model").
FORMAT = "hosedrogue-montecarlo/2"

#: Settings that must agree when a campaign is resumed (see campaign.json).
COMPARED_SETTINGS = ("format", "scenario", "runs", "seed", "capture_radii_m", "compare_controller",
                     "controllers", "duration_s")

_KEY_COLUMNS = ("run", "controller", "seed", "completed", "t_end_s")
#: Columns of an engagement campaign's runs.csv: the capture test's result ("captured", "miss",
#: "failed latch", "no contact", "stopped"), radial miss [m] and closure speed [m/s] at the coupler
#: plane, and the run's peak probe load [N], peak exit tension [N] and peak slack [m]
ENGAGEMENT_COLUMNS = ("result", "miss_distance_m", "closure_speed_m_s", "peak_probe_load_n", "peak_exit_tension_n",
                      "peak_slack_m")
#: Columns of a campaign whose drogue steers itself with control surfaces
#: (:func:`hosedrogue.results.surfaces.surface_statistics`: peak deflection [deg] and rate [deg/s], the
#: fractions of the window saturated in deflection and in rate [-])
ACTUATOR_COLUMNS = tuple(name for name, _ in SURFACE_STATISTICS)
def is_engagement(settings: dict) -> bool:
    """Whether campaign settings (:func:`make_settings`) are those of an engagement scenario.

    Parameters
    ----------
    settings : dict
        Content of campaign.json.

    Returns
    -------
    bool
    """
    return settings.get("model") == "engagement"


def run_columns(capture_radii_m: Sequence[float], engagement: bool = False, actuated: bool = False) -> list[str]:
    """The columns of ``runs.csv``.

    Parameters
    ----------
    capture_radii_m : sequence of float
        Capture radii [m].
    engagement : bool
        An engagement campaign: also :data:`ENGAGEMENT_COLUMNS` (before the message).
    actuated : bool
        A drogue with control surfaces: also :data:`ACTUATOR_COLUMNS` (before the message).

    Returns
    -------
    list of str
        Run index, controller, seed, completed, stop time [s], the statistics of
        :func:`hosedrogue.results.statistics.statistic_units`, the engagement columns, the actuator
        columns, message.
    """
    extra = (ENGAGEMENT_COLUMNS if engagement else ()) + (ACTUATOR_COLUMNS if actuated else ())
    return [*_KEY_COLUMNS, *statistic_units(capture_radii_m), *extra, "message"]


def is_actuated(settings: dict) -> bool:
    """Whether campaign settings (:func:`make_settings`) are those of a scenario whose drogue
    steers itself with control surfaces (a ``[drogue_actuator]`` table).

    Parameters
    ----------
    settings : dict
        Content of campaign.json.

    Returns
    -------
    bool
    """
    return "drogue_actuator" in settings.get("scenario", {})


# --- campaign.json -------------------------------------------------------------------------------
def _json_normal(value: Any) -> Any:
    """The value as it reads back from strict JSON (tuples become lists, NaN and infinities None),
    for comparisons."""
    return json.loads(jsonio.dumps(value))


def _scenario_content(scenario) -> dict:
    """Everything that determines the runs (the file path and description do not)."""
    data = scenario.to_dict()
    data["scenario"].pop("description", None)
    return _json_normal(data)


def _first_difference(a: Any, b: Any, path: str) -> str | None:
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b)):
            found = _first_difference(a.get(key), b.get(key), f"{path}.{key}")
            if found:
                return found
        return None
    return None if a == b else path


def make_settings(scenario, runs: int, seed: int, radii: Sequence[float], compare_controller: bool,
                  controllers: Sequence[str], window: tuple[float, float]) -> dict:
    """The content of campaign.json, as it reads back from JSON.

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The scenario with the campaign's duration.
    runs : int
        Number of runs (seeds).
    seed : int
        Campaign seed.
    radii : sequence of float
        Capture radii [m].
    compare_controller : bool
        Whether every seed also runs without a controller.
    controllers : sequence of str
        Controllers run for every seed.
    window : (float, float)
        Statistics window [s]; the end may be inf (written as null).

    Returns
    -------
    dict
    """
    return _json_normal({
        "format": FORMAT,
        "scenario_name": scenario.name,
        "scenario_source": scenario.source,
        "model": scenario.model,
        "scenario": _scenario_content(scenario),
        "runs": runs,
        "seed": seed,
        "seed_rule": SEED_RULE,
        "capture_radii_m": list(radii),
        "compare_controller": compare_controller,
        "controllers": list(controllers),
        "duration_s": scenario.duration_s,
        "statistics_window_s": [window[0], None if math.isinf(window[1]) else window[1]],
        "hosedrogue_version": __version__,
    })


def check_same_settings(out: Path, old: dict, new: dict) -> None:
    """Raise ParameterError when ``old`` and ``new`` settings differ in :data:`COMPARED_SETTINGS`.

    Parameters
    ----------
    out : Path
        The campaign folder (for the message).
    old, new : dict
        Settings read from campaign.json and those of this call (:func:`make_settings`).
    """
    for key in COMPARED_SETTINGS:
        where = _first_difference(old.get(key), new.get(key), key)
        if where:
            raise ParameterError(
                f"out = {str(out)!r}: holds a campaign with different settings ({where} differs; "
                f"see {out / 'campaign.json'}); use another out folder or the same settings to resume"
            )


def read_settings(out: Path) -> dict | None:
    """The settings in ``out/campaign.json``, or None when there is none.

    Parameters
    ----------
    out : Path
        The campaign folder.

    Returns
    -------
    dict or None
    """
    path = out / "campaign.json"
    if not path.exists():
        if (out / "runs.csv").exists():
            raise ParameterError(f"out = {str(out)!r}: holds runs.csv but no campaign.json; use another out folder")
        return None
    try:
        # plain: a campaign.json of an earlier version wrote infinities as Infinity
        settings = jsonio.plain(json.loads(path.read_bytes().decode("utf-8")))
    except (OSError, ValueError) as exc:
        raise ParameterError(f"out = {str(out)!r}: campaign.json is not readable JSON ({exc})") from None
    if not isinstance(settings, dict) or not isinstance(settings.get("scenario"), dict):
        raise ParameterError(f"out = {str(out)!r}: campaign.json is not a campaign's settings; use another out folder")
    return settings


def write_atomic(path: Path, text: str) -> None:
    """Replace ``path`` by ``text`` atomically (write a temporary file, then rename).

    Parameters
    ----------
    path : Path
        File to write.
    text : str
        Its new content.
    """
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


# --- runs.csv ------------------------------------------------------------------------------------
def _format_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)  # shortest string that reads back to the same double
    return str(v).replace("\n", " ").replace("\r", " ")


def csv_line(values: Iterable[Any]) -> str:
    """One CSV line (with newline) of ``values``: booleans as true/false, floats as ``repr``.

    Parameters
    ----------
    values : iterable
        The fields.

    Returns
    -------
    str
    """
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([_format_value(v) for v in values])
    return buf.getvalue()


def _drop_partial_line(path: Path) -> int:
    """Cut a last line without newline (a write interrupted by a kill); return bytes dropped."""
    if not path.exists():
        return 0
    data = path.read_bytes()
    if not data or data.endswith(b"\n"):
        return 0
    keep = data.rfind(b"\n") + 1
    with path.open("r+b") as fh:
        fh.truncate(keep)
    return len(data) - keep


def _parse_value(column: str, text: str) -> Any:
    if column in ("run", "seed"):
        return int(text)
    if column == "completed":
        if text not in ("true", "false"):
            raise ValueError(f"completed = {text!r}")
        return text == "true"
    if column in ("controller", "message", "result"):
        return text
    return float(text)


def read_runs(path: str | Path, capture_radii_m: Sequence[float] = DEFAULT_CAPTURE_RADII_M,
              engagement: bool = False, actuated: bool = False) -> list[dict]:
    """Rows of a ``runs.csv`` as typed dicts, in file order; a partial last line is ignored.

    Parameters
    ----------
    path : str or Path
        The runs.csv file (missing: no rows).
    capture_radii_m : sequence of float
        The campaign's capture radii [m] (they name columns).
    engagement : bool
        An engagement campaign (:func:`run_columns`).
    actuated : bool
        A campaign of a drogue with control surfaces (:func:`run_columns`).

    Returns
    -------
    list of dict
        Column -> value (int, bool, str or float).
    """
    path = Path(path)
    columns = run_columns(capture_radii_m, engagement, actuated)
    raw = path.read_bytes() if path.exists() else b""
    raw = raw[: raw.rfind(b"\n") + 1]  # a partial last line (a write cut by a kill) is not a row
    try:
        data = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise ParameterError(f"{path}, line {line}: not a valid run row (not UTF-8 text); remove the line or use "
                             "another out folder") from None
    lines = list(csv.reader(io.StringIO(data)))
    if not lines:
        return []
    if lines[0] != columns:
        raise ParameterError(f"{path}: header {lines[0]!r} does not match the campaign's columns {columns!r}")
    rows = []
    for number, fields in enumerate(lines[1:], start=2):
        try:
            if len(fields) != len(columns):
                raise ValueError(f"{len(fields)} fields, expected {len(columns)}")
            rows.append({c: _parse_value(c, f) for c, f in zip(columns, fields)})
        except ValueError as exc:
            raise ParameterError(f"{path}, line {number}: not a valid run row ({exc})") from None
    return rows


def check_rows(path: str | Path, rows: list[dict], settings: dict) -> None:
    """Raise ParameterError naming the first row of ``rows`` that is not one of the campaign's runs.

    A row is the campaign's when its run index is in ``[0, runs)``, its controller one of the
    campaign's, its seed the run's (:func:`~hosedrogue.studies.seeds.run_seed` of the campaign seed
    and the index) and no earlier row has its (run, controller).

    Parameters
    ----------
    path : str or Path
        The runs.csv file the rows were read from, in file order (:func:`read_runs`; for the message).
    rows : list of dict
        Its rows.
    settings : dict
        The campaign's settings (:func:`make_settings`): ``runs``, ``seed``, ``controllers``.
    """
    runs, seed, controllers = settings["runs"], settings["seed"], settings["controllers"]
    seen: set = set()
    for number, row in enumerate(rows, start=2):  # line 1 is the header; one line per row
        run, controller = row["run"], row["controller"]
        if not 0 <= run < runs:
            why = f"run = {run} is not a run of this campaign (0 to {runs - 1})"
        elif controller not in controllers:
            why = f"controller = {controller!r} is not one of this campaign's {controllers!r}"
        elif (run, controller) in seen:
            why = f"run {run} ({controller}) has a row already"
        elif row["seed"] != run_seed(seed, run):
            why = f"seed = {row['seed']} is not run {run}'s seed {run_seed(seed, run)} (campaign seed {seed})"
        else:
            seen.add((run, controller))
            continue
        raise ParameterError(f"{path}, line {number}: not a row of this campaign ({why}); remove the line or use "
                             "another out folder")


class AppendLog:
    """A CSV file appended one flushed line at a time, header once (its writer holds the folder's
    :class:`~hosedrogue.studies.folder.FolderLock`).

    Opening drops a partial last line (a write interrupted by a kill).

    Parameters
    ----------
    path : Path
        The CSV file (created if missing).
    columns : sequence of str
        Its columns; :meth:`append` writes a row's values in this order.
    """

    def __init__(self, path: Path, columns: Sequence[str]):
        self.columns = list(columns)
        self.fh = path.open("a", newline="")
        _drop_partial_line(path)  # O_APPEND: the next write goes to the new end
        if path.stat().st_size == 0:
            self._write(self.columns)

    def _write(self, values: Iterable[Any]) -> None:
        self.fh.write(csv_line(values))  # one write of a whole line: a kill leaves a partial line at most
        self.fh.flush()

    def append(self, row: dict) -> None:
        """Write one row (column -> value) and flush."""
        self._write(row[c] for c in self.columns)

    def close(self) -> None:
        """Close the file (and release the lock)."""
        self.fh.close()


def todo(done_rows: list[dict], runs: int, controllers: Sequence[str]) -> list[tuple[int, str]]:
    """The (run index, controller) pairs without a row yet, in run order.

    Parameters
    ----------
    done_rows : list of dict
        Rows already in runs.csv.
    runs : int
        Number of runs of the campaign.
    controllers : sequence of str
        Controllers run for every seed.

    Returns
    -------
    list of (int, str)
    """
    done = {(r["run"], r["controller"]) for r in done_rows}
    return [(i, c) for i in range(runs) for c in controllers if (i, c) not in done]


