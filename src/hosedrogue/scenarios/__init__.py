"""Scenarios: one typed description of a run, from a TOML file or built in Python.

A scenario file is TOML: a ``[scenario]`` table (``duration_s``, ``initial``, offsets, and
``extends`` to start from another scenario), the drogue's control loop (``[controller]``,
``[actuator]``, ``[sensor]``, and ``[drogue_actuator]`` for a drogue steered by control
surfaces), the engagement (``[reel]``, ``[probe]``, ``[bow_wave]``, ``[pilot]``, ``[receiver]``) and
any parameter section of :mod:`hosedrogue.spec.params` (``[flight]``, ``[turbulence]``, ...) overriding the
paper's case. ``[model] preset = "converged"`` starts from a
shipped model preset (:mod:`hosedrogue.spec.config`); the file's parameter sections then override it.
Every section, key, unit, default and range is listed in the documentation's scenario reference.

A scenario with a ``[reel]`` or ``[probe]`` section runs the hose of varying length (the
engagement, :mod:`hosedrogue.engagement`); without, the fixed-length hose. A section the chosen
model cannot honour is a one-line error naming it.

``extends = "NAME"`` reads the named scenario (a shipped name, or a TOML path relative to the
extending file) and overrides it table by table: keys given replace the parent's, tables are
merged key by key, a ``[controller]`` of another ``type`` replaces the parent's whole table.

Scenarios shipped with the package are found by name (``paper-turbulence``) or file name
(``scenarios/paper-turbulence.toml``); any other path is read from disk.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, Mapping

from ..simulation.budget import check_duration, check_integrator
from ..spec.config import load_preset, preset_names, read_toml
from ..spec.params import SECTIONS, PAPER, ParameterError, Params, params_from_dict
from ..spec.sections import (CONTROLLER_TYPES, ENGAGEMENT_SECTIONS, LOOP_SECTIONS, Actuator, Controller,
                        DrogueActuator, Engagement, Loop, Sensor)

#: Keys of the ``[scenario]`` table.
SCENARIO_KEYS = ("name", "description", "duration_s", "extends", "initial", "initial_pitch_offset_deg",
                 "initial_yaw_offset_deg")
#: Every table a scenario file may hold.
TABLES = ("scenario", "model", "controller", *LOOP_SECTIONS, *ENGAGEMENT_SECTIONS, *SECTIONS)
#: Longest simulated time of a scenario [s]: one day.
MAX_DURATION_S = 86400.0
#: Largest initial offset of every link for ``initial = "displaced"`` [deg].
MAX_OFFSET_DEG = 60.0
#: Longest chain of ``extends`` (a guard against a scenario that extends itself in a loop).
MAX_EXTENDS = 16

__all__ = ["CONTROLLER_TYPES", "Scenario", "load_scenario", "scenario_from_dict", "scenario_tables",
           "shipped_scenarios", "resolve", "merge_tables"]


@dataclass(frozen=True)
class Scenario:
    """A runnable case: the model's parameters, the run settings, the drogue's control loop and,
    for the hose of varying length, the engagement. Validated at construction (a bad value is a
    one-line :class:`~hosedrogue.errors.ParameterError`); :func:`hosedrogue.run` runs it.
    """

    name: str  #: scenario name (``[scenario] name``, or the file's stem)
    params: Params  #: the model, environment and numerics parameters
    duration_s: float  #: simulated time [s], in (0, 86400]
    description: str = ""  #: one line for people
    #: "equilibrium": start at rest at the balance position; "displaced": add the offsets below
    #: to every link's balance angles and release from rest.
    initial: str = "equilibrium"
    initial_pitch_offset_deg: float = 0.0  #: pitch added to every link for ``displaced`` [deg]
    initial_yaw_offset_deg: float = 0.0  #: yaw added to every link for ``displaced`` [deg]
    loop: Loop = field(default_factory=Loop)  #: the drogue's controller, actuator and sensor
    #: the reel, probe, bow wave and pilot; None: the fixed-length hose
    engagement: Engagement | None = None
    source: str = ""  #: where it was read from (``scenarios/NAME.toml`` or a path; "" if built in Python)

    def __post_init__(self) -> None:
        object.__setattr__(self, "duration_s", check_duration(self.duration_s, "scenario.duration_s", MAX_DURATION_S))
        if self.initial not in ("equilibrium", "displaced"):
            raise ParameterError(f"scenario.initial = {self.initial!r}: must be one of 'equilibrium', 'displaced'")
        for key in ("initial_pitch_offset_deg", "initial_yaw_offset_deg"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (
                    math.isfinite(v) and abs(v) <= MAX_OFFSET_DEG):
                raise ParameterError(f"scenario.{key} = {v!r}: must be a finite number in "
                                     f"[-{MAX_OFFSET_DEG:g}, {MAX_OFFSET_DEG:g}] deg")
            object.__setattr__(self, key, float(v))
        if not isinstance(self.params, Params):
            raise ParameterError(f"params = {self.params!r}: must be a hosedrogue.spec.params.Params")
        if not isinstance(self.loop, Loop):
            raise ParameterError(f"loop = {self.loop!r}: must be a hosedrogue.spec.sections.Loop")
        if self.engagement is not None and not isinstance(self.engagement, Engagement):
            raise ParameterError(f"engagement = {self.engagement!r}: must be a hosedrogue.spec.sections.Engagement or None")
        num = self.params.numerics
        if num.integrator != "adaptive" or self.engagement is not None:
            num.steps(self.duration_s, "scenario.duration_s")  # at least one step
        if self.loop.drogue_actuator is not None:
            self.loop.drogue_actuator.check_hose(self.params.hose.axial_stiffness_n)
            self.loop.drogue_actuator.check_loop(self.loop.actuator == Actuator(), self.loop.controller)
            if num.integrator == "rk4" or self.engagement is not None:
                self.loop.drogue_actuator.check_step(num.step_s)
        check_integrator(self.params, "fixed-length" if self.engagement is None else "engagement")

    # --- the control loop, by its parts --------------------------------------------------------------
    @property
    def controller(self) -> str:
        """The drogue controller's type: "none", "pid" or "lqr"."""
        return self.loop.controller.type

    @property
    def controller_options(self) -> dict:
        """The controller's design options (see :class:`hosedrogue.spec.sections.Controller`)."""
        return dict(self.loop.controller.options)

    @property
    def actuator(self) -> Actuator:
        """Force and rate limits of the control force."""
        return self.loop.actuator

    @property
    def sensor(self) -> Sensor:
        """Noise on the measured drogue offset."""
        return self.loop.sensor

    @property
    def drogue_actuator(self) -> DrogueActuator | None:
        """The drogue's control surfaces (None: the controller's force acts as such)."""
        return self.loop.drogue_actuator

    @property
    def model(self) -> str:
        """The hose model this scenario runs: ``"engagement"`` (varying length) or ``"fixed-length"``."""
        return "fixed-length" if self.engagement is None else "engagement"

    def require_model(self, model: str, field: str, purpose: str) -> "Scenario":
        """This scenario if it runs ``model`` (:attr:`model`); else a one-line error.

        Parameters
        ----------
        model : str
            ``"engagement"`` or ``"fixed-length"``.
        field : str
            The input that named the scenario (the error's first word).
        purpose : str
            What needs the other model, e.g. ``"the whip-load study runs engagements ..."``.

        Returns
        -------
        Scenario

        Raises
        ------
        ParameterError
            ``field: 'NAME' is a fixed-length scenario; PURPOSE`` (or ``is an engagement``).
        """
        if self.model != model:
            have = "a fixed-length scenario" if self.engagement is None else "an engagement"
            raise ParameterError(f"{field}: {self.name!r} is {have}; {purpose}")
        return self

    # --- copies ------------------------------------------------------------------------------------
    def with_overrides(self, duration_s: float | None = None, seed: int | None = None) -> "Scenario":
        """A copy with another duration [s] and/or turbulence seed (validated).

        Parameters
        ----------
        duration_s : float, optional
            Simulated time [s].
        seed : int, optional
            Turbulence seed, >= 0.

        Returns
        -------
        Scenario
        """
        s = self
        if duration_s is not None:
            s = dataclasses.replace(s, duration_s=check_duration(duration_s, "duration_s", MAX_DURATION_S))
        if seed is not None:
            if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
                raise ParameterError(f"seed = {seed!r}: must be an integer >= 0")
            s = dataclasses.replace(s, params=s.params.replace(turbulence={"seed": seed}))
        return s

    def with_controller(self, controller: str | Controller) -> "Scenario":
        """A copy with another drogue controller (a type keeps this scenario's options if it is the same type).

        Parameters
        ----------
        controller : str or Controller
            "none", "pid", "lqr", or a :class:`~hosedrogue.spec.sections.Controller`.

        Returns
        -------
        Scenario
        """
        if not isinstance(controller, Controller):
            if controller == self.loop.controller.type:
                return self  # the same type: this scenario's controller, options, sample time and entry
            controller = Controller(controller)
        return dataclasses.replace(self, loop=dataclasses.replace(self.loop, controller=controller))

    def to_dict(self) -> dict[str, Any]:
        """The scenario as the tables of a self-contained scenario file (no ``extends``, no preset).

        ``scenario_from_dict(s.to_dict())`` gives the same scenario (the source aside).

        Returns
        -------
        dict
            ``{"scenario": {...}, "controller": ..., "actuator": ..., "sensor": ..., [reel, probe, ...],
            [tanker, hose, ...]}``, tuples as lists (TOML/JSON-ready).
        """
        head = {"name": self.name, "description": self.description, "duration_s": self.duration_s,
                "initial": self.initial, "initial_pitch_offset_deg": self.initial_pitch_offset_deg,
                "initial_yaw_offset_deg": self.initial_yaw_offset_deg}
        out: dict[str, Any] = {"scenario": head, **self.loop.to_dict()}
        if self.engagement is not None:
            out.update(self.engagement.to_dict())
        out.update(self.params.to_dict())
        return out


def shipped_scenarios() -> list[str]:
    """Names of the scenarios shipped with the package."""
    root = resources.files(__package__)
    return sorted(p.name[:-5] for p in root.iterdir() if p.name.endswith(".toml"))


def resolve(name_or_path: str | Path, relative_to: Path | None = None) -> tuple[str, dict]:
    """Find a scenario by shipped name, ``scenarios/NAME.toml`` or path; return (source, data).

    Parameters
    ----------
    name_or_path : str or Path
        A shipped scenario name, ``scenarios/NAME.toml``, or a TOML file's path.
    relative_to : Path, optional
        Folder a relative path is looked up in first (the extending file's, for ``extends``).

    Returns
    -------
    source : str
        Where it was found.
    data : dict
        The parsed TOML.
    """
    path = Path(name_or_path)
    if relative_to is not None and not path.is_absolute() and (relative_to / path).is_file():
        path = relative_to / path
    if path.is_file():
        return str(path), read_toml(path)
    stem = path.name[:-5] if path.name.endswith(".toml") else path.name
    candidate = resources.files(__package__) / f"{stem}.toml"
    if candidate.is_file() and (path.parent in (Path("."), Path("scenarios"))):
        with resources.as_file(candidate) as p:
            return f"scenarios/{stem}.toml", read_toml(p)
    if path.exists():
        return str(path), read_toml(path)  # a folder or unreadable: read_toml says why in one line
    raise ParameterError(
        f"scenario {str(name_or_path)!r}: no such file or shipped scenario; shipped: {', '.join(shipped_scenarios())}"
    )


def merge_tables(parent: Mapping[str, Any], child: Mapping[str, Any]) -> dict[str, Any]:
    """``child`` over ``parent``: tables merged key by key, any other value replaced.

    A child's ``[controller]`` whose ``type`` differs from the parent's replaces the parent's
    table (the options of one controller type mean nothing to another).

    Parameters
    ----------
    parent, child : Mapping
        Parsed scenario tables.

    Returns
    -------
    dict
        A new mapping (the inputs are not modified).
    """
    out = {k: (dict(v) if isinstance(v, Mapping) else v) for k, v in parent.items()}
    for key, value in child.items():
        old = out.get(key)
        replace_controller = (key == "controller" and isinstance(value, Mapping) and isinstance(old, Mapping)
                              and value.get("type", old.get("type", "none")) != old.get("type", "none"))
        if isinstance(value, Mapping) and isinstance(old, Mapping) and not replace_controller:
            out[key] = merge_tables(old, value)
        else:
            out[key] = dict(value) if isinstance(value, Mapping) else value
    return out


def _anchor_entries(source: str, data: dict) -> dict:
    """``data`` with each table's ``entry = "FILE.py:factory"`` made absolute: a relative path is
    relative to the folder of the scenario file ``source`` that names it (a shipped scenario's
    entries are left as they are)."""
    from ..spec.fields import FILE_ENTRY_PATTERN

    if source.startswith("scenarios/"):
        return data
    out = dict(data)
    for key, table in data.items():
        entry = table.get("entry") if isinstance(table, Mapping) else None
        m = FILE_ENTRY_PATTERN.match(entry) if isinstance(entry, str) else None
        if m and not Path(m["path"]).is_absolute():
            path = (Path(source).parent / m["path"]).resolve()
            out[key] = {**table, "entry": f"{path}{entry[m.end('path'):]}"}
    return out


def _read_with_parents(name_or_path: str | Path) -> tuple[str, dict]:
    """The scenario's tables with its ``extends`` chain merged in (the chain's own keys dropped),
    each file's relative controller files anchored at its own folder (:func:`_anchor_entries`)."""
    source, data = resolve(name_or_path)
    data = _anchor_entries(source, data)
    chain = [source]
    while True:
        head = data.get("scenario", {})
        if not isinstance(head, Mapping) or "extends" not in head:
            break
        parent_name = head["extends"]
        if not isinstance(parent_name, str) or not parent_name:
            raise ParameterError(f"scenario.extends = {parent_name!r}: must be a scenario name or TOML path")
        if len(chain) > MAX_EXTENDS:
            raise ParameterError(f"scenario.extends = {parent_name!r}: more than {MAX_EXTENDS} levels "
                                 f"({' -> '.join(chain)})")
        here = Path(chain[-1]).parent if not chain[-1].startswith("scenarios/") else None
        parent_source, parent = resolve(parent_name, relative_to=here)
        parent = _anchor_entries(parent_source, parent)
        if parent_source in chain:
            raise ParameterError(f"scenario.extends = {parent_name!r}: a loop ({' -> '.join(chain + [parent_source])})")
        chain.append(parent_source)
        child_head = {k: v for k, v in head.items() if k != "extends"}
        # name is the extending file's own (its stem unless given); the rest is inherited
        parent_head = {k: v for k, v in dict(parent.get("scenario", {})).items() if k != "name"}
        data = merge_tables(parent, {k: v for k, v in data.items() if k != "scenario"})
        data["scenario"] = {**parent_head, **child_head}
    return source, data


def scenario_tables(name_or_path: str | Path) -> tuple[str, dict]:
    """A scenario file's tables as :func:`load_scenario` reads them, its ``extends`` chain merged
    in, not yet validated: to change some before :func:`scenario_from_dict` builds the scenario
    (a ``[model] preset`` stays a preset here, unlike :meth:`Scenario.to_dict`'s resolved tables).

    Parameters
    ----------
    name_or_path : str or Path
        A shipped scenario name or a TOML file (:func:`resolve`).

    Returns
    -------
    source : str
        Where it was found.
    tables : dict
        ``{table: {key: value}}`` (a new mapping: changing it changes nothing else).

    Raises
    ------
    ParameterError
        No such scenario, an ``extends`` loop or an unreadable file.
    """
    return _read_with_parents(name_or_path)  # parsed afresh on every call


def _table(data: Mapping[str, Any], name: str) -> dict:
    """The table ``data[name]`` (empty if absent) as a new dict; anything else is a ParameterError."""
    value = data.get(name, {})
    if not isinstance(value, Mapping):
        raise ParameterError(f"{name} = {value!r}: must be a table of fields ([{name}])")
    return dict(value)


def load_scenario(name_or_path: str | Path, base: Params = PAPER) -> Scenario:
    """Load and validate a scenario file (see the module docstring).

    Parameters
    ----------
    name_or_path : str or Path
        A shipped scenario name or a TOML file (:func:`resolve`).
    base : Params
        Parameters the file's sections override (the paper's case by default).

    Returns
    -------
    Scenario

    Raises
    ------
    ParameterError
        One line naming the field, the value and what is allowed.
    """
    source, data = _read_with_parents(name_or_path)
    default_name = Path(source).stem
    return scenario_from_dict(data, name=default_name, source=source, base=base)


def scenario_from_dict(data: Mapping[str, Any], *, name: str = "scenario", source: str = "",
                       base: Params = PAPER) -> Scenario:
    """A scenario from its tables, as a TOML scenario file holds them (``extends`` aside).

    Parameters
    ----------
    data : Mapping
        ``{table: {key: value}}`` (:data:`TABLES`); ``[scenario] duration_s`` is required.
    name : str
        The name if ``[scenario] name`` is not given.
    source : str
        Where the tables come from (recorded in the result's metadata).
    base : Params
        Parameters the tables override (the paper's case by default; a ``[model] preset`` is
        applied over it first).

    Returns
    -------
    Scenario

    Raises
    ------
    ParameterError
        One line naming the table or field, the value and what is allowed; also a section the
        chosen hose model cannot honour (``[bow_wave]`` or ``[pilot]`` without the engagement).
    """
    if not isinstance(data, Mapping):
        raise ParameterError(f"scenario = {data!r}: must be a table of tables")
    for key in data:
        if key not in TABLES:
            raise ParameterError(f"{key}: unknown section; allowed: {', '.join(sorted(TABLES))}")
    head = _table(data, "scenario")
    for key in head:
        if key not in SCENARIO_KEYS:
            raise ParameterError(f"scenario.{key}: unknown field; allowed: {', '.join(sorted(SCENARIO_KEYS))}")
    if "extends" in head:
        raise ParameterError(f"scenario.extends = {head['extends']!r}: only a scenario file may extend another "
                             "(load_scenario); merge the tables with merge_tables first")
    if "duration_s" not in head:
        raise ParameterError("scenario.duration_s: missing; give the simulated time in seconds")
    loop = Loop(controller=Controller.from_mapping(_table(data, "controller")),
                actuator=Actuator.from_mapping(_table(data, "actuator")),
                sensor=Sensor.from_mapping(_table(data, "sensor")),
                drogue_actuator=(DrogueActuator.from_mapping(_table(data, "drogue_actuator"))
                                 if "drogue_actuator" in data else None))
    params = params_from_dict({k: v for k, v in data.items() if k in SECTIONS}, base=_model_base(data, base))
    return Scenario(
        name=str(head.get("name", name)),
        params=params,
        duration_s=head["duration_s"],
        description=str(head.get("description", "")),
        initial=head.get("initial", "equilibrium"),
        initial_pitch_offset_deg=head.get("initial_pitch_offset_deg", 0.0),
        initial_yaw_offset_deg=head.get("initial_yaw_offset_deg", 0.0),
        loop=loop,
        engagement=_engagement(data),
        source=source,
    )


def _model_base(data: Mapping[str, Any], base: Params) -> Params:
    """``base``, or the ``[model] preset`` over it."""
    model = _table(data, "model")
    for key in model:
        if key != "preset":
            raise ParameterError(f"model.{key}: unknown field; allowed: preset")
    if "preset" not in model:
        return base
    if model["preset"] not in preset_names():
        raise ParameterError(
            f"model.preset = {model['preset']!r}: must be one of {', '.join(map(repr, preset_names()))}")
    return load_preset(model["preset"], base=base)


def _engagement(data: Mapping[str, Any]) -> Engagement | None:
    """The engagement of a scenario's tables: with a ``[reel]`` or ``[probe]``; None without (then
    ``[bow_wave]`` and ``[pilot]`` are refused: the fixed-length hose has no probe)."""
    present = {name: ENGAGEMENT_SECTIONS[name].from_mapping(_table(data, name))
               for name in ENGAGEMENT_SECTIONS if name in data}
    if "reel" not in present and "probe" not in present:
        for name in ("bow_wave", "pilot", "receiver"):
            if name in present:
                raise ParameterError(f"{name}: the fixed-length hose has no probe, so it cannot honour [{name}]; "
                                     "add [probe] (and [reel]) to run the engagement, or remove it")
        return None
    return Engagement(**present)
