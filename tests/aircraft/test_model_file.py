"""A receiver of one's own through the model file: a toy aircraft in SI, trimmed by the package and
by hand (its level-flight balance solved in closed form with a scalar root finder); and the
one-line errors of a bad file."""

import math

import pytest
from scipy.optimize import brentq

from hosedrogue.aircraft.air import air_data
from hosedrogue.aircraft.model_file import load_model
from hosedrogue.aircraft.trim import trim
from hosedrogue.errors import ParameterError

TOY = """
name = "toy"
description = "linear aerodynamics, a thrust independent of speed and height"
[units]
length = "m"
mass = "kg"
force = "N"
[mass]
mass = 5000.0
jxx = 8000.0
jyy = 20000.0
jzz = 26000.0
jxz = 0.0
engine_angular_momentum = 0.0
[geometry]
wing_area = 20.0
span = 10.0
chord = 2.0
xcg_ref = 0.25
xcg = 0.25
[atmosphere]
model = "icao"
[controls]
elevator = [-20.0, 20.0]
aileron = [-20.0, 20.0]
rudder = [-20.0, 20.0]
[tables.lift_slope]
axes = ["alpha"]
alpha = [-10.0, 30.0]
values = [0.9, -3.1]
[coefficients]
CX = [{ gain = -0.03 }]
CY = [{ gain = -0.01, times = ["beta"] }, { gain = 0.002, times = ["rudder"] }]
CZ = [{ table = "lift_slope" }]
Cl = [{ gain = -0.001, times = ["beta"] }, { gain = -0.002, times = ["aileron"] }, { gain = -0.4, times = ["p_hat"] }]
Cm = [{ gain = 0.02 }, { gain = -0.01, times = ["alpha"] }, { gain = -0.015, times = ["elevator"] },
      { gain = -8.0, times = ["q_hat"] }]
Cn = [{ gain = 0.002, times = ["beta"] }, { gain = -0.001, times = ["rudder"] }, { gain = -0.2, times = ["r_hat"] }]
[engine]
mach = [0.0, 1.0]
altitude = [0.0, 20000.0]
idle = [[0.0, 0.0], [0.0, 0.0]]
military = [[20000.0, 20000.0], [20000.0, 20000.0]]
maximum = [[30000.0, 30000.0], [30000.0, 30000.0]]
gearing = [[0.0, 1.0, 100.0, 0.0]]
afterburner_threshold = 50.0
afterburner_rate = 5.0
afterburner_entry = 60.0
afterburner_exit = 40.0
rate_points = [[25.0, 1.0], [50.0, 0.1]]
"""


@pytest.fixture
def toy(tmp_path):
    path = tmp_path / "toy.toml"
    path.write_text(TOY)
    return path


def test_own_receiver_trims_as_its_closed_form(toy):
    """Level flight: Z balance q S CZ(alpha) + W cos(alpha) = 0 with CZ = -0.1 - 0.1 alpha_deg (the
    table's line), solved by brentq; then elevator from Cm = 0 and thrust W sin(alpha) - q S CX. The
    solver's tolerance (1e-9 m/s^2) bounds the difference: 1e-8 in every unknown."""
    model = load_model(toy)
    assert model.mass_kg == 5000.0 and model.span_m == 10.0  # SI file: no conversion
    v, h, g = 100.0, 1000.0, 9.80665
    rho, _ = air_data("icao", h)
    qs = 0.5 * rho * v * v * 20.0
    weight = 5000.0 * g
    alpha_deg = brentq(lambda a: qs * (-0.1 - 0.1 * a) + weight * math.cos(math.radians(a)), -5.0, 25.0, xtol=1e-14)
    elevator = (0.02 - 0.01 * alpha_deg) / 0.015
    thrust = weight * math.sin(math.radians(alpha_deg)) + 0.03 * qs
    throttle = thrust / 20000.0 * 50.0 / 100.0  # below military: thrust = military * power / 50
    t = trim(model, v, h, gravity=g)
    assert math.degrees(t.alpha_rad) == pytest.approx(alpha_deg, abs=1e-8)
    assert t.controls[1] == pytest.approx(elevator, abs=1e-8)
    assert t.controls[0] == pytest.approx(throttle, abs=1e-8)


@pytest.mark.parametrize("old, new, message", [
    ('length = "m"', 'length = "yard"', "units.length = 'yard': one of ft, m"),
    ("jyy = 20000.0", "jyy = -1.0", "mass.jyy = -1.0: a finite number > 0"),
    ("values = [0.9, -3.1]", "values = [0.9]", "tables.lift_slope.values = 'shape (1,)'"),
    ('CZ = [{ table = "lift_slope" }]', 'CZ = [{ table = "cz" }]', "coefficients.CZ[0].table = 'cz'"),
    ('times = ["beta"] }, { gain = 0.002', 'times = ["mach"] }, { gain = 0.002', "coefficients.CY[0].times"),
    ('model = "icao"', 'model = "isa"', "atmosphere.model = 'isa'"),
    ("gearing = [[0.0, 1.0, 100.0, 0.0]]", "gearing = [[0.0, 0.5, 100.0, 0.0]]", "engine.gearing"),
])
def test_bad_file_is_one_line_naming_the_key(tmp_path, old, new, message):
    assert old in TOY
    path = tmp_path / "bad.toml"
    path.write_text(TOY.replace(old, new, 1))
    with pytest.raises(ParameterError) as exc:
        load_model(path)
    assert message in str(exc.value) and "\n" not in str(exc.value) and str(path) in str(exc.value)


def test_unknown_model_name():
    with pytest.raises(ParameterError, match="--model = 'f17': neither a shipped model"):
        load_model("f17")


def test_breakpoints_must_increase(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(TOY.replace("alpha = [-10.0, 30.0]", "alpha = [30.0, -10.0]", 1))
    with pytest.raises(ParameterError, match="tables.lift_slope.alpha = \\[30.0, -10.0\\]: at least two strictly"):
        load_model(path)
