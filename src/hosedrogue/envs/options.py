"""What a docking environment runs and how it scores an episode: the scenario built from the
environment's options (:func:`docking_scenario`) and the reward's weights (:class:`DockingReward`)
(docs/gym.md).

The options change a scenario's tables before it is built, as a scenario file that ``extends`` it
would: the turbulence intensity, the bow wave, the reel law, the drogue controller, the model
preset, and the episode's time limit (the run's duration; a turbulence window that lasts to the
scenario's end is stretched to the new end). The episode's length is put on the run's step grid
(:func:`on_grid`: the nearest whole number of steps, recorded as the scenario's ``duration_s``).

Helpers the other environments' modules share: :func:`set_turbulence` (the turbulence option and
window), :func:`on_grid`; a number option is checked by
:func:`~hosedrogue.simulation.budget.positive_number`.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

from ..errors import ParameterError
from ..simulation.budget import on_step_grid, positive_number
from ..spec.config import preset_names
from ..spec.rewards import DockingReward, DockingRewardV1
from ..scenarios import Scenario, scenario_from_dict
from ..spec.standards import INTENSITY_FT_S
from .task_common import scenario_source

#: Turbulence options besides a number [m/s]: off, or a MIL-F-8785C intensity at the altitude.
TURBULENCE_CHOICES = ("none", *INTENSITY_FT_S)
#: Reel laws an episode can run (the take-up law "python" would need a command the agent does not give).
REEL_CHOICES = ("locked", "constant-tension", "response")
#: Built-in drogue controllers, compiled in the loop (continuous).
DROGUE_CHOICES = ("none", "pid", "lqr")
#: The model without a preset: the paper's (Table 1), overridden by the scenario's own tables.
PAPER_MODEL = "paper"
#: Longest episode [s] (a gust record is drawn for the whole episode at every reset).
MAX_TIME_LIMIT_S = 600.0


def reward_weights(reward: DockingReward | DockingRewardV1 | dict | None, kind: type = DockingReward):
    """A reward section of class ``kind`` from one, a ``{weight: value}`` table (the rest default) or None.

    Parameters
    ----------
    reward : DockingReward, DockingRewardV1, dict or None
        The weights.
    kind : type
        :class:`DockingReward` (Docking-v0) or :class:`DockingRewardV1` (Docking-v1).

    Returns
    -------
    DockingReward or DockingRewardV1
    """
    if reward is None:
        return kind()
    if isinstance(reward, kind):
        return reward
    if isinstance(reward, (DockingReward, DockingRewardV1)):
        raise ParameterError(f"reward = {type(reward).__name__}(...): this environment's weights are a "
                             f"{kind.__name__} or a dict")
    return kind.from_mapping(reward)


def docking_scenario(scenario: str | Path | Scenario = "approach-moderate", *, turbulence: str | float | None = None,
                     bow_wave: bool | None = None, reel: str | None = None, drogue_controller: str | None = None,
                     model: str | None = None, time_limit_s: float = 10.0, receiver_model: str | None = None) -> Scenario:
    """The scenario an episode runs: ``scenario`` with the options applied (None: the scenario's own).

    Parameters
    ----------
    scenario : str, Path or Scenario
        An engagement with a probe: a shipped name, a TOML file, or a Scenario built in Python.
    turbulence : str or float, optional
        "none", a MIL-F-8785C intensity ("light", "moderate", "severe") at the scenario's
        altitude, or an isotropic intensity [m/s].
    bow_wave : bool, optional
        The receiver's bow wave on or off (its shape: the scenario's ``[bow_wave]``, else the defaults).
    reel : str, optional
        The reel law: "locked", "constant-tension" or "response".
    drogue_controller : str, optional
        The drogue's built-in controller, compiled in the loop: "none", "pid" or "lqr".
    model : str, optional
        A model preset ("converged") or "paper" (none: the paper's model); with a scenario given
        by name or file only (a Scenario object carries its model's parameters resolved).
    time_limit_s : float
        The episode's length [s] (the run's duration), in (0, 600].
    receiver_model : str, optional
        The receiver as an aircraft: "f16" or the path of a receiver model file (``[receiver]
        model``, docs/receiver.md), flown through its built-in inner loop; "" the point receiver.

    Returns
    -------
    Scenario

    Raises
    ------
    ParameterError
        One line naming the option, the value and what is allowed; also a scenario the agent
        cannot fly (no probe, a pilot, the user's controllers).
    """
    limit = positive_number("time_limit_s", time_limit_s, MAX_TIME_LIMIT_S)
    if isinstance(scenario, Scenario) and model is not None:
        raise ParameterError(f"model = {model!r}: a Scenario object carries its model's parameters resolved; "
                             "give the scenario by name or file to change its preset")
    base, source, tables, name = scenario_source(scenario)
    _check_flyable(base)
    set_turbulence(tables, turbulence, base, limit)
    if bow_wave is not None:
        if not isinstance(bow_wave, bool):
            raise ParameterError(f"bow_wave = {bow_wave!r}: must be True, False or None (the scenario's)")
        tables.setdefault("bow_wave", {})["enabled"] = bow_wave
    if reel is not None:
        tables.setdefault("reel", {})["law"] = _choice("reel", reel, REEL_CHOICES)
    if drogue_controller is not None:
        kind = _choice("drogue_controller", drogue_controller, DROGUE_CHOICES)
        if kind != tables.get("controller", {}).get("type", "none"):
            tables["controller"] = {"type": kind}
    if model is not None:
        _choice("model", model, (PAPER_MODEL, *preset_names()))
        tables.pop("model", None)
        if model != PAPER_MODEL:
            tables["model"] = {"preset": model}
    if receiver_model is not None:
        if not isinstance(receiver_model, str):
            raise ParameterError(f"receiver_model = {receiver_model!r}: must be \"f16\", a receiver model file's path, "
                                 "\"\" (the point receiver) or None (the scenario's)")
        tables["receiver"] = {**tables.get("receiver", {}), "model": receiver_model}
    tables["scenario"] = {**tables.get("scenario", {}), "duration_s": limit}
    out = on_grid(scenario_from_dict(tables, name=name, source=source))
    _check_flyable(out)
    return out


def on_grid(scenario: Scenario) -> Scenario:
    """``scenario`` with its duration on its output grid: the nearest whole number of output
    intervals, ``numerics.output_every`` steps of ``numerics.step_s``
    (:func:`hosedrogue.simulation.budget.on_step_grid`), since every run and its saved series must
    reach its duration exactly; the scenario records the duration the episode runs.

    Parameters
    ----------
    scenario : Scenario
        An episode's scenario.

    Returns
    -------
    Scenario
    """
    num = scenario.params.numerics
    duration = on_step_grid(scenario.duration_s, num.step_s, num.output_every)
    return scenario if duration == scenario.duration_s else dataclasses.replace(scenario, duration_s=duration)


def set_turbulence(tables: dict, turbulence, base: Scenario, limit: float) -> None:
    """Apply the turbulence option to a scenario's tables; a window lasting to the scenario's end
    is made to last to the episode's.

    Parameters
    ----------
    tables : dict
        The scenario's tables (``{table: {key: value}}``), changed in place.
    turbulence : str, float or None
        "none", a MIL-F-8785C intensity, an isotropic intensity [m/s] in (0, 50], or None (the scenario's).
    base : Scenario
        The scenario before the options.
    limit : float
        The episode's length [s].

    Raises
    ------
    ParameterError
        One line naming the option, the value and what is allowed.
    """
    table = tables.setdefault("turbulence", {})
    if turbulence is not None:
        if isinstance(turbulence, str):
            level = _choice("turbulence", turbulence, TURBULENCE_CHOICES)
            table["enabled"] = level != "none"
            if level != "none":
                table.pop("sigma_m_s", None)
                table["intensity"] = level
        else:
            sigma = positive_number("turbulence", turbulence, 50.0, unit="m/s", text=", or one of "
                              + ", ".join(map(repr, TURBULENCE_CHOICES)))
            table.pop("intensity", None)
            table.update(enabled=True, sigma_m_s=sigma)
    t = base.params.turbulence
    if t.start_s + t.duration_s >= base.duration_s and math.isfinite(t.duration_s):
        table["duration_s"] = max(limit - t.start_s, 0.0)


def _check_flyable(sc: Scenario) -> None:
    """The agent flies the probe: an engagement with an enabled probe, no pilot, no user's controllers
    (the drogue's control surfaces, a ``[drogue_actuator]``, fly with the built-in controller)."""
    e = sc.engagement
    if e is None or e.probe is None or not e.probe.enabled:
        raise ParameterError(f"scenario = {sc.name!r}: the agent flies the receiver's probe; give an engagement "
                             "scenario with an enabled [probe] (e.g. 'approach-moderate')")
    if e.pilot is not None and e.pilot.enabled:
        raise ParameterError(f"scenario = {sc.name!r}: pilot.enabled = True: the agent flies the probe in the "
                             "pilot's place; give a scenario without [pilot]")
    if e.reel.law == "python":
        raise ParameterError(f"scenario = {sc.name!r}: reel.law = 'python': an episode commands only the receiver; "
                             f"choose one of {', '.join(map(repr, REEL_CHOICES))} (the reel option)")
    ctrl = sc.loop.controller
    if ctrl.type not in DROGUE_CHOICES or ctrl.sampled:
        raise ParameterError(f"scenario = {sc.name!r}: controller.type = {ctrl.type!r} (sample_time_s = "
                             f"{ctrl.sample_time_s:g}): an episode runs a built-in drogue controller compiled in "
                             f"the loop, continuous; choose one of {', '.join(map(repr, DROGUE_CHOICES))}")


def _choice(name: str, value: Any, choices: tuple) -> str:
    if value not in choices:
        raise ParameterError(f"{name} = {value!r}: must be one of {', '.join(map(repr, choices))}, or None "
                             "(the scenario's)")
    return value


def episode_receiver(scenario: Scenario):
    """The receiver's response the agent flies through: the scenario's ``[receiver]`` limits
    (its entry dropped: the agent gives the commands), else the defaults.

    Parameters
    ----------
    scenario : Scenario
        An engagement.

    Returns
    -------
    hosedrogue.spec.sections.Receiver
    """
    from ..spec.sections import Receiver

    rcv = scenario.engagement.receiver
    return Receiver() if rcv is None else dataclasses.replace(rcv, entry="", options={})
