"""A flight's record: the probe-tip velocity commands of every control sample, as a step function
of the sample index, and their replay.

A live flight (:mod:`hosedrogue.fly.session`) holds each command for one receiver sample, like
any docking controller (docs/controllers.md). What it records is the list of *changes*,
``[[k, v_x, v_y, v_z], ...]``: from control sample k on (t = k T, T the receiver's
``sample_time_s``) the command is (v_x, v_y, v_z) [m/s] in the tanker frame, until the next
change. Integers and float64 values as they were held, so nothing is rounded.

:func:`replay` is a docking controller's factory (``entry = "hosedrogue.fly.record:replay"``,
the record in its ``commands`` option) that returns the same commands at the same samples, so a
scenario file with that ``[receiver]`` (the flight's ``flight.toml``) runs the flight again with
``hosedrogue simulate``: the same run, to the bit. :func:`scenario_toml` writes such a file
(floats written with their shortest exact decimal, so they read back to the same bits).
"""

from __future__ import annotations

import json
import math
from typing import Any, Mapping, Sequence

from ..errors import ParameterError

__all__ = ["REPLAY_ENTRY", "CommandRecord", "replay", "Replay", "scenario_toml"]

#: The entry point of the replaying controller, as a scenario file names it.
REPLAY_ENTRY = "hosedrogue.fly.record:replay"


class CommandRecord:
    """The commands of a flight, one per control sample, kept as their changes.

    Parameters
    ----------
    first : sequence of 3 float
        The command held from sample 0 [m/s].
    """

    def __init__(self, first: Sequence[float]):
        self.changes: list[list] = [[0, *map(float, first)]]
        self.samples = 0  #: control samples recorded [-]

    def add(self, k: int, command: Sequence[float]) -> None:
        """Record the command held at control sample ``k`` (the next sample index, in order).

        Parameters
        ----------
        k : int
            Control sample index [-] (t = k T).
        command : sequence of 3 float
            (v_x, v_y, v_z) [m/s].
        """
        if k != self.samples:
            raise ValueError(f"sample {k}: expected sample {self.samples} (commands are recorded in order)")
        vx, vy, vz = map(float, command)
        last = self.changes[-1]
        if k == 0:
            self.changes[0] = [0, vx, vy, vz]
        elif (last[1], last[2], last[3]) != (vx, vy, vz):
            self.changes.append([k, vx, vy, vz])
        self.samples = k + 1

    def at(self, k: int) -> tuple[float, float, float]:
        """The command held at sample ``k`` [m/s] (the last one after the record's end).

        Parameters
        ----------
        k : int
            Control sample index [-].

        Returns
        -------
        tuple of 3 float
        """
        return command_at(self.changes, k)


def command_at(changes: Sequence[Sequence[float]], k: int) -> tuple[float, float, float]:
    """The command of the step function ``changes`` at sample ``k`` (binary search).

    Parameters
    ----------
    changes : sequence of [k_i, v_x, v_y, v_z]
        Increasing k_i [-], the first 0; velocities [m/s].
    k : int
        Control sample index [-].

    Returns
    -------
    tuple of 3 float
        [m/s]
    """
    lo, hi = 0, len(changes) - 1
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if changes[mid][0] <= k:
            lo = mid
        else:
            hi = mid - 1
    c = changes[lo]
    return (c[1], c[2], c[3])


def check_changes(commands: Any) -> list[list]:
    """The ``commands`` option of :func:`replay`, checked: a non-empty list of ``[k, v_x, v_y, v_z]``
    with integer k increasing from 0 and finite velocities.

    Parameters
    ----------
    commands : Any
        The option's value.

    Returns
    -------
    list of [int, float, float, float]

    Raises
    ------
    ParameterError
        One line saying which entry is wrong and how.
    """
    if not isinstance(commands, (list, tuple)) or not commands:
        raise ParameterError(f"receiver.options.commands = {_short(commands)}: must be a non-empty list of "
                             "[sample, v_x_m_s, v_y_m_s, v_z_m_s]")
    out, previous = [], -1
    for i, row in enumerate(commands):
        ok = isinstance(row, (list, tuple)) and len(row) == 4
        if ok:
            k, *v = row
            ok = (isinstance(k, int) and not isinstance(k, bool) and k > previous
                  and all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in v))
        if not ok or (i == 0 and row[0] != 0):
            raise ParameterError(f"receiver.options.commands[{i}] = {_short(row)}: must be [sample, v_x, v_y, v_z] "
                                 "with the samples increasing from 0 (integers) and finite speeds [m/s]")
        previous = k
        out.append([k, float(v[0]), float(v[1]), float(v[2])])
    return out


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


class Replay:
    """A docking controller that returns recorded commands: at its k-th call (t = k T) the
    command of sample k of the record, the last one after the record's end.

    Parameters
    ----------
    commands : list of [k, v_x, v_y, v_z]
        The record (:class:`CommandRecord` ``changes``).
    """

    def __init__(self, commands):
        self.changes = check_changes(commands)
        self.k = 0

    def reset(self, m) -> None:
        """Start from sample 0.

        Parameters
        ----------
        m : hosedrogue.controllers.sampled.Measurement
            The first measurement (unused: the commands are recorded).
        """
        self.k = 0

    def __call__(self, t, m):
        """The recorded command of this sample [m/s].

        Parameters
        ----------
        t : float
            Time of the call [s].
        m : hosedrogue.controllers.sampled.Measurement
            The measurement (unused).

        Returns
        -------
        tuple of 3 float
        """
        v = command_at(self.changes, self.k)
        self.k += 1
        return v


def replay(commands) -> Replay:
    """Factory of :class:`Replay` (``[receiver] entry = "hosedrogue.fly.record:replay"``, the record
    in ``[receiver.options] commands``).

    Parameters
    ----------
    commands : list of [k, v_x, v_y, v_z]
        From control sample k on, the probe-tip velocity command (v_x, v_y, v_z) [m/s].

    Returns
    -------
    Replay
    """
    return Replay(commands)


# --- a scenario file ---------------------------------------------------------------------------
def _toml_key(key: str) -> str:
    return key if key.replace("_", "").replace("-", "").isalnum() and key.isascii() else json.dumps(key)


def _toml_value(value: Any) -> str:
    """A value in TOML: floats by their shortest exact decimal (``repr``), so they read back to the bit."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)  # a TOML basic string: JSON's escapes are TOML's
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    raise ParameterError(f"{value!r}: cannot be written to a scenario file (a {type(value).__name__})")


def _toml_table(name: str, table: Mapping[str, Any], lines: list[str]) -> None:
    plain = {k: v for k, v in table.items() if not isinstance(v, Mapping)}
    lines.append(f"[{name}]")
    for key, value in plain.items():
        if key == "commands" and isinstance(value, list) and len(value) > 1:  # one change a line
            lines.append(f"{key} = [\n" + "".join(f"  {_toml_value(v)},\n" for v in value) + "]")
        else:
            lines.append(f"{_toml_key(key)} = {_toml_value(value)}")
    lines.append("")
    for key, value in table.items():
        if isinstance(value, Mapping):
            _toml_table(f"{name}.{_toml_key(key)}", value, lines)


def scenario_toml(tables: Mapping[str, Mapping[str, Any]], header: str = "") -> str:
    """A scenario file of ``tables`` (:meth:`hosedrogue.scenarios.Scenario.to_dict`).

    Parameters
    ----------
    tables : mapping
        Table name -> {key: value} (values: bool, int, float, str, lists, nested tables).
    header : str
        Comment lines put first (each prefixed with ``#``).

    Returns
    -------
    str
        TOML text that :func:`hosedrogue.load_scenario` reads back to the same values.
    """
    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    if lines:
        lines.append("")
    for name, table in tables.items():
        _toml_table(_toml_key(name), table, lines)
    return "\n".join(lines).rstrip() + "\n"
