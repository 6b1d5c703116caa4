"""Tabulated data of published standards, below every other layer so that parameter loading
and the environment models read the same table.

Standard turbulence intensities: MIL-F-8785C (1980) Fig. 7 / MIL-HDBK-1797 (1997), "probability
of exceedance of high-altitude intensity", as digitized in the lookup table of the MathWorks
Aerospace Blockset "Dryden Wind Turbulence Model" blocks (light = 1e-2, moderate = 1e-3,
severe = 1e-5 probability of exceedance; the same numbers appear in JSBSim's ``FGWinds.cpp``).
Altitudes 500-80 000 ft, intensities in ft/s; the model is isotropic there.
"""

from __future__ import annotations

import math

import numpy as np

from ..constants import FT_TO_M
from ..errors import ParameterError

#: Altitude breakpoints of the high-altitude intensity table [ft].
INTENSITY_ALTITUDE_FT = (500.0, 1750.0, 3750.0, 7500.0, 15000.0, 25000.0, 35000.0, 45000.0,
                         55000.0, 65000.0, 75000.0, 80000.0)
#: Rms intensity [ft/s] per level at those altitudes (MIL-F-8785C Fig. 7, as digitized in the
#: MathWorks Aerospace Blockset Dryden blocks and JSBSim FGWinds).
INTENSITY_FT_S = {
    "light": (6.6, 6.9, 7.4, 6.7, 4.6, 2.7, 0.4, 0.0, 0.0, 0.0, 0.0, 0.0),
    "moderate": (8.6, 9.6, 10.6, 10.1, 8.0, 6.6, 5.0, 4.2, 2.7, 0.0, 0.0, 0.0),
    "severe": (15.6, 17.6, 23.0, 23.6, 22.1, 20.0, 16.0, 15.1, 12.1, 7.9, 6.2, 5.1),
}
#: Probability of exceedance of each level (MathWorks Dryden block documentation).
PROBABILITY_OF_EXCEEDANCE = {"light": 1e-2, "moderate": 1e-3, "severe": 1e-5}


def standard_intensity(level: str, altitude_m: float) -> tuple[float, float, float]:
    """Standard isotropic turbulence intensity at a medium/high altitude.

    Parameters
    ----------
    level : {"light", "moderate", "severe"}
        Probability of exceedance 1e-2, 1e-3 or 1e-5.
    altitude_m : float
        Altitude [m], within the table: 152.4-24 384 m (500-80 000 ft).

    Returns
    -------
    tuple of float
        ``(sigma_u, sigma_v, sigma_w)`` [m/s], all equal; linear interpolation in altitude of
        MIL-F-8785C Fig. 7 (see the module docstring for the source).

    Raises
    ------
    ParameterError
        For an unknown level or an altitude outside the table. (MIL-F-8785C prescribes its
        low-altitude model below 1000 ft; the table's lowest point, 500 ft, is accepted as given.)
    """
    if not isinstance(level, str) or level not in INTENSITY_FT_S:
        raise ParameterError(
            f"turbulence.intensity = {level!r}: must be one of 'light', 'moderate', 'severe'"
        )
    lo_m = INTENSITY_ALTITUDE_FT[0] * FT_TO_M
    hi_m = INTENSITY_ALTITUDE_FT[-1] * FT_TO_M
    h = float(altitude_m)
    if not (math.isfinite(h) and lo_m <= h <= hi_m):
        raise ParameterError(
            f"flight.altitude_m = {altitude_m!r}: standard turbulence intensities are tabulated for "
            f"[{lo_m:g}, {hi_m:g}] m (500-80000 ft, MIL-F-8785C Fig. 7); give turbulence.sigma_m_s instead"
        )
    sigma_ft_s = float(np.interp(h / FT_TO_M, INTENSITY_ALTITUDE_FT, INTENSITY_FT_S[level]))
    sigma = sigma_ft_s * FT_TO_M
    return (sigma, sigma, sigma)
