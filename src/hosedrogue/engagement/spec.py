"""Reel, probe, bow-wave and pilot parameters of the engagement (scenario sections ``[reel]``,
``[probe]``, ``[bow_wave]``, ``[pilot]``).

Validated at construction like :mod:`hosedrogue.params`: a wrong field raises a one-line
:class:`~hosedrogue.errors.ParameterError` naming field, value and allowed range. SI units, the
unit in every field name. Defaults and their reasons are in ``docs/engagement.md``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, Mapping

from ..errors import ParameterError
from ..params import _Section, _bool, _choice, _num, _vec3

REEL_LAWS = ("locked", "constant-tension", "response")


@dataclass(frozen=True)
class Reel(_Section):
    """Hose drum unit: ``J_r w' = tau_m - r_d T_0 - c_r w`` (docs/engagement.md, "Reel")."""

    _section = "reel"
    #: "locked": fixed length (or the length schedule below); "constant-tension": tau_m = r_d T_set;
    #: "response": constant tension plus a take-up speed loop driven by the slack.
    law: str = field(default="constant-tension", metadata=_choice(*REEL_LAWS))
    #: drum radius r_d [m] (hose speed r_d w)
    drum_radius_m: float = field(default=0.3, metadata=_num(0.0, 5.0, unit="m"))
    #: J_r [kg m^2]: drum plus wound hose, constant: 30 m of hose (4.4 kg/m) at 0.35 m (16 kg m^2) plus the drum
    inertia_kg_m2: float = field(default=20.0, metadata=_num(0.0, 1e5, unit="kg m^2"))
    #: c_r [N m s]: viscous friction torque per drum speed
    friction_n_m_s: float = field(default=1.0, metadata=_num(0.0, 1e5, lo_open=False, unit="N m s"))
    #: T_set [N]; < 0 means "the steady trail tension at the balance position" (the default)
    tension_set_n: float = field(default=-1.0, metadata=_num(-1.0, 1e6, lo_open=False, unit="N (-1: steady trail tension)"))
    #: motor torque limit |tau_m| [N m]
    max_torque_n_m: float = field(default=2000.0, metadata=_num(0.0, 1e6, unit="N m"))
    #: take-up (reel-in) and payout speed limits [m/s], held by the governor
    max_takeup_speed_m_s: float = field(default=3.0, metadata=_num(0.0, 50.0, unit="m/s"))
    #: payout speed limit [m/s]
    max_payout_speed_m_s: float = field(default=3.0, metadata=_num(0.0, 50.0, unit="m/s"))
    #: stiffness of the speed governor beyond the speed limits [N s/m]
    governor_gain_n_s_m: float = field(default=20000.0, metadata=_num(0.0, 1e8, unit="N s/m"))
    #: response law: commanded take-up speed per metre of slack beyond the dead band [1/s]
    takeup_gain_1_s: float = field(default=4.0, metadata=_num(0.0, 1e3, lo_open=False, unit="1/s"))
    #: response law: slack [m] below which no take-up speed is commanded
    slack_dead_band_m: float = field(default=0.02, metadata=_num(0.0, 100.0, lo_open=False, unit="m"))
    #: response law: speed-loop gain (force at the drum rim per m/s of speed error) [N s/m]
    speed_gain_n_s_m: float = field(default=3000.0, metadata=_num(0.0, 1e8, lo_open=False, unit="N s/m"))
    #: locked law: length change of a payout schedule [m] (negative: take up), 0 for a fixed length;
    #: speed up to payout_speed_m_s along a half-sine acceleration pulse of peak payout_acceleration_m_s2
    payout_m: float = field(default=0.0, metadata=_num(-1000.0, 1000.0, lo_open=False, unit="m"))
    #: payout schedule: cruise speed [m/s]
    payout_speed_m_s: float = field(default=1.0, metadata=_num(0.0, 50.0, unit="m/s"))
    #: payout schedule: peak acceleration [m/s^2]
    payout_acceleration_m_s2: float = field(default=2.0, metadata=_num(0.0, 1000.0, unit="m/s^2"))
    #: payout schedule: start time [s]
    payout_start_s: float = field(default=0.0, metadata=_num(0.0, 1e6, lo_open=False, unit="s"))
    #: the drum's end stops: the free hose length [m] fully reeled in (the drogue at the hose
    #: exit) and fully paid out (30 m, the hose the drum inertia above counts); a run whose free
    #: length leaves [min_length_m, max_length_m] stops there, marked incomplete
    min_length_m: float = field(default=1.0, metadata=_num(0.0, 1000.0, unit="m"))
    #: fully paid out [m]
    max_length_m: float = field(default=30.0, metadata=_num(0.0, 1000.0, unit="m"))

    def _check_consistency(self) -> None:
        if not self.min_length_m < self.max_length_m:
            raise ParameterError(f"reel.min_length_m = {self.min_length_m!r}: must be below reel.max_length_m = "
                                 f"{self.max_length_m!r} m")
        if self.payout_m != 0.0 and self.law != "locked":
            raise ParameterError(
                f"reel.payout_m = {self.payout_m!r}: a payout schedule needs reel.law = 'locked' (got {self.law!r})")


@dataclass(frozen=True)
class Probe(_Section):
    """Prescribed probe-tip path, capture test and probe-drogue coupling (docs/engagement.md, "Probe", "Capture" and
    "Coupled phase")."""

    _section = "probe"
    #: False: no probe (the reel alone)
    enabled: bool = field(default=True, metadata=_bool())
    #: start point: this far aft of the drogue's balance position [m], plus the offsets
    standoff_m: float = field(default=3.0, metadata=_num(0.0, 100.0, unit="m"))
    #: lateral (S_p y, right) and vertical (S_p z, down) offsets of the start point [m]
    offset_y_m: float = field(default=0.0, metadata=_num(-10.0, 10.0, lo_open=False, unit="m"))
    #: vertical offset of the start point (S_p z, down) [m]
    offset_z_m: float = field(default=0.0, metadata=_num(-10.0, 10.0, lo_open=False, unit="m"))
    #: speed of the probe forward (S_p x) [m/s]
    closure_speed_m_s: float = field(default=1.5, metadata=_num(0.0, 10.0, unit="m/s"))
    #: after contact the probe goes on this far forward [m], then holds
    push_m: float = field(default=2.0, metadata=_num(0.0, 50.0, lo_open=False, unit="m"))
    #: duration of the half-cosine speed ramp that stops the probe at the end of the push [s]
    stop_time_s: float = field(default=1.0, metadata=_num(0.0, 60.0, unit="s"))
    #: capture test: largest radial miss in the coupler plane [m]
    capture_radius_m: float = field(default=0.305, metadata=_num(0.0, 5.0, unit="m"))
    #: capture test: closure speed window at the coupler plane [m/s] (lower bound)
    min_closure_speed_m_s: float = field(default=0.5, metadata=_num(0.0, 10.0, lo_open=False, unit="m/s"))
    #: capture test: upper bound of the closure speed window [m/s]
    max_closure_speed_m_s: float = field(default=3.0, metadata=_num(0.0, 20.0, unit="m/s"))
    #: probe-drogue coupling once captured: spring stiffness [N/m]
    stiffness_n_m: float = field(default=5000.0, metadata=_num(0.0, 1e7, unit="N/m"))
    #: probe-drogue coupling: damping [N s/m]
    damping_n_s_m: float = field(default=500.0, metadata=_num(0.0, 1e6, lo_open=False, unit="N s/m"))

    def _check_consistency(self) -> None:
        if self.min_closure_speed_m_s >= self.max_closure_speed_m_s:
            raise ParameterError(
                f"probe.min_closure_speed_m_s = {self.min_closure_speed_m_s!r}: must be below "
                f"probe.max_closure_speed_m_s = {self.max_closure_speed_m_s!r}")


BOW_WAVE_SHAPES = ("rankine", "source-line")


@dataclass(frozen=True)
class BowWaveSection(_Section):
    """The receiver's forebody flow moving with the probe tip (docs/engagement.md, "Bow wave";
    the field of :mod:`hosedrogue.environment.bow_wave`), added to the air at every hose drag point
    and at the drogue."""

    _section = "bow_wave"
    #: False: no bow wave (the default)
    enabled: bool = field(default=False, metadata=_bool())
    #: fuselage radius R far aft of the nose [m]; source flux pi R^2 V
    forebody_radius_m: float = field(default=0.75, metadata=_num(0.0, 5.0, unit="m"))
    #: probe tip relative to the nose (forward, right, down) [m]
    probe_offset_m: tuple = field(default=(2.5, 0.0, 0.0), metadata=_vec3(-20.0, 20.0, unit="m"))
    #: "rankine": point source (Rankine half-body); "source-line": uniform line source of nose_length_m
    shape: str = field(default="rankine", metadata=_choice(*BOW_WAVE_SHAPES))
    #: length of the source line [m] (shape "source-line")
    nose_length_m: float = field(default=2.0, metadata=_num(0.0, 50.0, unit="m"))


@dataclass(frozen=True)
class Pilot(_Section):
    """The receiver's pilot flying the probe's lateral and vertical position toward the drogue
    seen one reaction time ago, through a lag, with bounded speed and acceleration; the axial
    closure stays the prescribed one (docs/engagement.md, "Pilot model": equations, defaults and
    their reasons)."""

    _section = "pilot"
    #: False: the probe flies the prescribed straight line (the default)
    enabled: bool = field(default=False, metadata=_bool())
    #: reaction time tau [s]: the pilot sees the drogue's position this long ago (exact delay)
    reaction_time_s: float = field(default=0.3, metadata=_num(0.0, 2.0, unit="s"))
    #: lag T_L [s]: commanded speed (aim - p) / T_L, the crossover model's 1 / omega_c
    lag_s: float = field(default=0.5, metadata=_num(0.0, 10.0, unit="s"))
    #: time constant tau_v [s] of the receiver's speed following the command (small next to the lag)
    velocity_time_constant_s: float = field(default=0.1, metadata=_num(0.0, 10.0, unit="s"))
    #: bound on the lateral and vertical speed [m/s] (each axis)
    max_speed_m_s: float = field(default=1.0, metadata=_num(0.0, 20.0, unit="m/s"))
    #: bound on the lateral and vertical acceleration [m/s^2] (each axis)
    max_acceleration_m_s2: float = field(default=2.0, metadata=_num(0.0, 50.0, unit="m/s^2"))


ENGAGEMENT_SECTIONS = {"reel": Reel, "probe": Probe, "bow_wave": BowWaveSection, "pilot": Pilot}


def section_from_dict(name: str, data: Any):
    """Build ``Reel``, ``Probe`` or ``BowWaveSection`` from a scenario table, rejecting unknown fields.

    Parameters
    ----------
    name : {"reel", "probe", "bow_wave", "pilot"}
        The scenario section.
    data : mapping
        Its fields (SI units, the unit in every field name).

    Returns
    -------
    Reel, Probe, BowWaveSection or Pilot

    Raises
    ------
    ParameterError
        ``data`` not a table, an unknown field, or a value out of range.
    """
    cls = ENGAGEMENT_SECTIONS[name]
    if not isinstance(data, Mapping):
        raise ParameterError(f"{name} = {data!r}: must be a table of fields")
    known = {f.name for f in dataclasses.fields(cls)}
    for key in data:
        if key not in known:
            raise ParameterError(f"{name}.{key}: unknown field; allowed: {', '.join(sorted(known))}")
    return cls(**data)


def validate_sections(data: Mapping[str, Any]) -> dict:
    """The scenario loader's hook: validate ``[reel]``/``[probe]``/``[bow_wave]`` now, return them as objects.

    Parameters
    ----------
    data : mapping
        The scenario's tables; only ``reel``, ``probe``, ``bow_wave`` and ``pilot`` are read.

    Returns
    -------
    dict
        ``{"reel": Reel, "probe": Probe, "bow_wave": BowWaveSection, "pilot": Pilot}`` for the
        sections present.

    Raises
    ------
    ParameterError
        A bad section (:func:`section_from_dict`), or an enabled ``[pilot]`` without an enabled
        ``[probe]``.
    """
    out = {name: section_from_dict(name, data[name]) for name in ENGAGEMENT_SECTIONS if name in data}
    pilot, probe = out.get("pilot"), out.get("probe")
    if pilot is not None and pilot.enabled and (probe is None or not probe.enabled):
        raise ParameterError("pilot.enabled = True: the pilot flies the probe; give an enabled [probe] section")
    return out


def plain(obj) -> dict:
    """The fields of a dataclass (``Reel``, ``Probe``) as a plain dict, for run.json.

    Parameters
    ----------
    obj : dataclass instance
        The section.

    Returns
    -------
    dict
        Field name -> value (SI units, the unit in the name).
    """
    return {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}
