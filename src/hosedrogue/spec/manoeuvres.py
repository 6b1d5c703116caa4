"""The tanker's manoeuvres: coordinated turns, climbs and descents, speed changes (scenario table
``[tanker_motion]`` with its ``[[tanker_motion.segments]]``; docs/model.md §9).

The tanker starts in steady flight - wings level, or a steady coordinated turn at
``bank_deg``, level or climbing at ``flight_path_deg``, at ``flight.airspeed_m_s`` - and each
segment, from its ``start_s``, flies to the bank angle, flight-path angle and airspeed it names
(what it leaves out keeps its value) at the rates it gives. Every change is smooth: its rate
builds up and dies away along half-sine pulses of the tanker's roll acceleration, pitch
acceleration or jerk (the fields of ``[tanker_motion]``), so the frame's angular acceleration
and the tow point's acceleration are continuous and the fixed-step integrators keep their order
(the same profile as the locked reel's length schedule). A segment must end before the next
one starts.

Conventions (docs/model.md §9): bank phi > 0 is right wing down, turning right, at the turn rate
``g tan(phi) / V`` about the inertial vertical in a level turn; flight-path angle gamma > 0
climbs; the tow point flies at the true airspeed V.

:meth:`TankerMotion.ramps` turns the segments into :class:`Ramp` s (one quantity's change
each) for the compiled core (:mod:`hosedrogue.model.frame`), checking the timeline against the
initial airspeed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import ParameterError
from .fields import Section, real, records

#: Largest bank angle [deg]: a 2 g coordinated turn, beyond any refuelling track (25-30 deg).
MAX_BANK_DEG = 60.0
#: Largest flight-path angle [deg], climbing or descending.
MAX_FLIGHT_PATH_DEG = 30.0
#: The quantities a ramp changes (:class:`Ramp`): bank angle [rad], flight-path angle [rad],
#: airspeed [m/s].
BANK, FLIGHT_PATH, AIRSPEED = 0, 1, 2
QUANTITY_NAMES = ("bank_deg", "flight_path_deg", "airspeed_m_s")


@dataclass(frozen=True)
class Manoeuvre(Section):
    """One segment of the tanker's motion: from ``start_s`` it flies to the bank angle, the
    flight-path angle and the airspeed it names, each at its rate; a target left out is unchanged."""

    _section = "tanker_motion.segments"
    #: Time the segment starts [s].
    start_s: float = field(default=0.0, metadata=real(0.0, lo_open=False, unit="s"))
    #: Bank angle to roll to [deg] (> 0 right wing down, a coordinated turn to the right; 0:
    #: wings level, straight flight); left out: unchanged.
    bank_deg: float | None = field(default=None, metadata=real(-MAX_BANK_DEG, MAX_BANK_DEG, lo_open=False,
                                                                unit="deg", optional=True))
    #: Roll rate of the change of bank [deg/s] (reached after a ramp of the roll acceleration).
    roll_rate_deg_s: float = field(default=5.0, metadata=real(0.0, 30.0, unit="deg/s"))
    #: Flight-path angle to fly to [deg] (> 0 climbing, < 0 descending); left out: unchanged.
    flight_path_deg: float | None = field(default=None, metadata=real(
        -MAX_FLIGHT_PATH_DEG, MAX_FLIGHT_PATH_DEG, lo_open=False, unit="deg", optional=True))
    #: Rate of change of the flight-path angle [deg/s] (the pitch rate of a pull-up or push-over).
    pitch_rate_deg_s: float = field(default=0.5, metadata=real(0.0, 10.0, unit="deg/s"))
    #: True airspeed to fly to [m/s]; left out: unchanged.
    airspeed_m_s: float | None = field(default=None, metadata=real(0.0, 400.0, unit="m/s", optional=True))
    #: Acceleration (or deceleration) of the speed change [m/s^2].
    acceleration_m_s2: float = field(default=1.0, metadata=real(0.0, 20.0, unit="m/s^2"))

    def _check_consistency(self) -> None:
        if self.bank_deg is None and self.flight_path_deg is None and self.airspeed_m_s is None:
            raise ParameterError(f"{self._section}: names none of bank_deg, flight_path_deg, airspeed_m_s; "
                                 "a segment must change at least one of them")

    def targets(self) -> tuple:
        """The targets in the units of the compiled core: bank [rad], flight path [rad], airspeed
        [m/s] (None where unchanged)."""
        rad = (lambda v: None if v is None else math.radians(v))
        return rad(self.bank_deg), rad(self.flight_path_deg), self.airspeed_m_s


@dataclass(frozen=True)
class Ramp:
    """One quantity's smooth change.

    From ``start_s`` its rate follows a half-sine ramp of ``ramp_s`` up to ``rate`` (signed), holds
    it for ``cruise_s`` and ramps down again, changing the quantity by
    ``delta = rate (ramp_s + cruise_s)``.

    Parameters
    ----------
    quantity : int
        :data:`BANK`, :data:`FLIGHT_PATH` or :data:`AIRSPEED`.
    start_s : float
        Start of the change [s].
    delta : float
        The change [rad, or m/s for the airspeed].
    rate : float
        The rate held between the ramps, signed [rad/s, or m/s^2].
    ramp_s : float
        Length of each of the two half-sine ramps of the rate [s].
    cruise_s : float
        Time at the full rate between them [s].
    """

    quantity: int
    start_s: float
    delta: float
    rate: float
    ramp_s: float
    cruise_s: float

    @property
    def end_s(self) -> float:
        """When the change is complete [s]."""
        return self.start_s + 2.0 * self.ramp_s + self.cruise_s


def ramp(quantity: int, start_s: float, delta: float, rate: float, acceleration: float) -> Ramp | None:
    """The smooth change of a quantity by ``delta`` at up to ``rate`` whose rate changes along
    half-sine pulses of peak ``acceleration`` (None for no change).

    When the change is too small to reach ``rate`` (``pi rate^2 / (2 acceleration) > |delta|``)
    the rate peaks lower, at ``sqrt(2 acceleration |delta| / pi)``, with no cruise.

    Parameters
    ----------
    quantity : int
        :data:`BANK`, :data:`FLIGHT_PATH` or :data:`AIRSPEED`.
    start_s : float
        Start [s].
    delta : float
        Change [rad or m/s].
    rate : float
        Largest rate, > 0 [rad/s or m/s^2].
    acceleration : float
        Peak rate of change of the rate, > 0 [rad/s^2 or m/s^3].

    Returns
    -------
    Ramp or None
    """
    d = abs(delta)
    if d == 0.0:
        return None
    vmax = rate
    if math.pi * vmax * vmax / (2.0 * acceleration) > d:
        vmax = math.sqrt(2.0 * acceleration * d / math.pi)
    ta = math.pi * vmax / (2.0 * acceleration)
    tc = max(d / vmax - ta, 0.0)
    return Ramp(quantity, start_s, delta, math.copysign(vmax, delta), ta, tc)


@dataclass(frozen=True)
class TankerMotion(Section):
    """The tanker's flight: the steady condition at the start and the segments that change it
    (docs/model.md §9). The default, no table, is straight and level flight at constant speed."""

    _section = "tanker_motion"
    #: Bank angle at the start [deg]: a steady coordinated turn at the turn rate g tan(phi) / V
    #: (> 0 right wing down, turning right).
    bank_deg: float = field(default=0.0, metadata=real(-MAX_BANK_DEG, MAX_BANK_DEG, lo_open=False, unit="deg"))
    #: Flight-path angle at the start [deg] (> 0 climbing, < 0 descending).
    flight_path_deg: float = field(default=0.0, metadata=real(-MAX_FLIGHT_PATH_DEG, MAX_FLIGHT_PATH_DEG,
                                                               lo_open=False, unit="deg"))
    #: Peak roll acceleration [deg/s^2] of the ramps in and out of a segment's roll rate.
    roll_acceleration_deg_s2: float = field(default=10.0, metadata=real(0.0, 1000.0, unit="deg/s^2"))
    #: Peak pitch acceleration [deg/s^2] of the ramps in and out of a segment's pitch rate.
    pitch_acceleration_deg_s2: float = field(default=1.0, metadata=real(0.0, 100.0, unit="deg/s^2"))
    #: Peak jerk [m/s^3] of the ramps in and out of a segment's acceleration.
    jerk_m_s3: float = field(default=2.0, metadata=real(0.0, 1000.0, unit="m/s^3"))
    #: The segments, in time order, each ending before the next starts (``[[tanker_motion.segments]]``).
    segments: tuple = field(default=(), metadata=records(Manoeuvre))

    def _check_consistency(self) -> None:
        for i in range(1, len(self.segments)):
            a, b = self.segments[i - 1], self.segments[i]
            if b.start_s < a.start_s:
                raise ParameterError(f"tanker_motion.segments[{i}].start_s = {b.start_s!r}: before "
                                     f"segments[{i - 1}].start_s = {a.start_s!r}; list the segments in time order")

    @property
    def is_level(self) -> bool:
        """Straight and level flight at constant speed throughout (no table)."""
        return self.bank_deg == 0.0 and self.flight_path_deg == 0.0 and not self.segments

    @property
    def is_steady(self) -> bool:
        """No segments: the initial steady flight throughout (a turn, a climb, or level)."""
        return not self.segments

    def initial(self, airspeed_m_s: float) -> tuple[float, float, float]:
        """The steady flight at the start: bank [rad], flight path [rad], airspeed [m/s].

        Parameters
        ----------
        airspeed_m_s : float
            ``flight.airspeed_m_s`` [m/s].

        Returns
        -------
        tuple of float
        """
        return math.radians(self.bank_deg), math.radians(self.flight_path_deg), float(airspeed_m_s)

    def ramps(self, airspeed_m_s: float) -> tuple[Ramp, ...]:
        """The segments as ramps of the three quantities, checked against each other.

        Parameters
        ----------
        airspeed_m_s : float
            The airspeed at the start, ``flight.airspeed_m_s`` [m/s].

        Returns
        -------
        tuple of Ramp
            In time order.

        Raises
        ------
        ParameterError
            A segment starts before the previous one's changes are complete.
        """
        value = list(self.initial(airspeed_m_s))
        rates = (math.radians(self.roll_acceleration_deg_s2), math.radians(self.pitch_acceleration_deg_s2),
                 self.jerk_m_s3)
        out: list[Ramp] = []
        end, end_of = -math.inf, None
        for i, seg in enumerate(self.segments):
            if seg.start_s < end:
                raise ParameterError(
                    f"tanker_motion.segments[{i}].start_s = {seg.start_s!r}: starts before segments[{end_of}] "
                    f"ends at {end:.6g} s (its changes at the rates given); segments must not overlap")
            speeds = (math.radians(seg.roll_rate_deg_s), math.radians(seg.pitch_rate_deg_s), seg.acceleration_m_s2)
            seg_end = seg.start_s
            for q, target in enumerate(seg.targets()):
                if target is None:
                    continue
                r = ramp(q, seg.start_s, target - value[q], speeds[q], rates[q])
                value[q] = target
                if r is not None:
                    out.append(r)
                    seg_end = max(seg_end, r.end_s)
            end, end_of = seg_end, i
        return tuple(out)

    def final(self, airspeed_m_s: float) -> tuple[float, float, float]:
        """The steady flight after the last segment: bank [rad], flight path [rad], airspeed [m/s].

        Parameters
        ----------
        airspeed_m_s : float
            The airspeed at the start [m/s].

        Returns
        -------
        tuple of float
        """
        value = list(self.initial(airspeed_m_s))
        for r in self.ramps(airspeed_m_s):
            value[r.quantity] += r.delta
        return tuple(value)

    def end_s(self, airspeed_m_s: float) -> float:
        """When the last segment's changes are complete [s] (0 without segments).

        Parameters
        ----------
        airspeed_m_s : float
            The airspeed at the start [m/s].

        Returns
        -------
        float
        """
        return max((r.end_s for r in self.ramps(airspeed_m_s)), default=0.0)


def steady_motion(bank_deg: float = 0.0, flight_path_deg: float = 0.0) -> TankerMotion:
    """A steady coordinated turn and/or climb (no segments), validated.

    Parameters
    ----------
    bank_deg : float
        Bank angle [deg], > 0 turning right.
    flight_path_deg : float
        Flight-path angle [deg], > 0 climbing.

    Returns
    -------
    TankerMotion
    """
    return TankerMotion(bank_deg=bank_deg, flight_path_deg=flight_path_deg)
