"""The engine of a receiver model: throttle gearing, power lag and thrust.

After the F-16 engine of Stevens, Lewis & Johnson (2015, Appendix A.7, functions TGEAR, PDOT, RTAU
and THRUST), with its numbers in the model file (:class:`~hosedrogue.aircraft.model_file.Engine`).
The power level P is in percent: 0 idle, 50 military, 100 maximum afterburner.
"""

from __future__ import annotations

from .model_file import Engine


def commanded_power(engine: Engine, throttle: float) -> float:
    """The power level [%] the throttle commands (TGEAR): piecewise linear in the throttle.

    Parameters
    ----------
    engine : Engine
        The engine.
    throttle : float
        Throttle [-], 0 to 1 (held to it).

    Returns
    -------
    float
    """
    th = min(max(float(throttle), 0.0), 1.0)
    for lo, hi, slope, offset in engine.gearing:
        if th <= hi:
            return slope * th + offset
    return slope * th + offset  # pragma: no cover - the last piece ends at 1


def _rate(engine: Engine, difference: float) -> float:
    """RTAU: the lag's rate [1/s] for a power difference [%], linear between the two points."""
    (d0, r0), (d1, r1) = engine.rate_points
    if difference <= d0:
        return r0
    if difference >= d1:
        return r1
    return r0 + (r1 - r0) * (difference - d0) / (d1 - d0)


def power_rate(engine: Engine, power: float, command: float) -> float:
    """d(power)/dt [%/s] (PDOT): a first-order lag towards the command, faster in afterburner.

    Parameters
    ----------
    engine : Engine
        The engine.
    power : float
        Power level now [%].
    command : float
        Commanded power level [%] (:func:`commanded_power`).

    Returns
    -------
    float
    """
    ab = engine.afterburner_threshold
    if command >= ab:
        if power >= ab:
            return engine.afterburner_rate * (command - power)
        target = engine.afterburner_entry
        return _rate(engine, target - power) * (target - power)
    if power >= ab:
        return engine.afterburner_rate * (engine.afterburner_exit - power)
    return _rate(engine, command - power) * (command - power)


def thrust_n(engine: Engine, power: float, altitude_m: float, mach: float) -> float:
    """Thrust [N] at power level ``power`` [%], altitude and Mach number (THRUST).

    Parameters
    ----------
    engine : Engine
        The engine.
    power : float
        Power level [%].
    altitude_m : float
        Altitude [m].
    mach : float
        Mach number [-].

    Returns
    -------
    float
    """
    at = {"mach": mach, "altitude": altitude_m}
    mil = engine.military(at)
    ab = engine.afterburner_threshold
    if power < ab:
        idle = engine.idle(at)
        return idle + (mil - idle) * power / ab
    return mil + (engine.maximum(at) - mil) * (power - ab) / (100.0 - ab)
