"""ICAO standard atmosphere (ICAO Doc 7488/3), 0-20 km geopotential altitude.

Altitudes are treated as geopotential; the difference from geometric altitude is below 0.2 %
up to 15 km, far inside the uncertainty of the hose's drag coefficients.
"""

from __future__ import annotations

import math

from ..constants import (
    G0,
    H_MAX_ATMOSPHERE,
    H_TROPOPAUSE,
    LAPSE_TROPOSPHERE,
    P0_SEA_LEVEL,
    R_AIR,
    T0_SEA_LEVEL,
)
from ..spec.params import ParameterError


def temperature_pressure(altitude_m: float) -> tuple[float, float]:
    """Static temperature [K] and pressure [Pa] at ``altitude_m`` [m].

    Parameters
    ----------
    altitude_m : float
        Geopotential altitude [m], within the table of the ICAO standard atmosphere.

    Returns
    -------
    temperature_k, pressure_pa : float
    """
    h = float(altitude_m)
    if not (math.isfinite(h) and 0.0 <= h <= H_MAX_ATMOSPHERE):
        raise ParameterError(
            f"flight.altitude_m = {altitude_m!r}: must be in [0, {H_MAX_ATMOSPHERE:g}] m "
            "(ICAO standard atmosphere, troposphere and lower stratosphere)"
        )
    t_trop = T0_SEA_LEVEL + LAPSE_TROPOSPHERE * H_TROPOPAUSE
    if h <= H_TROPOPAUSE:
        t = T0_SEA_LEVEL + LAPSE_TROPOSPHERE * h
        p = P0_SEA_LEVEL * (t / T0_SEA_LEVEL) ** (-G0 / (LAPSE_TROPOSPHERE * R_AIR))
        return t, p
    p_trop = P0_SEA_LEVEL * (t_trop / T0_SEA_LEVEL) ** (-G0 / (LAPSE_TROPOSPHERE * R_AIR))
    return t_trop, p_trop * math.exp(-G0 * (h - H_TROPOPAUSE) / (R_AIR * t_trop))


def density(altitude_m: float) -> float:
    """Air density [kg/m^3] at ``altitude_m`` [m] (ICAO standard atmosphere).

    Parameters
    ----------
    altitude_m : float
        Geopotential altitude [m].

    Returns
    -------
    float
        Density [kg/m^3].
    """
    t, p = temperature_pressure(altitude_m)
    return p / (R_AIR * t)
