"""The units of the project's names (hosedrogue.units): the table against SI definitions written
out here, and the suffixes it reads. (The FMUs' units: tests/interop/test_fmu_description.py.)"""

import math
import re

import pytest

from hosedrogue.units import NO_UNIT, UNITS, unit_of

#: SI definitions written out independently of hosedrogue.units: base-unit exponents (kg, m, s, rad)
#: and factor of each symbol the table may use.
SI = {"kg": ({"kg": 1}, 1.0), "m": ({"m": 1}, 1.0), "s": ({"s": 1}, 1.0), "rad": ({"rad": 1}, 1.0),
      "N": ({"kg": 1, "m": 1, "s": -2}, 1.0), "J": ({"kg": 1, "m": 2, "s": -2}, 1.0),
      "W": ({"kg": 1, "m": 2, "s": -3}, 1.0), "Pa": ({"kg": 1, "m": -1, "s": -2}, 1.0),
      "Hz": ({"s": -1}, 1.0), "deg": ({"rad": 1}, math.pi / 180.0)}


def parse_symbol(symbol):
    """Exponents and factor of a compound symbol such as ``N.s/m`` or ``m/s2``."""
    exponents, factor = {}, 1.0
    for sign, part in zip((1, -1), (symbol.split("/") + [""])[:2]):
        for token in filter(None, part.split(".")):
            name, power = re.fullmatch(r"([A-Za-z]+)(\d*)", token).groups()
            base, f = SI[name]
            p = sign * int(power or 1)
            factor *= f ** p
            for k, e in base.items():
                exponents[k] = exponents.get(k, 0) + p * e
    return {k: e for k, e in exponents.items() if e}, factor


def test_units_table_holds_the_si_definitions():
    for symbol, unit in UNITS.items():
        exponents, factor = parse_symbol(symbol)
        assert {k: v for k, v in (("kg", unit.kg), ("m", unit.m), ("s", unit.s), ("rad", unit.rad)) if v} \
            == exponents, symbol
        assert unit.factor == pytest.approx(factor, rel=1e-15), symbol  # deg: pi/180 to double precision


def test_unit_of_reads_the_longest_suffix():
    expected = {"drogue_x_m": "m", "drogue_vy_m_s": "m/s", "gravity_m_s2": "m/s2", "t_s": "s",
                "tow_tension_n": "N", "u_y_n": "N", "motor_torque_n_m": "N.m", "theta_1_2_rad": "rad",
                "theta_1_2_rad_s": "rad/s", "max_yaw_deg": "deg", "pressure_pa": "Pa", "hose_mass_kg": "kg",
                "mass_per_length_kg_m": "kg/m", "energy_jump_j": "J", "links": NO_UNIT, "wake_enabled": NO_UNIT}
    assert {name: unit_of(name) for name in expected} == expected
    from hosedrogue.interop.matlab import unit_of as mat_unit_of

    assert mat_unit_of is unit_of  # the .mat writer's units are the same table


def test_every_suffix_has_a_defined_unit():
    from hosedrogue.units import SUFFIX_UNITS

    assert set(SUFFIX_UNITS.values()) == set(UNITS)  # each unit reached by a suffix, each suffix defined
    assert all(suffix.startswith("_") and unit_of("x" + suffix) == unit for suffix, unit in SUFFIX_UNITS.items())
