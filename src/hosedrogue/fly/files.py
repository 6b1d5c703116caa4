"""A flight's folder: what ``hosedrogue simulate`` writes for a run (``timeseries.csv``,
``run.json``, ``hose.npz``, ``engagement.png``), the viewer's page of it (``view.html``, the
page's replay) and ``flight.toml``, the scenario that runs the flight again
(``hosedrogue simulate flight.toml``: the receiver replaying the recorded commands).

``run.json`` records the flight as a run of that scenario (its ``receiver`` the replaying
controller, the commands in its options) plus a ``"flight"`` object: how it was flown, how it
ended and how it kept to real time.
"""

from __future__ import annotations

import dataclasses
import datetime
import shutil
from pathlib import Path

from ..scenarios import Scenario, load_scenario
from ..scenarios.runner import run_meta, write
from .clock import Pace
from .record import REPLAY_ENTRY, CommandRecord, check_changes, scenario_toml

__all__ = ["write_flight", "read_commands", "replay_scenario", "FLIGHT_FILE"]

#: The scenario file of a flight's folder that runs it again.
FLIGHT_FILE = "flight.toml"


def flight_document(record: CommandRecord, pace: Pace, *, number: int, ended: str, sources: dict,
                    sample_time_s: float) -> dict:
    """The ``"flight"`` object of a flight's ``run.json``.

    Parameters
    ----------
    record : CommandRecord
        The commands flown.
    pace : Pace
        How the flight kept to real time.
    number : int
        The flight's number in its session [-].
    ended : str
        How it ended ("the run's end", "the pilot ended it", "the page was closed", "Ctrl-C", ...).
    sources : dict
        Input source -> samples it gave [-] ("keyboard", "gamepad", "none" before any input).
    sample_time_s : float
        The receiver's sample time [s].

    Returns
    -------
    dict
    """
    return {"flown": "live (hosedrogue fly)", "number": number,
            "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
            "ended": ended, "sample_time_s": sample_time_s, "samples": record.samples,
            "command_changes": len(record.changes), "inputs": sources, "real_time": pace.to_dict(),
            "commands": f"receiver.options.commands (from sample k on, (v_x, v_y, v_z) [m/s]); {FLIGHT_FILE} "
                        "runs them again"}


def write_flight(result, folder: str | Path, replay: Scenario, record: CommandRecord, pace: Pace, *, number: int,
                 ended: str, sources: dict):
    """Write a flight's folder (see the module docstring).

    Parameters
    ----------
    result : EngagementResult
        The flight's run (the stepper's result).
    folder : str or pathlib.Path
        The folder to write (created).
    replay : Scenario
        The flight's scenario with the receiver replaying its commands.
    record : CommandRecord
        The commands.
    pace : Pace
        How the flight kept to real time.
    number : int
        The flight's number [-].
    ended : str
        How it ended.
    sources : dict
        Input source -> samples [-].

    Returns
    -------
    EngagementResult
        ``result`` with the run's ``meta`` (what ``run.json`` holds).
    """
    from ..viewer import ViewRun, write_view

    folder = Path(folder)
    doc = flight_document(record, pace, number=number, ended=ended, sources=sources,
                          sample_time_s=replay.engagement.receiver.sample_time_s)
    result = dataclasses.replace(result, meta={**result.meta, **run_meta(replay), "flight": doc})
    created = not folder.exists()
    try:
        write(result, folder)
        write_view([ViewRun.from_result(result, label=f"{replay.name}")], folder / "view.html",
                   title=f"hosedrogue fly: {replay.name}")
        header = (f"Flight {number} of hosedrogue fly ({doc['date']}): the scenario {replay.source or replay.name!r} "
                  f"as flown, the receiver\nreplaying the pilot's commands. Run it again: "
                  f"hosedrogue simulate {folder / FLIGHT_FILE} --out DIR")
        (folder / FLIGHT_FILE).write_text(scenario_toml(replay.to_dict(), header=header))
    except BaseException:
        if created:
            shutil.rmtree(folder, ignore_errors=True)
        raise
    return result


def read_commands(document: dict) -> list:
    """The commands of a flight's ``run.json`` (its receiver's replay options), checked.

    Parameters
    ----------
    document : dict
        The parsed ``run.json``.

    Returns
    -------
    list of [k, v_x, v_y, v_z]
        From control sample k on, the command [m/s].
    """
    receiver = document.get("receiver") or {}
    if receiver.get("entry") != REPLAY_ENTRY:
        from ..errors import ParameterError

        raise ParameterError(f"run.json receiver.entry = {receiver.get('entry')!r}: not a flight of hosedrogue fly "
                             f"(expected {REPLAY_ENTRY!r})")
    return check_changes((receiver.get("options") or {}).get("commands"))


def replay_scenario(folder: str | Path) -> Scenario:
    """The scenario of a flight's folder that runs it again (``flight.toml``).

    Parameters
    ----------
    folder : str or pathlib.Path
        A folder written by ``hosedrogue fly``.

    Returns
    -------
    Scenario
    """
    return load_scenario(Path(folder) / FLIGHT_FILE)
