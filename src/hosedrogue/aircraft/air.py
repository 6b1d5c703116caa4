"""The air a receiver model flies in: density and speed of sound at an altitude.

Two atmospheres, chosen by the model file's ``[atmosphere] model``:

* ``"icao"``: the package's ICAO standard atmosphere (:mod:`hosedrogue.environment.atmosphere`),
  the air of the hose; 0 to 20 km.
* ``"stevens-lewis"``: the air-data routine ADC of Stevens, Lewis & Johnson (2015, Appendix A.6),
  which the book's F-16 tables and trim tables were computed with: density
  2.377e-3 slug/ft^3 (1 - 0.703e-5 h)^4.14, temperature 519 R (1 - 0.703e-5 h) (390 R from
  35,000 ft), speed of sound sqrt(1.4 x 1716.3 ft^2/(s^2 R) x T); h in feet. Within 0.2 % of the
  ICAO density below 10 km. Held here to 0..20 km, as the ICAO one.
"""

from __future__ import annotations

import math

from ..constants import FT_TO_M, H_MAX_ATMOSPHERE, R_AIR, SLUG_TO_KG
from ..environment.atmosphere import temperature_pressure
from ..errors import ParameterError

#: The book's sea-level density [slug/ft^3] (ADC, R0).
_RHO0_SLUG_FT3 = 2.377e-3

#: Ratio of specific heats of air [-] (the ICAO atmosphere's, and the book's 1.4).
GAMMA_AIR = 1.4


def air_data(atmosphere: str, altitude_m: float) -> tuple[float, float]:
    """Density [kg/m^3] and speed of sound [m/s] at ``altitude_m``.

    Parameters
    ----------
    atmosphere : str
        ``"icao"`` or ``"stevens-lewis"``.
    altitude_m : float
        Altitude [m], 0 to 20,000.

    Returns
    -------
    density_kg_m3, speed_of_sound_m_s : float
    """
    h = float(altitude_m)
    if not (math.isfinite(h) and 0.0 <= h <= H_MAX_ATMOSPHERE):
        raise ParameterError(f"altitude_m = {altitude_m!r}: must be in [0, {H_MAX_ATMOSPHERE:g}] m")
    if atmosphere == "icao":
        t, p = temperature_pressure(h)
        return p / (R_AIR * t), math.sqrt(GAMMA_AIR * R_AIR * t)
    h_ft = h / FT_TO_M
    tfac = 1.0 - 0.703e-5 * h_ft
    t_rankine = 390.0 if h_ft >= 35000.0 else 519.0 * tfac
    rho = _RHO0_SLUG_FT3 * tfac**4.14 * SLUG_TO_KG / FT_TO_M**3
    return rho, math.sqrt(GAMMA_AIR * 1716.3 * t_rankine) * FT_TO_M
