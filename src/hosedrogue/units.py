"""SI units of the project's names: the unit is the suffix of every parameter, column and
signal name (``_m`` metres, ``_m_s`` metres per second, ``_n`` newtons, ...), and
:func:`unit_of` reads it back (the MATLAB files and the FMUs label their signals with it)."""

from __future__ import annotations

#: Unit of a name, by its suffix (longest suffixes first, so ``_m_s`` wins over ``_s``).
SUFFIX_UNITS = (("_m_s2", "m/s2"), ("_rad_s", "rad/s"), ("_n_m_s", "N.m.s"), ("_n_s_m", "N.s/m"),
                ("_kg_m2", "kg.m2"), ("_m_s", "m/s"), ("_n_m", "N.m"), ("_n_s", "N.s"), ("_rad", "rad"),
                ("_deg", "deg"), ("_pa", "Pa"), ("_kg", "kg"), ("_hz", "Hz"), ("_j", "J"), ("_m", "m"),
                ("_n", "N"), ("_s", "s"))


def unit_of(name: str) -> str:
    """The SI unit of a name from its suffix (``"1"`` when it has none).

    Parameters
    ----------
    name : str
        A signal, column or parameter name such as ``drogue_vy_m_s``.

    Returns
    -------
    str
        Unit, e.g. ``"m/s"``.
    """
    for suffix, unit in SUFFIX_UNITS:
        if name.endswith(suffix):
            return unit
    return "1"
