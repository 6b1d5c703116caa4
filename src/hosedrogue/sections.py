"""The run's sections besides the model's parameters: the control loop's actuator and sensor, the
drogue's control surfaces, the drogue controller, and the engagement's reel, probe, bow wave and
pilot (scenario tables ``[actuator]``, ``[sensor]``, ``[drogue_actuator]``, ``[controller]``,
``[reel]``, ``[probe]``, ``[bow_wave]``, ``[pilot]``).

Validated at construction like :mod:`hosedrogue.params` (:class:`hosedrogue.fields.Section`): a
wrong field raises a one-line :class:`~hosedrogue.errors.ParameterError` naming field, value and
allowed range. SI units, the unit in every field name. The defaults and their reasons are in
``docs/engagement.md`` (engagement) and ``docs/model.md`` (actuator, sensor, drogue actuator).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

from .errors import ParameterError
from .fields import Section, choice, flag, integer, real, vec3


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
    """White position noise on the measured drogue offset."""

    _section = "sensor"
    #: Standard deviation of the noise per sample [m].
    noise_std_m: float = field(default=0.0, metadata=real(0.0, lo_open=False, unit="m"))
    #: Time each noise sample is held [s].
    sample_time_s: float = field(default=0.01, metadata=real(0.0, unit="s"))


@dataclass(frozen=True)
class DrogueActuator(Section):
    """The drogue's control surfaces: the force they make, their limits and their servos
    (docs/model.md, "Actuated drogue": the model and where each default comes from).

    ``surfaces`` surfaces sit at equal roll intervals around the drogue; surface k deflected by
    delta_k pushes the drogue with ``q S C_F,delta delta_k`` along its own direction in the S_p
    y-z plane, q the dynamic pressure of the local air at the drogue (free stream, wake,
    turbulence, bow wave). A force command is mixed to the surfaces by the minimum-norm inversion
    at the measured q, each deflection command is clipped to the deflection limit and followed
    by the surface's servo, whose rate is clipped to the rate limit. Deflected surfaces add drag
    ``q S k_D sum delta_k^2`` along the relative wind.
    """

    _section = "drogue_actuator"
    #: Number of control surfaces n [-], at roll intervals of 360 / n deg.
    surfaces: int = field(default=4, metadata=integer(3, 8))
    #: Roll position of surface 1 from the S_p y axis (right) toward z (down) [deg]; 0: the "+"
    #: layout (two surfaces per axis), 45: the "x" layout.
    roll_angle_deg: float = field(default=0.0, metadata=real(-180.0, 180.0, lo_open=False, unit="deg"))
    #: Deflection limit |delta_k| of every surface [deg] (the linear force slope holds to about 20 deg).
    max_deflection_deg: float = field(default=20.0, metadata=real(0.0, 90.0, unit="deg"))
    #: Rate limit |d delta_k / dt| of every surface's servo [deg/s].
    max_rate_deg_s: float = field(default=200.0, metadata=real(0.0, 1e5, unit="deg/s"))
    #: Order of the servo from the deflection command to the deflection [-]: 1 (a lag of
    #: bandwidth_hz) or 2 (natural frequency bandwidth_hz, damping ``damping``).
    servo_order: int = field(default=2, metadata=integer(1, 2))
    #: Servo bandwidth [Hz]: the corner frequency 1 / (2 pi tau) of the first-order servo, the
    #: natural frequency omega_n / (2 pi) of the second-order one.
    bandwidth_hz: float = field(default=30.0, metadata=real(0.0, 1000.0, unit="Hz"))
    #: Damping ratio zeta of the second-order servo [-].
    damping: float = field(default=0.7, metadata=real(0.0, 10.0))
    #: Side-force coefficient slope C_F,delta of one surface on the reference area [1/rad].
    force_slope_per_rad: float = field(default=0.45, metadata=real(0.0, 20.0, unit="1/rad"))
    #: Reference area S of the coefficients [m^2]: the paper's basket, pi (0.61 m)^2 / 4.
    reference_area_m2: float = field(default=0.2922, metadata=real(0.0, 10.0, unit="m^2"))
    #: Drag increment k_D of one surface on the reference area [1/rad^2]: Delta C_D = k_D delta_k^2.
    drag_slope_per_rad2: float = field(default=0.25, metadata=real(0.0, 50.0, lo_open=False, unit="1/rad^2"))

    @property
    def roll_angles_rad(self) -> list[float]:
        """Roll position phi_k of each surface [rad] (surface 1 first)."""
        return [math.radians(self.roll_angle_deg) + 2.0 * math.pi * k / self.surfaces for k in range(self.surfaces)]

    #: Largest ``rate x step`` of the servo RK4 may take [-]: the RK4 update of a lag x' = w (u - x)
    #: is a weighted mean of x and the stage inputs u (all weights positive, so the surfaces' limits
    #: hold exactly) for w h <= 1.2956 (the root of a^3 - 2 a^2 + 4 a - 4); with a margin.
    RK4_RATE_STEP = 1.25

    @property
    def max_step_s(self) -> float:
        """The largest RK4 step [s] that resolves the servo: ``RK4_RATE_STEP / w_max``, w_max its
        fastest rate [1/s] (omega for the first order; max(2 zeta omega, omega) for the second,
        2 zeta omega being its rate loop's and its soft stop's)."""
        w = 2.0 * math.pi * self.bandwidth_hz
        fastest = w if self.servo_order == 1 else max(2.0 * self.damping * w, w)
        return self.RK4_RATE_STEP / fastest

    def check_step(self, step_s: float) -> None:
        """Refuse an RK4 step [s] too long for the servo (:attr:`max_step_s`).

        Parameters
        ----------
        step_s : float
            The RK4 step [s] (``numerics.step_s``).

        Raises
        ------
        ParameterError
            One line naming ``numerics.step_s``, the servo and the largest step allowed.
        """
        if step_s > self.max_step_s:
            raise ParameterError(
                f"numerics.step_s = {step_s!r}: the drogue actuator's {self.bandwidth_hz:g} Hz servo needs an RK4 step "
                f"<= {self.max_step_s:.4g} s (its fastest rate x step <= {self.RK4_RATE_STEP:g}, where RK4 keeps the "
                "surfaces within their limits); shorten the step or slow the servo")


#: The drogue controller's types: none, the paper's PID (Eq. 33) or its LQR (Eq. 34).
CONTROLLER_TYPES = ("none", "pid", "lqr")
#: LQR readings: "balanced" (the paper's Q on the balanced states of each 2nd-order channel) or
#: "integral" (Eq. 34 read as integral action); docs/paper-differences.md.
LQR_DESIGNS = ("balanced", "integral")
#: Options each controller type accepts: name -> (length, lower bound, bound is exclusive); the
#: LQR's ``design`` is one of :data:`LQR_DESIGNS`.
CONTROLLER_OPTIONS = {
    "none": {},
    "pid": {"lateral": (4, 0.0, False), "vertical": (4, 0.0, False)},
    "lqr": {"design": None, "q_diag": (4, 0.0, False), "r_diag": (2, 0.0, True)},
}


@dataclass(frozen=True)
class Controller:
    """The drogue controller of a scenario (``[controller]``): its type and design options.

    Options: PID ``lateral``/``vertical`` = [K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s]];
    LQR ``design`` (:data:`LQR_DESIGNS`), ``q_diag`` (4: the balanced states, lateral then
    vertical [1/(m N)]; integral: [P_ny, P_nz, z_ny, z_nz]) and ``r_diag`` (2) [1/N^2]. Missing
    entries take the paper's values.
    """

    #: "none", "pid" or "lqr"
    type: str = "none"
    #: the design options of the type (validated; lists of floats, or the LQR's design name)
    options: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.type not in CONTROLLER_TYPES:
            raise ParameterError(f"controller.type = {self.type!r}: must be one of "
                                 f"{', '.join(map(repr, CONTROLLER_TYPES))}")
        object.__setattr__(self, "options", _controller_options(self.type, dict(self.options)))

    @classmethod
    def from_mapping(cls, data: Any) -> "Controller":
        """The controller of a ``[controller]`` table (``type`` plus the type's options).

        Parameters
        ----------
        data : Mapping
            ``{"type": ..., option: value, ...}``.

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
        return cls(data.pop("type", "none"), data)

    def to_dict(self) -> dict[str, Any]:
        """``{"type": ..., **options}`` (TOML/JSON-ready).

        Returns
        -------
        dict
        """
        return {"type": self.type, **{k: (list(v) if isinstance(v, (list, tuple)) else v)
                                      for k, v in self.options.items()}}


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


REEL_LAWS = ("locked", "constant-tension", "response")


@dataclass(frozen=True)
class Reel(Section):
    """Hose drum unit: ``J_r w' = tau_m - r_d T_0 - c_r w`` (docs/engagement.md, "Reel")."""

    _section = "reel"
    #: "locked": fixed length (or the length schedule below); "constant-tension": tau_m = r_d T_set;
    #: "response": constant tension plus a take-up speed loop driven by the slack.
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

    def _check_consistency(self) -> None:
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
ENGAGEMENT_SECTIONS = {"reel": Reel, "probe": Probe, "bow_wave": BowWave, "pilot": Pilot}
#: The control loop's sections by table name (besides ``[controller]``).
LOOP_SECTIONS = {"actuator": Actuator, "sensor": Sensor, "drogue_actuator": DrogueActuator}


@dataclass(frozen=True)
class Loop:
    """The drogue's control loop: the controller, the actuator that applies its force, the sensor
    that measures the drogue (``[controller]``, ``[actuator]``, ``[sensor]``) and, for a drogue
    that steers itself with control surfaces, those surfaces (``[drogue_actuator]``; then they
    make the force and ``[actuator]`` must keep its defaults)."""

    controller: Controller = field(default_factory=Controller)  #: the controller's type and design options
    actuator: Actuator = field(default_factory=Actuator)  #: force and rate limits
    sensor: Sensor = field(default_factory=Sensor)  #: measurement noise
    drogue_actuator: DrogueActuator | None = None  #: the drogue's control surfaces (None: the ideal force)

    def __post_init__(self) -> None:
        if self.drogue_actuator is not None and self.actuator != Actuator():
            raise ParameterError(f"actuator = {self.actuator.to_dict()!r}: with [drogue_actuator] the control "
                                 "surfaces make the force and limit it; remove the [actuator] limits")

    def to_dict(self) -> dict[str, Any]:
        """``{"controller": ..., "actuator": ..., "sensor": ...}`` tables (TOML/JSON-ready), and
        ``"drogue_actuator"`` when there is one.

        Returns
        -------
        dict
        """
        out = {"controller": self.controller.to_dict(), "actuator": self.actuator.to_dict(),
               "sensor": self.sensor.to_dict()}
        if self.drogue_actuator is not None:
            out["drogue_actuator"] = self.drogue_actuator.to_dict()
        return out


@dataclass(frozen=True)
class Engagement:
    """The refuelling engagement: the hose drum unit and, optionally, the receiver's probe, its
    forebody's bow wave and the pilot flying it (``[reel]``, ``[probe]``, ``[bow_wave]``,
    ``[pilot]``). A scenario with an engagement runs the hose of varying length
    (docs/engagement.md); without one, the fixed-length hose."""

    reel: Reel = field(default_factory=Reel)  #: the hose drum unit
    probe: Probe | None = None  #: the receiver's probe (None: no probe)
    bow_wave: BowWave | None = None  #: the receiver's forebody flow (None: none)
    pilot: Pilot | None = None  #: the pilot flying the probe (None: the prescribed path)

    def __post_init__(self) -> None:
        probing = self.probe is not None and self.probe.enabled
        for name in ("pilot", "bow_wave"):
            section = getattr(self, name)
            if section is not None and section.enabled and not probing:
                what = "the pilot flies the probe" if name == "pilot" else "the bow wave moves with the probe tip"
                raise ParameterError(f"{name}.enabled = True: {what}; give an enabled [probe] section")

    def to_dict(self) -> dict[str, Any]:
        """The sections present as ``{name: {field: value}}`` (TOML/JSON-ready).

        Returns
        -------
        dict
        """
        return {name: getattr(self, name).to_dict() for name in ENGAGEMENT_SECTIONS
                if getattr(self, name) is not None}
