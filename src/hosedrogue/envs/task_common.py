"""What the environments share: the scenario's tables from a name, a file or a Scenario (every
environment); and, for the station-keeping and whip-suppression environments, the one reset option
(the turbulence seed), the action's check and the observation of a measurement's numbers, scaled and
clipped."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from ..scenarios import Scenario, scenario_from_dict, scenario_tables


def scenario_source(scenario: str | Path | Scenario) -> tuple[Scenario, str, dict, str]:
    """A scenario as given, with its source, a copy of its tables and its name.

    Parameters
    ----------
    scenario : str, Path or Scenario
        A shipped name, a TOML file or a Scenario.

    Returns
    -------
    (Scenario, str, dict, str)
        The scenario, its source, its tables (each table a copy, to change) and its name.
    """
    if isinstance(scenario, Scenario):
        source, tables, name = scenario.source, scenario.to_dict(), scenario.name
    elif isinstance(scenario, (str, Path)):
        source, tables = scenario_tables(scenario)
        name = Path(source).stem
    else:
        raise ParameterError(f"scenario = {scenario!r}: must be a scenario name, a TOML path or a Scenario")
    base = scenario_from_dict(tables, name=name, source=source)
    return base, source, {k: (dict(v) if isinstance(v, dict) else v) for k, v in tables.items()}, name


def turbulence_seed_option(options: dict | None):
    """The one option of a reset: ``{"turbulence_seed": k}`` (None when not given).

    Parameters
    ----------
    options : dict or None
        ``reset``'s options.

    Returns
    -------
    int or None
    """
    options = dict(options or {})
    seed = options.pop("turbulence_seed", None)
    if options:
        raise ParameterError(f"options: unknown key(s) {', '.join(map(repr, options))}; allowed: 'turbulence_seed'")
    return seed


def checked_action(action, n: int) -> np.ndarray:
    """An action as n float64 numbers clipped to [-1, 1]; not n finite numbers: one line.

    Parameters
    ----------
    action : array_like (n,)
        The agent's action.
    n : int
        Its size.

    Returns
    -------
    numpy.ndarray (n,)
    """
    try:
        a = np.asarray(action, dtype=np.float64).reshape(n)
    except (TypeError, ValueError):
        a = None
    if a is None or not math.isfinite(float(a.sum())):
        raise ParameterError(f"action = {action!r}: must be {n} finite number{'s' if n > 1 else ''} in [-1, 1]")
    return np.clip(a, -1.0, 1.0)


def scaled(raw: np.ndarray, scale: np.ndarray, bound: np.ndarray, last: np.ndarray) -> np.ndarray:
    """``raw / scale`` clipped to the bound; ``last`` (the previous valid one) when not finite (a failed state).

    Parameters
    ----------
    raw : numpy.ndarray
        The observation's numbers in their units.
    scale, bound : numpy.ndarray
        Each component's scale and the bound of the scaled value.
    last : numpy.ndarray
        The last valid scaled observation.

    Returns
    -------
    numpy.ndarray
        float64; the environment keeps it as its last valid one and returns it as float32.
    """
    obs = raw / scale
    return np.clip(obs, -bound, bound) if math.isfinite(obs.sum()) else last
