"""Scenario files: a TOML file with a ``[scenario]`` table (run settings), optional
``[controller]``, ``[actuator]`` and ``[sensor]`` tables, and any parameter sections of
:mod:`hosedrogue.params` (``[flight]``, ``[turbulence]``, ...) overriding the paper's case.
``[model] preset = "converged"`` starts from a shipped model preset (:mod:`hosedrogue.config`)
instead; the file's parameter sections then override the preset.

Scenarios shipped with the package are found by name (``paper-turbulence``) or file name
(``scenarios/paper-turbulence.toml``); any other path is read from disk.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from ..config import read_toml
from ..params import SECTIONS, PAPER, ParameterError, Params, params_from_dict

SCENARIO_KEYS = {
    "name", "description", "duration_s", "initial", "initial_pitch_offset_deg",
    "initial_yaw_offset_deg",
}
CONTROLLER_TYPES = ("none", "pid", "lqr")


@dataclass(frozen=True)
class Scenario:
    """A runnable case: parameters plus run settings."""

    name: str  #: scenario name (``[scenario] name``, or the file's stem)
    params: Params  #: the model, environment and numerics parameters
    duration_s: float  #: simulated time [s]
    description: str = ""  #: one line for people
    #: "equilibrium": start at rest at the balance position; "displaced": add the offsets below
    #: to every link's balance angles and release from rest.
    initial: str = "equilibrium"
    initial_pitch_offset_deg: float = 0.0  #: pitch added to every link for ``displaced`` [deg]
    initial_yaw_offset_deg: float = 0.0  #: yaw added to every link for ``displaced`` [deg]
    controller: str = "none"  #: "none", "pid" or "lqr"
    #: Design options of the controller: PID ``lateral``/``vertical`` = [K_P, K_I, K_D, N];
    #: LQR ``design`` ("balanced", the paper's reading, default; or "integral"), ``q_diag`` (4:
    #: the balanced states, lateral then vertical [1/(m N)]; integral: [P_ny, P_nz, z_ny, z_nz])
    #: and ``r_diag`` (2) [1/N^2]. Missing entries take the paper's values.
    controller_options: dict = field(default_factory=dict)
    actuator: dict = field(default_factory=dict)  #: actuator limits: max_force_n [N], max_rate_n_s [N/s], ...
    sensor: dict = field(default_factory=dict)  #: sensor noise: noise_std_m [m], sample_time_s [s]
    source: str = ""  #: where it was read from (``scenarios/NAME.toml`` or a path)
    #: Sections validated outside the core (``[reel]``, ``[probe]``): name -> validated object.
    extra: dict = field(default_factory=dict)

    def with_overrides(self, duration_s: float | None = None, seed: int | None = None) -> "Scenario":
        import dataclasses

        s = self
        if duration_s is not None:
            _check_duration(duration_s, "--duration")
            s = dataclasses.replace(s, duration_s=float(duration_s))
        if seed is not None:
            if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
                raise ParameterError(f"--seed = {seed!r}: must be an integer >= 0")
            s = dataclasses.replace(s, params=s.params.replace(turbulence={"seed": seed}))
        return s


def _check_duration(value: Any, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (
        math.isfinite(value) and 0 < value <= 86400
    ):
        raise ParameterError(f"{name} = {value!r}: must be a finite number in (0, 86400] s")
    return float(value)


#: Options each controller type accepts: name -> (length, lower bound, bound is exclusive).
CONTROLLER_OPTIONS = {
    "none": {},
    "pid": {"lateral": (4, 0.0, False), "vertical": (4, 0.0, False)},
    "lqr": {"design": None, "q_diag": (4, 0.0, False), "r_diag": (2, 0.0, True)},
}


def _controller_options(ctype: str, given: dict) -> dict:
    allowed = CONTROLLER_OPTIONS[ctype]
    out = {}
    for key, value in given.items():
        if key not in allowed:
            names = ", ".join(["type", *allowed])
            raise ParameterError(f"controller.{key}: unknown field for type {ctype!r}; allowed: {names}")
        if key == "design":
            from ..controllers.design import LQR_DESIGNS  # one definition, next to the designs

            if value not in LQR_DESIGNS:
                raise ParameterError(
                    f"controller.design = {value!r}: must be one of {', '.join(map(repr, LQR_DESIGNS))}")
            out[key] = value
            continue
        size, lo, strict = allowed[key]
        ok = (isinstance(value, list) and len(value) == size and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            and (v > lo if strict else v >= lo) for v in value))
        if not ok:
            rel = ">" if strict else ">="
            raise ParameterError(f"controller.{key} = {value!r}: must be a list of {size} finite numbers {rel} {lo:g}")
        out[key] = [float(v) for v in value]
    if ctype == "pid":
        for key in ("lateral", "vertical"):
            if key in out and out[key][3] <= 0:
                raise ParameterError(f"controller.{key} = {out[key]!r}: the derivative filter N (4th) must be > 0 rad/s")
    return out


def shipped_scenarios() -> list[str]:
    """Names of the scenarios shipped with the package."""
    root = resources.files(__package__)
    return sorted(p.name[:-5] for p in root.iterdir() if p.name.endswith(".toml"))


def resolve(name_or_path: str) -> tuple[str, dict]:
    """Find a scenario by shipped name, ``scenarios/NAME.toml`` or path; return (source, data).

    Parameters
    ----------
    name_or_path : str
        A shipped scenario name, ``scenarios/NAME.toml``, or a TOML file's path.

    Returns
    -------
    source : str
        Where it was found.
    data : dict
        The parsed TOML.
    """
    path = Path(name_or_path)
    if path.exists():
        return str(path), read_toml(path)
    stem = path.name[:-5] if path.name.endswith(".toml") else path.name
    root = resources.files(__package__)
    candidate = root / f"{stem}.toml"
    if candidate.is_file() and (path.parent in (Path("."), Path("scenarios"))):
        with resources.as_file(candidate) as p:
            return f"scenarios/{stem}.toml", read_toml(p)
    raise ParameterError(
        f"scenario {name_or_path!r}: no such file or shipped scenario; shipped: {', '.join(shipped_scenarios())}"
    )


def _table(data: dict, name: str) -> dict:
    """The table ``data[name]`` (empty if absent) as a new dict; anything else is a ParameterError."""
    value = data.get(name, {})
    if not isinstance(value, dict):
        raise ParameterError(f"{name} = {value!r}: must be a table of fields ([{name}])")
    return dict(value)


def load_scenario(name_or_path: str, base: Params = PAPER) -> Scenario:
    """Load and validate a scenario file (see the module docstring).

    Parameters
    ----------
    name_or_path : str
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
    source, data = resolve(name_or_path)
    from ..engagement.spec import ENGAGEMENT_SECTIONS, validate_sections  # hook: non-core sections

    known = set(SECTIONS) | {"scenario", "controller", "actuator", "sensor", "model"} | set(ENGAGEMENT_SECTIONS)
    for key in data:
        if key not in known:
            raise ParameterError(f"{key}: unknown section; allowed: {', '.join(sorted(known))}")
    sc = _table(data, "scenario")
    for key in sc:
        if key not in SCENARIO_KEYS:
            raise ParameterError(f"scenario.{key}: unknown field; allowed: {', '.join(sorted(SCENARIO_KEYS))}")
    if "duration_s" not in sc:
        raise ParameterError("scenario.duration_s: missing; give the simulated time in seconds")
    duration = _check_duration(sc["duration_s"], "scenario.duration_s")
    initial = sc.get("initial", "equilibrium")
    if initial not in ("equilibrium", "displaced"):
        raise ParameterError(f"scenario.initial = {initial!r}: must be one of 'equilibrium', 'displaced'")
    offsets = {}
    for key in ("initial_pitch_offset_deg", "initial_yaw_offset_deg"):
        v = sc.get(key, 0.0)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and abs(v) <= 60):
            raise ParameterError(f"scenario.{key} = {v!r}: must be a finite number in [-60, 60] deg")
        offsets[key] = float(v)
    ctrl = _table(data, "controller")
    ctype = ctrl.pop("type", "none")
    if ctype not in CONTROLLER_TYPES:
        raise ParameterError(f"controller.type = {ctype!r}: must be one of {', '.join(map(repr, CONTROLLER_TYPES))}")
    options = _controller_options(ctype, ctrl)
    actuator = _table(data, "actuator")
    for key in actuator:
        if key not in ("max_force_n", "max_rate_n_s", "time_constant_s"):
            raise ParameterError(
                f"actuator.{key}: unknown field; allowed: max_force_n, max_rate_n_s, time_constant_s")
    sensor = _table(data, "sensor")
    for key in sensor:
        if key not in ("noise_std_m", "sample_time_s"):
            raise ParameterError(f"sensor.{key}: unknown field; allowed: noise_std_m, sample_time_s")
    from ..params import Actuator, Sensor  # validates values now, before any run or output

    Actuator(**actuator)
    Sensor(**sensor)
    model = data.get("model", {})
    if not isinstance(model, dict):
        raise ParameterError(f"model = {model!r}: must be a table with the field preset")
    for key in model:
        if key != "preset":
            raise ParameterError(f"model.{key}: unknown field; allowed: preset")
    if "preset" in model:
        from ..config import load_preset, preset_names

        if model["preset"] not in preset_names():
            raise ParameterError(
                f"model.preset = {model['preset']!r}: must be one of {', '.join(map(repr, preset_names()))}")
        base = load_preset(model["preset"], base=base)
    params = params_from_dict({k: v for k, v in data.items() if k in SECTIONS}, base=base)
    extra = validate_sections(data)
    return Scenario(
        name=str(sc.get("name", Path(source).stem)),
        params=params,
        duration_s=duration,
        description=str(sc.get("description", "")),
        initial=initial,
        controller=ctype,
        controller_options=options,
        actuator=actuator,
        sensor=sensor,
        source=source,
        extra=extra,
        **offsets,
    )
