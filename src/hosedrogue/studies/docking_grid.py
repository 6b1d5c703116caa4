"""The docking studies' cells: which campaigns run, what each is called and the scenario it runs.

A cell is a :class:`CellSpec`: the shipped ``approach-LEVEL`` scenario with a drogue controller,
the bow wave on or off and, optionally, the pilot model flying the probe, another probe closure
speed (the scenario's duration and turbulence window following it: :func:`approach_duration_s`)
or a force limit on the drogue controller (``[actuator] max_force_n``). :func:`cell_scenario`
builds the cell's :class:`~hosedrogue.scenarios.Scenario` in Python from the shipped one, and
:func:`same_scenario` tells two cells that run the same scenario apart from those that do not
(:func:`hosedrogue.studies.docking.run_grid` runs such a scenario once).

Three lists of cells are defined here (docs/engagement.md, "Docking statistics"):

* :func:`grid_specs`: turbulence level x drogue controller x bow wave, and the pilot's cell;
* :func:`speed_specs`: the closure-speed study (approach-moderate, bow wave on, no controller and
  PID, per probe speed);
* :func:`force_specs`: the force-limit study (bow wave on, PID and LQR per force limit, with the
  unlimited and the no-controller cells of the main grid beside them).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

__all__ = ["CONTROLLERS", "LEVELS", "PILOT", "CAMPAIGN_SEED", "CLOSURE_SPEEDS_M_S", "SPEED_LEVEL",
           "SPEED_CONTROLLERS", "FORCE_LIMITS_N", "FORCE_LEVELS", "FORCE_CONTROLLERS", "CellSpec", "cell_name",
           "grid_specs", "speed_specs", "force_specs", "approach_duration_s", "cell_scenario", "same_scenario"]

#: Drogue controllers of the grid, in the order of the legends (the paper's gains; each acts on
#: the drogue during the approach and is off once coupled).
CONTROLLERS = ("none", "pid", "lqr")

#: The pilot model flying the probe (docs/engagement.md, "Pilot model", its defaults) with no drogue
#: controller: not a drogue controller but a row of the grid beside them, bow wave on only (cells
#: ``<level>-pilot-bow-on``), so the receiver's own chase compares with the drogue's station keeping.
PILOT = "pilot"

#: Turbulence levels of the shipped approach scenarios (``approach-LEVEL``), in the order of the x axis.
LEVELS = ("light", "moderate", "severe")

#: Campaign seed of every cell: run i uses ``run_seed(CAMPAIGN_SEED, i)`` in every cell, so the
#: cells of a level of the same duration see the same gust records (common random numbers).
CAMPAIGN_SEED = 0

#: Probe closure speeds of the closure-speed study [m/s]: from the latch window's 0.5 m/s minimum
#: up to 2 m/s, the fastest at which the 1 m push still cruises before its 1 s stop.
CLOSURE_SPEEDS_M_S = (0.5, 0.75, 1.0, 1.5, 2.0)

#: Turbulence level of the closure-speed study (the middle one: neither always nor never captured).
SPEED_LEVEL = "moderate"

#: Drogue controllers of the closure-speed study.
SPEED_CONTROLLERS = ("none", "pid")

#: Force limits per axis of the force-limit study [N]: from well below the PID's median peak in
#: moderate turbulence (92 N unlimited) to about its largest there (231 N), in factors of two.
FORCE_LIMITS_N = (25.0, 50.0, 100.0, 200.0)

#: Turbulence levels of the force-limit study (light is captured by either controller with 77 N at most).
FORCE_LEVELS = ("moderate", "severe")

#: Drogue controllers of the force-limit study.
FORCE_CONTROLLERS = ("pid", "lqr")

#: :func:`approach_duration_s` rounds up to whole tenths of a second (this many per second [1/s]),
#: after rounding away the float noise below 1e-6 of a tenth (so 3 m / 1 m/s + 1.5 s stays 4.5 s).
_TENTHS_PER_S = 10.0


def cell_name(level: str, controller: str, bow_wave: bool, pilot: bool = False,
              closure_speed_m_s: float | None = None, max_force_n: float | None = None) -> str:
    """Folder name of one campaign, e.g. ``moderate-pid-bow-on``, ``moderate-pilot-bow-on``,
    ``moderate-none-bow-on-v0.5`` or ``moderate-pid-bow-on-f100``.

    Parameters
    ----------
    level : str
        Turbulence level ("light", "moderate", "severe").
    controller : str
        Drogue controller type ("none", "pid", "lqr").
    bow_wave : bool
        Bow wave on.
    pilot : bool
        The pilot model flies the probe (named ``pilot`` in place of the controller "none").
    closure_speed_m_s : float or None
        The probe's closure speed [m/s] when it is not the scenario's own (suffix ``-v<speed>``).
    max_force_n : float or None
        The actuator's force limit per axis [N] (suffix ``-f<limit>``); None: unlimited.

    Returns
    -------
    str
    """
    who = (PILOT if controller == "none" else f"{controller}-{PILOT}") if pilot else controller
    name = f"{level}-{who}-bow-{'on' if bow_wave else 'off'}"
    name = name if closure_speed_m_s is None else f"{name}-v{closure_speed_m_s:g}"
    return name if max_force_n is None else f"{name}-f{max_force_n:g}"


@dataclass(frozen=True)
class CellSpec:
    """What one campaign of the grid runs: ``approach-LEVEL`` with these changes (:func:`cell_scenario`)."""

    level: str  #: turbulence level ("light", "moderate", "severe")
    controller: str = "none"  #: drogue controller type ("none", "pid", "lqr")
    bow_wave: bool = True  #: bow wave on
    pilot: bool = False  #: the pilot model flies the probe
    closure_speed_m_s: float | None = None  #: probe closure speed [m/s]; None: the scenario's own
    max_force_n: float | None = None  #: ``[actuator] max_force_n``, per axis [N]; None: unlimited

    def __post_init__(self) -> None:
        from ..errors import ParameterError
        from ..sections import CONTROLLER_TYPES

        if self.level not in LEVELS:
            raise ParameterError(f"level = {self.level!r}: must be one of {', '.join(map(repr, LEVELS))}")
        if self.controller not in CONTROLLER_TYPES:
            raise ParameterError(f"controller = {self.controller!r}: must be one of "
                                 f"{', '.join(map(repr, CONTROLLER_TYPES))}")
        for key in ("closure_speed_m_s", "max_force_n"):
            v = getattr(self, key)
            if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
                                  or v <= 0):
                raise ParameterError(f"{key} = {v!r}: must be a finite number > 0 or None")

    @property
    def name(self) -> str:
        """The cell's folder name (:func:`cell_name`)."""
        return cell_name(self.level, self.controller, self.bow_wave, self.pilot, self.closure_speed_m_s,
                         self.max_force_n)


def grid_specs(levels=LEVELS, controllers=CONTROLLERS, pilot_levels=LEVELS) -> list[CellSpec]:
    """The main grid: level x controller x bow wave (on, off), and the pilot's cell (bow wave on)
    for each level also in ``pilot_levels``, in table order.

    Parameters
    ----------
    levels : sequence of str
        Turbulence levels.
    controllers : sequence of str
        Drogue controller types.
    pilot_levels : sequence of str
        Levels that get a pilot cell (empty: none).

    Returns
    -------
    list of CellSpec
    """
    specs = []
    for level in levels:
        specs += [CellSpec(level, c, True) for c in controllers]
        if level in pilot_levels:
            specs.append(CellSpec(level, "none", True, pilot=True))
        specs += [CellSpec(level, c, False) for c in controllers]
    return specs


def speed_specs(speeds=CLOSURE_SPEEDS_M_S, level: str = SPEED_LEVEL, controllers=SPEED_CONTROLLERS) -> list[CellSpec]:
    """The closure-speed study's cells: bow wave on, each controller x probe speed.

    Parameters
    ----------
    speeds : sequence of float
        Probe closure speeds [m/s].
    level : str
        Turbulence level.
    controllers : sequence of str
        Drogue controller types.

    Returns
    -------
    list of CellSpec
    """
    return [CellSpec(level, c, True, False, float(v)) for c in controllers for v in speeds]


def force_specs(limits=FORCE_LIMITS_N, levels=FORCE_LEVELS, controllers=FORCE_CONTROLLERS) -> list[CellSpec]:
    """The force-limit study's cells per level: no controller (the main grid's), then per
    controller each limit and the unlimited one (the main grid's), all with the bow wave on.

    Parameters
    ----------
    limits : sequence of float
        Force limits per axis [N].
    levels : sequence of str
        Turbulence levels.
    controllers : sequence of str
        Drogue controller types.

    Returns
    -------
    list of CellSpec
    """
    specs = []
    for level in levels:
        specs.append(CellSpec(level, "none", True))
        for c in controllers:
            specs += [CellSpec(level, c, True, max_force_n=float(f)) for f in limits]
            specs.append(CellSpec(level, c, True))
    return specs


def approach_duration_s(probe, closure_speed_m_s: float) -> float:
    """Scenario duration for a closure speed: the time at which the prescribed probe path stops if
    contact is at the balance position, rounded up to 0.1 s.

    The probe reaches the balance position after ``standoff_m / v``; once coupled it cruises
    ``max(push_m - v stop_time_s / 2, 0)`` and stops over ``stop_time_s`` (the half-cosine ramp
    covers ``v stop_time_s / 2``). The shipped approach scenarios' 4.5 s is this at 1 m/s (3 m, 1 m
    of push, 1 s stop), so the 1 m/s cell is the shipped scenario. The push is the margin for
    contact: a drogue up to ``push_m + v stop_time_s / 2`` (1.5 m at 1 m/s) ahead of its balance
    position is still met; a run that is not would be counted "no contact".

    Parameters
    ----------
    probe : hosedrogue.sections.Probe
        The scenario's probe: ``standoff_m`` [m], ``push_m`` [m], ``stop_time_s`` [s].
    closure_speed_m_s : float
        Probe closure speed v [m/s], > 0.

    Returns
    -------
    float
        Duration [s].
    """
    from ..errors import ParameterError

    v = float(closure_speed_m_s)
    if not (math.isfinite(v) and v > 0):
        raise ParameterError(f"closure_speed_m_s = {closure_speed_m_s!r}: must be a finite number > 0 m/s")
    after = max(probe.push_m - 0.5 * v * probe.stop_time_s, 0.0) / v + probe.stop_time_s
    return math.ceil(round((probe.standoff_m / v + after) * _TENTHS_PER_S, 6)) / _TENTHS_PER_S


def cell_scenario(spec: CellSpec):
    """The scenario of one cell: the shipped ``approach-LEVEL`` with the cell's drogue controller,
    bow wave, pilot (its defaults), closure speed (with the duration of :func:`approach_duration_s`)
    and force limit, named ``approach-<cell>``.

    The turbulence window is set explicitly in every cell: from the shipped scenario's start to the
    end of the cell's run, so the gusts last the whole approach at every closure speed.

    Parameters
    ----------
    spec : CellSpec
        The cell.

    Returns
    -------
    hosedrogue.scenarios.Scenario
    """
    from ..scenarios import load_scenario
    from ..sections import Pilot

    base = load_scenario(f"approach-{spec.level}")
    eng = base.engagement
    eng = dataclasses.replace(eng, bow_wave=dataclasses.replace(eng.bow_wave, enabled=bool(spec.bow_wave)))
    if spec.pilot:
        eng = dataclasses.replace(eng, pilot=Pilot(enabled=True))
    duration, description = base.duration_s, base.description
    if spec.closure_speed_m_s is not None:
        v = float(spec.closure_speed_m_s)
        duration = approach_duration_s(eng.probe, v)
        eng = dataclasses.replace(eng, probe=dataclasses.replace(eng.probe, closure_speed_m_s=v))
        description += f"; here the probe closes at {v:g} m/s"
    loop = base.with_controller(spec.controller).loop
    if spec.max_force_n is not None:
        loop = dataclasses.replace(loop, actuator=dataclasses.replace(loop.actuator, max_force_n=float(spec.max_force_n)))
    window = {"start_s": base.params.turbulence.start_s, "duration_s": duration}
    return dataclasses.replace(base, name=f"approach-{spec.name}", description=description, duration_s=duration,
                               params=base.params.replace(turbulence=window), loop=loop, engagement=eng, source="")


def same_scenario(a, b) -> bool:
    """Whether two scenarios run the same: equal but for their names, descriptions and sources.

    Parameters
    ----------
    a, b : hosedrogue.scenarios.Scenario
        The scenarios.

    Returns
    -------
    bool
    """
    def content(s):
        return dataclasses.replace(s, name="", description="", source="")
    return content(a) == content(b)
