"""Randomized episodes of the docking environment (docs/gym.md, "Randomized episodes"): which
quantities an episode can draw, in what ranges, and how a draw becomes the episode's scenario.

A randomization is a table ``{name: (low, high)}`` (drawn uniformly) or ``{name: value}``
(fixed) over the names of :data:`RANDOMIZABLE`; ``True`` means :data:`DEFAULT_RANGES`. The
environment's generator draws one number per name in the order of :data:`RANDOMIZABLE`, after
the episode's turbulence seed, so the seed of ``reset`` decides every draw.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..scenarios import Scenario, scenario_from_dict

#: What an episode can draw: name -> (scenario table, key, lowest, highest allowed, unit, what).
RANDOMIZABLE = {
    "airspeed_m_s": ("flight", "airspeed_m_s", 100.0, 250.0, "m/s", "the tanker's true airspeed"),
    "altitude_m": ("flight", "altitude_m", 0.0, 12000.0, "m", "the flight altitude (air density, wake)"),
    "turbulence_sigma_m_s": ("turbulence", "sigma_m_s", 0.0, 8.0, "m/s",
                             "isotropic Dryden intensity (0: no turbulence)"),
    "hose_length_m": ("hose", "length_m", 10.0, 25.0, "m", "the trailed hose's length (the same number of links)"),
    "hose_mass_kg_m": ("hose", "mass_per_length_kg_m", 2.0, 8.0, "kg/m", "the hose's mass per length, fuel-filled"),
    "drogue_mass_kg": ("drogue", "mass_kg", 15.0, 50.0, "kg", "the drogue's mass"),
    "drogue_drag_coefficient": ("drogue", "drag_coefficient", 0.4, 1.2, "-", "the drogue's drag coefficient"),
    "start_standoff_m": ("probe", "standoff_m", 1.5, 5.0, "m", "the probe tip's start aft of the drogue"),
    "start_offset_y_m": ("probe", "offset_y_m", -1.5, 1.5, "m", "the probe tip's start to the right of the drogue"),
    "start_offset_z_m": ("probe", "offset_z_m", -1.5, 1.5, "m", "the probe tip's start below the drogue"),
    "bow_wave_radius_m": ("bow_wave", "forebody_radius_m", 0.0, 1.5, "m",
                          "the receiver's forebody radius in the bow-wave model (0: no bow wave)"),
    "sensor_noise_m": ("sensor", "noise_std_m", 0.0, 0.2, "m", "noise on the measured drogue position, per axis"),
    "sensor_delay_s": ("sensor", "delay_s", 0.0, 0.3, "s",
                       "the measurement's delay, rounded down to a whole number of control steps"),
}

#: The ranges of ``randomize=True``: around the default episode (150 m/s, 8000 m, moderate
#: turbulence, the paper's hose and drogue, 3 m aft on the drogue's line, the bow wave of a
#: 0.75 m forebody, an exact sensor), wide enough to matter and inside every allowed range.
DEFAULT_RANGES = {
    "airspeed_m_s": (130.0, 170.0), "altitude_m": (6000.0, 10000.0), "turbulence_sigma_m_s": (0.5, 3.0),
    "hose_length_m": (14.0, 18.0), "hose_mass_kg_m": (3.5, 5.5), "drogue_mass_kg": (25.0, 33.0),
    "drogue_drag_coefficient": (0.6, 0.8), "start_standoff_m": (2.5, 4.0), "start_offset_y_m": (-0.5, 0.5),
    "start_offset_z_m": (-0.5, 0.5), "bow_wave_radius_m": (0.5, 1.0), "sensor_noise_m": (0.0, 0.02),
    "sensor_delay_s": (0.0, 0.1),
}


def ranges(randomize: Any) -> dict:
    """The checked ranges of a randomization: name -> (low, high), a fixed value as (v, v).

    Parameters
    ----------
    randomize : None, bool or dict
        None or False: none; True: :data:`DEFAULT_RANGES`; a dict ``{name: (low, high) or value}``.

    Returns
    -------
    dict
        In the order of :data:`RANDOMIZABLE`.
    """
    if randomize is None or randomize is False:
        return {}
    if randomize is True:
        randomize = DEFAULT_RANGES
    if not isinstance(randomize, dict):
        raise ParameterError(f"randomize = {randomize!r}: must be True, False, None or a dict "
                             "{name: (low, high) or value}")
    unknown = [k for k in randomize if k not in RANDOMIZABLE]
    if unknown:
        raise ParameterError(f"randomize: unknown name(s) {', '.join(map(repr, unknown))}; allowed: "
                             f"{', '.join(RANDOMIZABLE)}")
    return {name: _range(name, randomize[name]) for name in RANDOMIZABLE if name in randomize}


def check_start(table: dict, probe, breakaway_distance_m: float) -> None:
    """Refuse a randomization whose farthest start point is beyond the breakaway distance (the
    episode would end at its first step).

    Parameters
    ----------
    table : dict
        From :func:`ranges`.
    probe : hosedrogue.spec.sections.Probe
        The scenario's probe (its start point where the table draws none).
    breakaway_distance_m : float
        The environment's breakaway distance [m].
    """
    def far(name, value):
        return max(abs(v) for v in table[name]) if name in table else abs(value)

    d = math.sqrt(far("start_standoff_m", probe.standoff_m) ** 2 + far("start_offset_y_m", probe.offset_y_m) ** 2
                  + far("start_offset_z_m", probe.offset_z_m) ** 2)
    if d >= breakaway_distance_m:
        raise ParameterError(f"randomize: the probe may start {d:.2f} m from the drogue (start_standoff_m, "
                             f"start_offset_y_m, start_offset_z_m): must stay below breakaway_distance_m = "
                             f"{breakaway_distance_m:g} m")


def _range(name: str, value: Any) -> tuple[float, float]:
    lo_ok, hi_ok, unit = RANDOMIZABLE[name][2], RANDOMIZABLE[name][3], RANDOMIZABLE[name][4]
    pair = value if isinstance(value, (tuple, list)) else (value, value)
    ok = len(pair) == 2 and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                                for v in pair)
    if not ok or not lo_ok <= pair[0] <= pair[1] <= hi_ok:
        raise ParameterError(f"randomize[{name!r}] = {value!r}: must be a number or a (low, high) pair with "
                             f"{lo_ok:g} <= low <= high <= {hi_ok:g} {unit}")
    return float(pair[0]), float(pair[1])


def draw(table: dict, rng: np.random.Generator) -> dict:
    """One episode's values: one uniform draw per name, in the table's order.

    Parameters
    ----------
    table : dict
        From :func:`ranges`.
    rng : numpy.random.Generator
        The environment's generator.

    Returns
    -------
    dict
        name -> value.
    """
    return {name: lo + (hi - lo) * float(rng.random()) for name, (lo, hi) in table.items()}


def episode_scenario(base: Scenario, values: dict, control_step_s: float) -> Scenario:
    """The scenario of an episode: ``base`` with the drawn values set in its tables.

    Parameters
    ----------
    base : Scenario
        The environment's scenario (its options applied).
    values : dict
        From :func:`draw`.
    control_step_s : float
        The control step [s] (the sensor's delay is rounded down to a whole number of them).

    Returns
    -------
    Scenario
    """
    tables = {k: (dict(v) if isinstance(v, dict) else v) for k, v in base.to_dict().items()}
    for name, value in values.items():
        table, key = RANDOMIZABLE[name][:2]
        if name == "sensor_delay_s":
            value = math.floor(value / control_step_s + 1e-9) * control_step_s
        if name == "turbulence_sigma_m_s":
            tables.setdefault(table, {}).pop("intensity", None)
            tables[table]["enabled"] = value > 0.0
            if value <= 0.0:
                continue
        if name == "bow_wave_radius_m":
            tables.setdefault(table, {})["enabled"] = value > 0.0
            if value <= 0.0:
                continue
        tables.setdefault(table, {})[key] = value
    return scenario_from_dict(tables, name=base.name, source=base.source)


def ranges_markdown() -> str:
    """The table of docs/gym.md "Randomized episodes" (a test checks the page shows it).

    Returns
    -------
    str
        Markdown rows: name, allowed, default range, what (the scenario key).
    """
    rows = ["| name | allowed | default range | what |", "|---|---|---|---|"]
    for name, (table, key, lo, hi, unit, what) in RANDOMIZABLE.items():
        u = "" if unit == "-" else f" {unit}"
        dlo, dhi = DEFAULT_RANGES[name]
        rows.append(f"| `{name}` | {lo:g} to {hi:g}{u} | {dlo:g} to {dhi:g}{u} | {what}; `{table}.{key}` |")
    return "\n".join(rows)
