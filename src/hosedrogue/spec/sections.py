"""The run's sections besides the model's parameters: the control loop's actuator and sensor, the
drogue controller, and the engagement's reel, probe, bow wave, pilot and receiver (scenario tables
``[actuator]``, ``[sensor]``, ``[controller]``, ``[reel]``, ``[probe]``, ``[bow_wave]``,
``[pilot]``, ``[receiver]``; the drogue's control surfaces, ``[drogue_actuator]``, are
:mod:`hosedrogue.spec.drogue_surfaces`'). Validated at construction like :mod:`hosedrogue.spec.params`
(:class:`hosedrogue.spec.fields.Section`): a wrong field raises a one-line
:class:`~hosedrogue.errors.ParameterError` naming field, value and allowed range. SI units, the
unit in every field name. The defaults and their reasons are in ``docs/engagement.md``
(engagement) and ``docs/model.md`` (actuator, sensor, drogue actuator); the sampled-data
controllers of the user (``[controller] type = "python"``, ``[reel] law = "python"``,
``[receiver]``) in ``docs/controllers.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

from ..errors import ParameterError
from .drogue_surfaces import DrogueActuator
from .fields import Section, check_entry, choice, entry, entry_name, flag, real, table, vec3
from .receiver import Receiver


@dataclass(frozen=True)
class Actuator(Section):
    """Limits on the control force applied to the drogue.

    With a finite rate the applied force follows the command through a first-order lag of
    ``time_constant_s`` whose slope is clipped to the rate limit.
    """

    _section = "actuator"
    #: Largest force magnitude per axis [N] (inf: no limit).
    max_force_n: float = field(default=math.inf, metadata=real(0.0, unit="N", inf_ok=True))
    #: Largest rate of change of the applied force [N/s] (inf: no limit, no lag).
    max_rate_n_s: float = field(default=math.inf, metadata=real(0.0, unit="N/s", inf_ok=True))
    #: Time constant of the lag of a rate-limited actuator [s].
    time_constant_s: float = field(default=0.01, metadata=real(0.0, unit="s"))

    @property
    def rate_limited(self) -> bool:
        """True when the rate limit is finite (the applied force is then part of the state)."""
        return math.isfinite(self.max_rate_n_s)

    def as_array(self):
        """``[max_hor_n, max_ver_n, max_rate_n_s, time_constant_s]`` [N, N, N/s, s] for the kernels."""
        import numpy as np

        return np.array([self.max_force_n, self.max_force_n, self.max_rate_n_s, self.time_constant_s])


@dataclass(frozen=True)
class Sensor(Section):
    """White position noise on the measured drogue position, and the measurement's delay.

    The built-in continuous controllers read the drogue's lateral and vertical offset plus the
    noise; the sampled-data controllers (docs/controllers.md) read a whole measurement taken
    ``delay_s`` before each call, its drogue position with the noise of that instant.
    """

    _section = "sensor"
    #: Standard deviation of the noise per sample and axis [m].
    noise_std_m: float = field(default=0.0, metadata=real(0.0, lo_open=False, unit="m"))
    #: Time each noise sample is held [s].
    sample_time_s: float = field(default=0.01, metadata=real(0.0, unit="s"))
    #: Transport delay of the sampled-data controllers' measurement [s]: each call reads the
    #: quantities of this long ago (those at t = 0 before then); a whole multiple of their sample time
    delay_s: float = field(default=0.0, metadata=real(0.0, 60.0, lo_open=False, unit="s"))


#: The drogue controller's types: none, the paper's PID (Eq. 33), its LQR (Eq. 34), or the user's
#: sampled-data controller in Python (docs/controllers.md).
CONTROLLER_TYPES = ("none", "pid", "lqr", "python")
#: LQR readings: "balanced" (the paper's Q on the balanced states of each 2nd-order channel) or
#: "integral" (Eq. 34 read as integral action); docs/paper-differences.md.
LQR_DESIGNS = ("balanced", "integral")
#: Options each controller type accepts: name -> (length, lower bound, bound is exclusive); the
#: LQR's ``design`` is one of :data:`LQR_DESIGNS`.
CONTROLLER_OPTIONS = {
    "none": {},
    "pid": {"lateral": (4, 0.0, False), "vertical": (4, 0.0, False)},
    "lqr": {"design": None, "q_diag": (4, 0.0, False), "r_diag": (2, 0.0, True)},
    "python": {},
}
#: Keys of ``[controller]`` besides ``type`` and the design options, per type: the built-in
#: designs may run sampled (``sample_time_s`` > 0), a Python controller names its factory.
CONTROLLER_KEYS = {"none": (), "pid": ("sample_time_s",), "lqr": ("sample_time_s",),
                   "python": ("entry", "sample_time_s", "options")}
#: Longest sample time of a sampled-data controller [s].
MAX_SAMPLE_TIME_S = 10.0


@dataclass(frozen=True)
class Controller:
    """The drogue controller of a scenario (``[controller]``): its type and design options.

    Options: PID ``lateral``/``vertical`` = [K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s]];
    LQR ``design`` (:data:`LQR_DESIGNS`), ``q_diag`` (4: the balanced states, lateral then
    vertical [1/(m N)]; integral: [P_ny, P_nz, z_ny, z_nz]) and ``r_diag`` (2) [1/N^2]. Missing
    entries take the paper's values. A PID or LQR with ``sample_time_s`` > 0 runs as its
    zero-order-hold discretization, called every ``sample_time_s`` (0: continuous, compiled in
    the loop). Type ``"python"``: the user's sampled-data controller ``entry`` (``"package.module:
    factory"``, or the factory itself from Python), built as ``factory(**options)`` and called
    every ``sample_time_s`` (docs/controllers.md).
    """

    #: "none", "pid", "lqr" or "python"
    type: str = "none"
    #: the design options of the type (validated; lists of floats, or the LQR's design name); for
    #: "python" the keyword options of the factory
    options: dict = field(default_factory=dict, hash=False)
    #: time between the controller's calls [s]; 0: continuous (the built-in designs only)
    sample_time_s: float = 0.0
    #: "python": the factory, ``"package.module:factory"`` (from Python also the callable itself)
    entry: Any = ""

    def __post_init__(self) -> None:
        if self.type not in CONTROLLER_TYPES:
            raise ParameterError(f"controller.type = {self.type!r}: must be one of "
                                 f"{', '.join(map(repr, CONTROLLER_TYPES))}")
        object.__setattr__(self, "sample_time_s", _sample_time(self.type, self.sample_time_s))
        if self.type == "python":
            object.__setattr__(self, "entry", check_entry("controller.entry", self.entry))
            if self.entry == "":
                raise ParameterError('controller.entry: missing; type "python" needs the factory of the controller, '
                                     '"package.module:factory"')
            if not isinstance(self.options, Mapping) or not all(isinstance(k, str) for k in self.options):
                raise ParameterError(f"controller.options = {self.options!r}: must be a table of options "
                                     "(keyword arguments of the factory)")
            object.__setattr__(self, "options", dict(self.options))
            return
        if self.entry != "":
            raise ParameterError(f"controller.entry = {entry_name(self.entry)!r}: only type 'python' names a factory "
                                 f"(type is {self.type!r})")
        object.__setattr__(self, "options", _controller_options(self.type, dict(self.options)))

    @property
    def sampled(self) -> bool:
        """True when the controller runs as a sampled-data controller (``sample_time_s`` > 0)."""
        return self.sample_time_s > 0.0

    @classmethod
    def from_mapping(cls, data: Any) -> "Controller":
        """The controller of a ``[controller]`` table (``type`` plus the type's options).

        Parameters
        ----------
        data : Mapping
            ``{"type": ..., option: value, ...}``; type "python": ``entry``, ``sample_time_s``
            and an ``options`` table.

        Returns
        -------
        Controller

        Raises
        ------
        ParameterError
            Not a table, an unknown type or option, or an option's value out of range.
        """
        if not isinstance(data, Mapping):
            raise ParameterError(f"controller = {data!r}: must be a table of fields ([controller])")
        data = dict(data)
        ctype = data.pop("type", "none")
        if ctype not in CONTROLLER_TYPES:
            return cls(ctype)  # the one-line error of an unknown type
        extra = {key: data.pop(key) for key in CONTROLLER_KEYS[ctype] if key in data}
        if ctype == "python":
            for key in data:
                raise ParameterError(f"controller.{key}: unknown field for type 'python'; allowed: type, "
                                     f"{', '.join(CONTROLLER_KEYS['python'])} (the factory's options go in "
                                     "[controller.options])")
            return cls(ctype, extra.pop("options", {}), **extra)
        return cls(ctype, data, **extra)

    def to_dict(self) -> dict[str, Any]:
        """``{"type": ..., **options}`` (TOML/JSON-ready); with ``sample_time_s`` when sampled and,
        for "python", ``entry`` (a factory given from Python as ``"module:qualname"``) and ``options``.

        Returns
        -------
        dict
        """
        if self.type == "python":
            return {"type": self.type, "entry": entry_name(self.entry), "sample_time_s": self.sample_time_s,
                    "options": dict(self.options)}
        out = {"type": self.type, **{k: (list(v) if isinstance(v, (list, tuple)) else v)
                                     for k, v in self.options.items()}}
        return {**out, "sample_time_s": self.sample_time_s} if self.sampled else out


def _sample_time(ctype: str, value: Any) -> float:
    """The checked ``controller.sample_time_s`` [s] of a controller of type ``ctype``."""
    ok = not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value)
    if ctype == "none" and value != 0.0:
        raise ParameterError(f"controller.sample_time_s = {value!r}: type 'none' has no sample time")
    if ctype == "python":
        if not ok or not 0.0 < value <= MAX_SAMPLE_TIME_S:
            raise ParameterError(f"controller.sample_time_s = {value!r}: must be a finite number in "
                                 f"(0, {MAX_SAMPLE_TIME_S:g}] s (type 'python' is called every sample_time_s)")
    elif not ok or not 0.0 <= value <= MAX_SAMPLE_TIME_S:
        raise ParameterError(f"controller.sample_time_s = {value!r}: must be a finite number in "
                             f"[0, {MAX_SAMPLE_TIME_S:g}] s (0: continuous)")
    return float(value)


def _controller_options(ctype: str, given: dict) -> dict:
    allowed = CONTROLLER_OPTIONS[ctype]
    out = {}
    for key, value in given.items():
        if key not in allowed:
            names = ", ".join(["type", *allowed])
            raise ParameterError(f"controller.{key}: unknown field for type {ctype!r}; allowed: {names}")
        if key == "design":
            if value not in LQR_DESIGNS:
                raise ParameterError(
                    f"controller.design = {value!r}: must be one of {', '.join(map(repr, LQR_DESIGNS))}")
            out[key] = value
            continue
        size, lo, strict = allowed[key]
        ok = (isinstance(value, (list, tuple)) and len(value) == size and all(
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


REEL_LAWS = ("locked", "constant-tension", "response", "python")


@dataclass(frozen=True)
class Reel(Section):
    """Hose drum unit: ``J_r w' = tau_m - r_d T_0 - c_r w`` (docs/engagement.md, "Reel")."""

    _section = "reel"
    #: "locked": fixed length (or the length schedule below); "constant-tension": tau_m = r_d T_set;
    #: "response": constant tension plus a take-up speed loop driven by the slack; "python": the
    #: user's sampled-data law (entry) commands the take-up speed, which the drive follows
    law: str = field(default="constant-tension", metadata=choice(*REEL_LAWS))
    #: drum radius r_d [m] (hose speed r_d w)
    drum_radius_m: float = field(default=0.3, metadata=real(0.0, 5.0, unit="m"))
    #: J_r [kg m^2]: drum plus wound hose, constant: 30 m of hose (4.4 kg/m) at 0.35 m (16 kg m^2) plus the drum
    inertia_kg_m2: float = field(default=20.0, metadata=real(0.0, 1e5, unit="kg m^2"))
    #: c_r [N m s]: viscous friction torque per drum speed
    friction_n_m_s: float = field(default=1.0, metadata=real(0.0, 1e5, lo_open=False, unit="N m s"))
    #: T_set [N]; < 0 means "the steady trail tension at the balance position" (the default)
    tension_set_n: float = field(default=-1.0, metadata=real(-1.0, 1e6, lo_open=False, unit="N"))
    #: motor torque limit |tau_m| [N m]
    max_torque_n_m: float = field(default=2000.0, metadata=real(0.0, 1e6, unit="N m"))
    #: take-up (reel-in) and payout speed limits [m/s], held by the governor
    max_takeup_speed_m_s: float = field(default=3.0, metadata=real(0.0, 50.0, unit="m/s"))
    #: payout speed limit [m/s]
    max_payout_speed_m_s: float = field(default=3.0, metadata=real(0.0, 50.0, unit="m/s"))
    #: stiffness of the speed governor beyond the speed limits [N s/m]
    governor_gain_n_s_m: float = field(default=20000.0, metadata=real(0.0, 1e8, unit="N s/m"))
    #: response law: commanded take-up speed per metre of slack beyond the dead band [1/s]
    takeup_gain_1_s: float = field(default=4.0, metadata=real(0.0, 1e3, lo_open=False, unit="1/s"))
    #: response law: slack [m] below which no take-up speed is commanded
    slack_dead_band_m: float = field(default=0.02, metadata=real(0.0, 100.0, lo_open=False, unit="m"))
    #: response law: speed-loop gain (force at the drum rim per m/s of speed error) [N s/m]
    speed_gain_n_s_m: float = field(default=3000.0, metadata=real(0.0, 1e8, lo_open=False, unit="N s/m"))
    #: locked law: length change of a payout schedule [m] (negative: take up), 0 for a fixed length;
    #: speed up to payout_speed_m_s along a half-sine acceleration pulse of peak payout_acceleration_m_s2
    payout_m: float = field(default=0.0, metadata=real(-1000.0, 1000.0, lo_open=False, unit="m"))
    #: payout schedule: cruise speed [m/s]
    payout_speed_m_s: float = field(default=1.0, metadata=real(0.0, 50.0, unit="m/s"))
    #: payout schedule: peak acceleration [m/s^2]
    payout_acceleration_m_s2: float = field(default=2.0, metadata=real(0.0, 1000.0, unit="m/s^2"))
    #: payout schedule: start time [s]
    payout_start_s: float = field(default=0.0, metadata=real(0.0, 1e6, lo_open=False, unit="s"))
    #: the drum's end stops: the free hose length [m] fully reeled in (the drogue at the hose
    #: exit) and fully paid out (30 m, the hose the drum inertia above counts); a run whose free
    #: length leaves [min_length_m, max_length_m] stops there, marked incomplete
    min_length_m: float = field(default=1.0, metadata=real(0.0, 1000.0, unit="m"))
    #: fully paid out [m]
    max_length_m: float = field(default=30.0, metadata=real(0.0, 1000.0, unit="m"))
    #: python law: the take-up law's factory "package.module:factory" (docs/controllers.md); its
    #: controller returns the take-up speed command [m/s], positive reeling in; needed to run the
    #: scenario ("" when the stepping API commands the reel)
    entry: Any = field(default="", metadata=entry())
    #: python law: time between the law's calls [s]; the command is held in between
    sample_time_s: float = field(default=0.01, metadata=real(0.0, 10.0, unit="s"))
    #: python law: keyword options of the factory
    options: dict = field(default_factory=dict, hash=False, metadata=table())
    #: python law: time constant of the drum speed's first-order response to the command [s]: the
    #: drive sets the torque this needs, within max_torque_n_m; the command is clipped to the speed limits
    speed_time_constant_s: float = field(default=0.05, metadata=real(0.0, 10.0, unit="s"))

    #: The keys of the "python" law, which mean nothing to the others (left out of their :meth:`to_dict`).
    PYTHON_KEYS = ("entry", "sample_time_s", "options", "speed_time_constant_s")

    def to_dict(self) -> dict[str, Any]:
        """``{field: value}`` (TOML/JSON-ready); the "python" law's keys only with that law.

        Returns
        -------
        dict
        """
        out = super().to_dict()
        return out if self.law == "python" else {k: v for k, v in out.items() if k not in self.PYTHON_KEYS}

    def _check_consistency(self) -> None:
        if self.law != "python" and self.entry != "":
            raise ParameterError(f"reel.entry = {entry_name(self.entry)!r}: only law 'python' names a factory "
                                 f"(law is {self.law!r})")
        if not self.min_length_m < self.max_length_m:
            raise ParameterError(f"reel.min_length_m = {self.min_length_m!r}: must be below reel.max_length_m = "
                                 f"{self.max_length_m!r} m")
        if self.payout_m != 0.0 and self.law != "locked":
            raise ParameterError(
                f"reel.payout_m = {self.payout_m!r}: a payout schedule needs reel.law = 'locked' (got {self.law!r})")


@dataclass(frozen=True)
class Probe(Section):
    """Prescribed probe-tip path, capture test and probe-drogue coupling (docs/engagement.md, "Probe", "Capture" and
    "Coupled phase")."""

    _section = "probe"
    #: False: no probe (the reel alone)
    enabled: bool = field(default=True, metadata=flag())
    #: start point: this far aft of the drogue's balance position [m], plus the offsets
    standoff_m: float = field(default=3.0, metadata=real(0.0, 100.0, unit="m"))
    #: lateral (S_p y, right) and vertical (S_p z, down) offsets of the start point [m]
    offset_y_m: float = field(default=0.0, metadata=real(-10.0, 10.0, lo_open=False, unit="m"))
    #: vertical offset of the start point (S_p z, down) [m]
    offset_z_m: float = field(default=0.0, metadata=real(-10.0, 10.0, lo_open=False, unit="m"))
    #: speed of the probe forward (S_p x) [m/s]
    closure_speed_m_s: float = field(default=1.5, metadata=real(0.0, 10.0, unit="m/s"))
    #: after contact the probe goes on this far forward [m], then holds
    push_m: float = field(default=2.0, metadata=real(0.0, 50.0, lo_open=False, unit="m"))
    #: duration of the half-cosine speed ramp that stops the probe at the end of the push [s]
    stop_time_s: float = field(default=1.0, metadata=real(0.0, 60.0, unit="s"))
    #: capture test: largest radial miss in the coupler plane [m]
    capture_radius_m: float = field(default=0.305, metadata=real(0.0, 5.0, unit="m"))
    #: capture test: closure speed window at the coupler plane [m/s] (lower bound)
    min_closure_speed_m_s: float = field(default=0.5, metadata=real(0.0, 10.0, lo_open=False, unit="m/s"))
    #: capture test: upper bound of the closure speed window [m/s]
    max_closure_speed_m_s: float = field(default=3.0, metadata=real(0.0, 20.0, unit="m/s"))
    #: probe-drogue coupling once captured: spring stiffness [N/m]
    stiffness_n_m: float = field(default=5000.0, metadata=real(0.0, 1e7, unit="N/m"))
    #: probe-drogue coupling: damping [N s/m]
    damping_n_s_m: float = field(default=500.0, metadata=real(0.0, 1e6, lo_open=False, unit="N s/m"))

    def _check_consistency(self) -> None:
        if self.min_closure_speed_m_s >= self.max_closure_speed_m_s:
            raise ParameterError(
                f"probe.min_closure_speed_m_s = {self.min_closure_speed_m_s!r}: must be below "
                f"probe.max_closure_speed_m_s = {self.max_closure_speed_m_s!r}")


BOW_WAVE_SHAPES = ("rankine", "source-line")


@dataclass(frozen=True)
class BowWave(Section):
    """The receiver's forebody flow moving with the probe tip (docs/engagement.md, "Bow wave";
    the field of :mod:`hosedrogue.environment.bow_wave`), added to the air at every hose drag point
    and at the drogue."""

    _section = "bow_wave"
    #: False: no bow wave (the default)
    enabled: bool = field(default=False, metadata=flag())
    #: fuselage radius R far aft of the nose [m]; source flux pi R^2 V
    forebody_radius_m: float = field(default=0.75, metadata=real(0.0, 5.0, unit="m"))
    #: probe tip relative to the nose (forward, right, down) [m]
    probe_offset_m: tuple = field(default=(2.5, 0.0, 0.0),
                                  metadata=vec3(-20.0, 20.0, unit="m", labels=("forward", "right", "down")))
    #: "rankine": point source (Rankine half-body); "source-line": uniform line source of nose_length_m
    shape: str = field(default="rankine", metadata=choice(*BOW_WAVE_SHAPES))
    #: length of the source line [m] (shape "source-line")
    nose_length_m: float = field(default=2.0, metadata=real(0.0, 50.0, unit="m"))


@dataclass(frozen=True)
class Pilot(Section):
    """The receiver's pilot flying the probe's lateral and vertical position toward the drogue
    seen one reaction time ago, through a lag, with bounded speed and acceleration; the axial
    closure stays the prescribed one (docs/engagement.md, "Pilot model": equations, defaults and
    their reasons)."""

    _section = "pilot"
    #: False: the probe flies the prescribed straight line (the default)
    enabled: bool = field(default=False, metadata=flag())
    #: reaction time tau [s]: the pilot sees the drogue's position this long ago (exact delay)
    reaction_time_s: float = field(default=0.3, metadata=real(0.0, 2.0, unit="s"))
    #: lag T_L [s]: commanded speed (aim - p) / T_L, the crossover model's 1 / omega_c
    lag_s: float = field(default=0.5, metadata=real(0.0, 10.0, unit="s"))
    #: time constant tau_v [s] of the receiver's speed following the command (small next to the lag)
    velocity_time_constant_s: float = field(default=0.1, metadata=real(0.0, 10.0, unit="s"))
    #: bound on the lateral and vertical speed [m/s] (each axis)
    max_speed_m_s: float = field(default=1.0, metadata=real(0.0, 20.0, unit="m/s"))
    #: bound on the lateral and vertical acceleration [m/s^2] (each axis)
    max_acceleration_m_s2: float = field(default=2.0, metadata=real(0.0, 50.0, unit="m/s^2"))


#: The engagement's sections by table name.
ENGAGEMENT_SECTIONS = {"reel": Reel, "probe": Probe, "bow_wave": BowWave, "pilot": Pilot, "receiver": Receiver}
#: The control loop's sections by table name (besides ``[controller]``).
LOOP_SECTIONS = {"actuator": Actuator, "sensor": Sensor, "drogue_actuator": DrogueActuator}


@dataclass(frozen=True)
class Loop:
    """The drogue's control loop: the controller, the actuator that applies its force, the sensor
    that measures the drogue (``[controller]``, ``[actuator]``, ``[sensor]``), a drogue's surfaces."""

    controller: Controller = field(default_factory=Controller)  #: the controller's type and design options
    actuator: Actuator = field(default_factory=Actuator)  #: force and rate limits
    sensor: Sensor = field(default_factory=Sensor)  #: measurement noise
    drogue_actuator: DrogueActuator | None = None  #: the drogue's control surfaces (None: the ideal force)

    def to_dict(self) -> dict[str, Any]:
        """``{"controller": ..., "actuator": ..., "sensor": ...}`` tables (TOML/JSON-ready), and the surfaces'.

        Returns
        -------
        dict
        """
        surfaces = {} if self.drogue_actuator is None else {"drogue_actuator": self.drogue_actuator.to_dict()}
        return {"controller": self.controller.to_dict(), "actuator": self.actuator.to_dict(),
                "sensor": self.sensor.to_dict(), **surfaces}


@dataclass(frozen=True)
class Engagement:
    """The refuelling engagement: the hose drum unit and, optionally, the receiver's probe, its
    forebody's bow wave and the pilot or the user's docking controller flying it (``[reel]``,
    ``[probe]``, ``[bow_wave]``, ``[pilot]``, ``[receiver]``). A scenario with an engagement runs the hose of varying length
    (docs/engagement.md); without one, the fixed-length hose."""

    reel: Reel = field(default_factory=Reel)  #: the hose drum unit
    probe: Probe | None = None  #: the receiver's probe (None: no probe)
    bow_wave: BowWave | None = None  #: the receiver's forebody flow (None: none)
    pilot: Pilot | None = None  #: the pilot flying the probe (None: the prescribed path)
    #: the user's docking controller flying the probe (None: the prescribed path or the pilot)
    receiver: Receiver | None = None

    def __post_init__(self) -> None:
        probing = self.probe is not None and self.probe.enabled
        for name in ("pilot", "bow_wave"):
            section = getattr(self, name)
            if section is not None and section.enabled and not probing:
                what = "the pilot flies the probe" if name == "pilot" else "the bow wave moves with the probe tip"
                raise ParameterError(f"{name}.enabled = True: {what}; give an enabled [probe] section")
        if self.receiver is not None:
            if not probing:
                raise ParameterError(f"receiver.entry = {entry_name(self.receiver.entry)!r}: the receiver flies the "
                                     "probe; give an enabled [probe] section")
            if self.pilot is not None and self.pilot.enabled:
                raise ParameterError("receiver: the pilot model and the docking controller would both fly the probe; "
                                     "remove [receiver] or set pilot.enabled = false")

    def to_dict(self) -> dict[str, Any]:
        """The sections present as ``{name: {field: value}}`` (TOML/JSON-ready).

        Returns
        -------
        dict
        """
        return {name: getattr(self, name).to_dict() for name in ENGAGEMENT_SECTIONS
                if getattr(self, name) is not None}
