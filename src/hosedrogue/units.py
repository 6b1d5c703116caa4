"""SI units of the project's names, read from their suffixes (docs/develop.md, "Units").

Every parameter, column and interface variable carries its unit at the end of its name:
``drogue_vy_m_s`` is in m/s, ``tow_tension_n`` in N, ``theta_1_2_rad_s`` in rad/s. This module is
the one table from those suffixes to units, each unit with its SI base-unit exponents (as FMI 2.0
``<UnitDefinitions>`` write them). The MATLAB files' ``signal_units`` and the FMUs' units both come
from :func:`unit_of`.

The suffix decides: ``_n_m`` is N.m (a torque, e.g. ``motor_torque_n_m``); a name that uses a
suffix for something else (a stiffness in N/m named ``..._n_m``) gets the table's unit, so signal
and interface names keep to the table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: The value :func:`unit_of` returns for a name without a unit suffix (dimensionless).
NO_UNIT = "1"


@dataclass(frozen=True)
class Unit:
    """A unit as SI base-unit exponents: value in base units = ``factor`` x value in this unit.

    Exponents follow FMI 2.0's ``<BaseUnit>`` (kg, m, s, and rad kept as its own base unit).
    """

    name: str  #: symbol, FMI/Modelica style: ``"m/s"``, ``"N.m"``, ``"m/s2"``
    kg: int = 0  #: exponent of kilogram
    m: int = 0  #: exponent of metre
    s: int = 0  #: exponent of second
    rad: int = 0  #: exponent of radian
    factor: float = 1.0  #: base-unit value of one of this unit (deg: pi/180) [-]

    def base_unit(self) -> dict[str, str]:
        """The attributes of this unit's FMI 2.0 ``<BaseUnit>`` element (non-zero exponents only).

        Returns
        -------
        dict of str to str
            E.g. ``{"kg": "1", "m": "1", "s": "-2"}`` for N; ``factor`` only when it is not 1.
        """
        attrs = {k: str(v) for k, v in (("kg", self.kg), ("m", self.m), ("s", self.s), ("rad", self.rad)) if v}
        if self.factor != 1.0:
            attrs["factor"] = repr(self.factor)
        return attrs


#: The units the package's names use, by symbol.
UNITS: dict[str, Unit] = {u.name: u for u in (
    Unit("m", m=1),
    Unit("m/s", m=1, s=-1),
    Unit("m/s2", m=1, s=-2),
    Unit("s", s=1),
    Unit("Hz", s=-1),
    Unit("kg", kg=1),
    Unit("kg/m", kg=1, m=-1),
    Unit("kg.m2", kg=1, m=2),
    Unit("N", kg=1, m=1, s=-2),
    Unit("N.m", kg=1, m=2, s=-2),
    Unit("N.s/m", kg=1, s=-1),
    Unit("Pa", kg=1, m=-1, s=-2),
    Unit("J", kg=1, m=2, s=-2),
    Unit("W", kg=1, m=2, s=-3),
    Unit("rad", rad=1),
    Unit("rad/s", rad=1, s=-1),
    Unit("deg", rad=1, factor=math.pi / 180.0),
    Unit("deg/s", rad=1, s=-1, factor=math.pi / 180.0),
)}

#: Name suffix -> unit symbol (matched longest suffix first, so ``_m_s`` wins over ``_s``).
SUFFIX_UNITS: dict[str, str] = {
    "_m": "m",
    "_m_s": "m/s",
    "_m_s2": "m/s2",
    "_s": "s",
    "_hz": "Hz",
    "_kg": "kg",
    "_kg_m": "kg/m",
    "_kg_m2": "kg.m2",
    "_n": "N",
    "_n_m": "N.m",
    "_n_s_m": "N.s/m",
    "_pa": "Pa",
    "_j": "J",
    "_w": "W",
    "_rad": "rad",
    "_rad_s": "rad/s",
    "_deg": "deg",
    "_deg_s": "deg/s",
}

_BY_LENGTH = sorted(SUFFIX_UNITS.items(), key=lambda item: -len(item[0]))


def unit_of(name: str) -> str:
    """The SI unit of a signal or variable from its name's suffix (``"1"`` when it has none).

    Parameters
    ----------
    name : str
        Name such as ``drogue_vy_m_s`` or ``tow_tension_n``.

    Returns
    -------
    str
        Unit symbol, a key of :data:`UNITS` (e.g. ``"m/s"``), or :data:`NO_UNIT`.
    """
    for suffix, unit in _BY_LENGTH:
        if name.endswith(suffix):
            return unit
    return NO_UNIT

