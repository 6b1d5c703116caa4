"""Physical constants, each defined once, with its source.

SI units throughout.
"""

#: Standard acceleration of gravity [m/s^2] (ISO 80000-3; ICAO Doc 7488 standard atmosphere).
G0 = 9.80665

#: Specific gas constant of dry air [J/(kg K)] (ICAO Doc 7488/3, 1993).
R_AIR = 287.05287

#: Sea-level standard temperature [K] (ICAO Doc 7488/3).
T0_SEA_LEVEL = 288.15

#: Sea-level standard pressure [Pa] (ICAO Doc 7488/3).
P0_SEA_LEVEL = 101325.0

#: Temperature lapse rate of the troposphere, 0-11 km geopotential [K/m] (ICAO Doc 7488/3).
LAPSE_TROPOSPHERE = -0.0065

#: Geopotential altitude of the tropopause [m] (ICAO Doc 7488/3).
H_TROPOPAUSE = 11000.0

#: Upper limit of the atmosphere model implemented here [m]: the isothermal layer 11-20 km.
H_MAX_ATMOSPHERE = 20000.0

#: Feet to metres (exact, international foot).
FT_TO_M = 0.3048

#: Pound-force to newtons (exact: 0.45359237 kg x 9.80665 m/s^2; NIST SP 811, 2008, B.8).
LBF_TO_N = 4.4482216152605

#: Slug to kilograms: 1 lbf s^2/ft (exact from the foot and the pound-force; NIST SP 811, B.8).
SLUG_TO_KG = LBF_TO_N / FT_TO_M
