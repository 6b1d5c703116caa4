"""The docking studies' cells: which campaigns run, what each is called and the scenario it runs.

A cell is a :class:`CellSpec`: the shipped ``approach-LEVEL`` scenario with a drogue controller,
the bow wave on or off and, optionally, the pilot model flying the probe, another probe closure
speed (the scenario's duration and turbulence window following it: :func:`approach_duration_s`),
a force limit on the drogue controller (``[actuator] max_force_n``) or a drogue that steers
itself with control surfaces (``[drogue_actuator]``, their deflection limit and servo bandwidth). :func:`cell_scenario`
builds the cell's :class:`~hosedrogue.scenarios.Scenario` in Python from the shipped one, and
:func:`same_scenario` tells two cells that run the same scenario apart from those that do not
(:func:`hosedrogue.studies.docking.run_grid` runs such a scenario once).

Three lists of cells are defined here (docs/engagement.md, "Docking statistics"):

* :func:`grid_specs`: turbulence level x drogue controller x bow wave, and the pilot's cell;
* :func:`speed_specs`: the closure-speed study (approach-moderate, bow wave on, no controller and
  PID, per probe speed);
* :func:`force_specs`: the force-limit study (bow wave on, PID and LQR per force limit, with the
  unlimited and the no-controller cells of the main grid beside them);
* :func:`actuator_specs`: the actuated-drogue study (bow wave on, the PID commanding the surfaces,
  per deflection limit and per servo bandwidth, with the ideal-force cell beside them).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

__all__ = ["CONTROLLERS", "LEVELS", "PILOT", "CAMPAIGN_SEED", "CLOSURE_SPEEDS_M_S", "SPEED_LEVEL",
           "SPEED_CONTROLLERS", "FORCE_LIMITS_N", "FORCE_LEVELS", "FORCE_CONTROLLERS", "DEFLECTION_LIMITS_DEG",
           "SERVO_BANDWIDTHS_HZ", "ACTUATOR_LEVELS", "ACTUATOR_CONTROLLERS", "CellSpec", "cell_name", "grid_specs",
           "speed_specs", "force_specs", "actuator_specs", "approach_duration_s", "level_scenario", "cell_scenario",
           "same_scenario"]

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

#: Deflection limits of the actuated-drogue study [deg]: at the paper's flight condition 1 deg of
#: every surface is 27 N per axis (two surfaces of C_F,delta = 0.45 /rad on 0.2922 m^2 at q = 5.9
#: kPa), so 1, 2, 4, 8 deg are the force-limit study's 25-200 N; 20 deg is the default.
DEFLECTION_LIMITS_DEG = (1.0, 2.0, 4.0, 8.0, 20.0)

#: Servo bandwidths of the actuated-drogue study [Hz]: below, at and above the paper's PID's
#: stability limit of about 11 Hz (hosedrogue.studies.drogue_actuator.servo_margins); 30 Hz is the default.
SERVO_BANDWIDTHS_HZ = (5.0, 10.0, 15.0, 20.0, 30.0, 60.0)

#: Turbulence levels of the actuated-drogue study (light is captured with a few deg: the PID's peak there is 77 N).
ACTUATOR_LEVELS = ("moderate", "severe")

#: Drogue controllers of the actuated-drogue study.
ACTUATOR_CONTROLLERS = ("pid",)

#: :func:`approach_duration_s` rounds up to whole tenths of a second (this many per second [1/s]),
#: after rounding away the float noise below 1e-6 of a tenth (so 3 m / 1 m/s + 1.5 s stays 4.5 s).
_TENTHS_PER_S = 10.0


def cell_name(level: str, controller: str, bow_wave: bool, pilot: bool = False,
              closure_speed_m_s: float | None = None, max_force_n: float | None = None,
              surfaces: tuple | None = None) -> str:
    """Folder name of one campaign, e.g. ``moderate-pid-bow-on``, ``moderate-pilot-bow-on``,
    ``moderate-none-bow-on-v0.5``, ``moderate-pid-bow-on-f100`` or ``moderate-pid-bow-on-d4-b30``.

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
    surfaces : (float, float) or None
        The drogue's control surfaces' deflection limit [deg] and servo bandwidth [Hz] (suffix
        ``-d<limit>-b<bandwidth>``); None: the ideal force.

    Returns
    -------
    str
    """
    who = (PILOT if controller == "none" else f"{controller}-{PILOT}") if pilot else controller
    name = f"{level}-{who}-bow-{'on' if bow_wave else 'off'}"
    name = name if closure_speed_m_s is None else f"{name}-v{closure_speed_m_s:g}"
    name = name if max_force_n is None else f"{name}-f{max_force_n:g}"
    return name if surfaces is None else f"{name}-d{surfaces[0]:g}-b{surfaces[1]:g}"


@dataclass(frozen=True)
class CellSpec:
    """What one campaign of the grid runs: ``approach-LEVEL`` with these changes (:func:`cell_scenario`)."""

    level: str  #: turbulence level ("light", "moderate", "severe")
    controller: str = "none"  #: drogue controller type ("none", "pid", "lqr")
    bow_wave: bool = True  #: bow wave on
    pilot: bool = False  #: the pilot model flies the probe
    closure_speed_m_s: float | None = None  #: probe closure speed [m/s]; None: the scenario's own
    max_force_n: float | None = None  #: ``[actuator] max_force_n``, per axis [N]; None: unlimited
    #: the drogue's control surfaces (``[drogue_actuator]``): their deflection limit [deg]; None: the
    #: ideal force (unless bandwidth_hz is given: then the default limit)
    max_deflection_deg: float | None = None
    bandwidth_hz: float | None = None  #: their servo bandwidth [Hz]; None: the default (with max_deflection_deg)

    def __post_init__(self) -> None:
        from ..errors import ParameterError
        from ..spec.sections import CONTROLLER_TYPES

        if self.level not in LEVELS:
            raise ParameterError(f"level = {self.level!r}: must be one of {', '.join(map(repr, LEVELS))}")
        if self.controller not in CONTROLLER_TYPES:
            raise ParameterError(f"controller = {self.controller!r}: must be one of "
                                 f"{', '.join(map(repr, CONTROLLER_TYPES))}")
        for key in ("closure_speed_m_s", "max_force_n", "max_deflection_deg", "bandwidth_hz"):
            v = getattr(self, key)
            if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
                                  or v <= 0):
                raise ParameterError(f"{key} = {v!r}: must be a finite number > 0 or None")

    @property
    def surfaces(self):
        """The cell's ``[drogue_actuator]`` (:class:`hosedrogue.spec.sections.DrogueActuator`), or None
        for the ideal force."""
        from ..spec.sections import DrogueActuator

        if self.max_deflection_deg is None and self.bandwidth_hz is None:
            return None
        given = {"max_deflection_deg": self.max_deflection_deg, "bandwidth_hz": self.bandwidth_hz}
        return DrogueActuator(**{k: float(v) for k, v in given.items() if v is not None})

    @property
    def name(self) -> str:
        """The cell's folder name (:func:`cell_name`)."""
        s = self.surfaces
        return cell_name(self.level, self.controller, self.bow_wave, self.pilot, self.closure_speed_m_s,
                         self.max_force_n, None if s is None else (s.max_deflection_deg, s.bandwidth_hz))


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


def actuator_specs(deflections_deg=DEFLECTION_LIMITS_DEG, bandwidths_hz=SERVO_BANDWIDTHS_HZ, levels=ACTUATOR_LEVELS,
                   controllers=ACTUATOR_CONTROLLERS) -> list[CellSpec]:
    """The actuated-drogue study's cells per level and controller, bow wave on: the ideal force
    (the main grid's cell), each deflection limit at the default bandwidth, each bandwidth at the
    default deflection limit (the default cell once).

    Parameters
    ----------
    deflections_deg : sequence of float
        Deflection limits [deg].
    bandwidths_hz : sequence of float
        Servo bandwidths [Hz].
    levels : sequence of str
        Turbulence levels.
    controllers : sequence of str
        Drogue controller types ("pid", "lqr").

    Returns
    -------
    list of CellSpec
    """
    from ..spec.sections import DrogueActuator

    default = DrogueActuator()
    specs = []
    for level in levels:
        for c in controllers:
            cells = [CellSpec(level, c, True)]
            cells += [CellSpec(level, c, True, max_deflection_deg=float(d), bandwidth_hz=default.bandwidth_hz)
                      for d in deflections_deg]
            cells += [CellSpec(level, c, True, max_deflection_deg=default.max_deflection_deg, bandwidth_hz=float(f))
                      for f in bandwidths_hz]
            specs += list(dict.fromkeys(cells))  # the default cell once
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
    probe : hosedrogue.spec.sections.Probe
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


def level_scenario(base, level: str):
    """A user's approach scenario in a cell's turbulence: ``base`` with the standard intensity
    ``level`` at its altitude, turbulence on (the shipped ``approach-LEVEL`` are
    ``approach-moderate`` so changed).

    Parameters
    ----------
    base : hosedrogue.scenarios.Scenario
        An engagement scenario (with ``[probe]``).
    level : str
        One of :data:`LEVELS`.

    Returns
    -------
    hosedrogue.scenarios.Scenario

    Raises
    ------
    ParameterError
        ``base`` is a fixed-length scenario.
    """
    base.require_model("engagement", "scenario", "a docking cell runs an approach (an engagement scenario with "
                       "[probe], e.g. approach-moderate)")
    return dataclasses.replace(base, params=base.params.replace(turbulence={"enabled": True, "intensity": level}))


def cell_scenario(spec: CellSpec, base=None):
    """The scenario of one cell: the shipped ``approach-LEVEL`` with the cell's drogue controller,
    bow wave, pilot (its defaults), closure speed (with the duration of :func:`approach_duration_s`),
    force limit and control surfaces (with the RK4 step their servo needs), named ``approach-<cell>``.

    The turbulence window is set explicitly in every cell: from the shipped scenario's start to the
    end of the cell's run, so the gusts last the whole approach at every closure speed.

    Parameters
    ----------
    spec : CellSpec
        The cell.
    base : hosedrogue.scenarios.Scenario, optional
        Instead of the shipped ``approach-LEVEL``, the user's approach in the cell's turbulence
        (:func:`level_scenario`); the cell is then named ``<base name>-<cell>``.

    Returns
    -------
    hosedrogue.scenarios.Scenario
    """
    from ..scenarios import load_scenario
    from ..spec.sections import Pilot

    prefix = "approach" if base is None else base.name
    base = load_scenario(f"approach-{spec.level}") if base is None else level_scenario(base, spec.level)
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
    params = base.params.replace(turbulence={"start_s": base.params.turbulence.start_s, "duration_s": duration})
    if spec.surfaces is not None:
        from .drogue_actuator import resolved_params

        loop = dataclasses.replace(loop, drogue_actuator=spec.surfaces)
        params = resolved_params(params, spec.surfaces)  # the RK4 step the servo needs
    return dataclasses.replace(base, name=f"{prefix}-{spec.name}", description=description, duration_s=duration,
                               params=params, loop=loop, engagement=eng, source="")


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
