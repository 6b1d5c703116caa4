"""Property-based tests (Hypothesis) of parameter and scenario loading: any mutation of a valid
file - values of the wrong type, out of range, NaN/inf, huge numbers, strings, unknown keys,
missing or extra sections - either loads or fails with a one-line ParameterError that names the
field; no other exception escapes."""

import datetime
import json
import math

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from hosedrogue.errors import ParameterError  # noqa: E402
from hosedrogue.spec.config import load_params  # noqa: E402
from hosedrogue.scenarios import load_scenario  # noqa: E402

#: A valid scenario touching every section and kind of field (choices, vectors, lists, booleans).
VALID = {
    "scenario": {"name": "fuzz", "description": "valid start", "duration_s": 2.0, "initial": "displaced",
                 "initial_pitch_offset_deg": 5.0, "initial_yaw_offset_deg": -3.0},
    "controller": {"type": "pid", "lateral": [1.0, 0.1, 0.5, 20.0]},
    "actuator": {"max_force_n": 2000.0, "max_rate_n_s": 1e4},
    "sensor": {"noise_std_m": 0.01, "sample_time_s": 0.01},
    "tanker": {"mass_kg": 60000.0, "span_m": 34.0},
    "hose": {"length_m": 16.0, "links": 6, "inner_diameter_m": 0.051, "outer_diameter_m": 0.067,
             "bending": "moment", "link_inertia": "rod"},
    "drogue": {"mass_kg": 29.0, "diameter_m": 0.61},
    "flight": {"altitude_m": 8000.0, "airspeed_m_s": 150.0},
    "wake": {"enabled": True, "tow_point_y_over_span": 0.25},
    "turbulence": {"enabled": True, "sigma_m_s": [1.5, 1.0, 1.0], "scale_length_m": 530.0, "start_s": 0.5,
                   "duration_s": 1.0, "distribution": "frozen", "seed": 7},
    "numerics": {"step_s": 0.005, "output_every": 2, "max_yaw_deg": 85.0},
}
PARAM_SECTIONS = ("tanker", "hose", "drogue", "flight", "wake", "turbulence", "numerics")
#: A valid parameter file; its turbulence takes the named intensity at the flight altitude.
VALID_PARAMS = {**{k: VALID[k] for k in PARAM_SECTIONS},
                "turbulence": {"enabled": True, "intensity": "moderate", "scale_length_m": [530.0, 265.0, 265.0]}}

#: Examples per property: a few hundred loads (a few ms each); derandomized, so CI is repeatable.
SETTINGS = settings(max_examples=300, deadline=None, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow])

names = st.text(alphabet="abcdefghijklmnopqrstuvwxyz_", min_size=1, max_size=12)
scalars = st.one_of(
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.integers(min_value=2**63, max_value=10**30),  # beyond 64 bits
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0, -1, 1, 0.0, -0.0, 1e308, -1e308, 5e-324, 1e-300, 2**63, 86401.0]),
    st.booleans(),
    st.text(alphabet=st.characters(blacklist_categories=("Cs", "Cc")), max_size=12),
    st.sampled_from(["", "nan", "inf", "1.5", "pid", "lqr", "none", "equilibrium", "light", "severe"]),
    st.dates(),
)
values = st.one_of(scalars, st.lists(scalars, max_size=5), st.dictionaries(names, scalars, max_size=3))


def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, datetime.date):
        return v.isoformat()
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(v)


def to_toml(data: dict) -> str:
    """TOML text of ``data``: top-level values first, then one [table] per dict (inline tables below)."""
    lines = [f"{json.dumps(k)} = {toml_value(v)}" for k, v in data.items() if not isinstance(v, dict)]
    for k, v in data.items():
        if isinstance(v, dict):
            lines.append(f"[{json.dumps(k)}]")
            lines += [f"{json.dumps(kk)} = {toml_value(vv)}" for kk, vv in v.items()]
    return "\n".join(lines) + "\n"


@st.composite
def mutation(draw, base):
    """(mutated data, names the error may cite): one change to a copy of ``base``.

    An error may name the changed field or another field of its section that the change made
    invalid (dropping ``controller.type`` makes ``controller.lateral`` unknown): ``section.``.
    """
    data = json.loads(json.dumps(base))
    section = draw(st.sampled_from(sorted(data)))
    kind = draw(st.sampled_from(["value", "value", "value", "unknown key", "drop key", "section value",
                                 "drop section", "extra section"]))
    if kind == "value":
        key = draw(st.sampled_from(sorted(data[section])))
        data[section][key] = draw(values)
        return data, {f"{section}."}
    if kind == "unknown key":
        key = draw(names.filter(lambda k: k not in data[section]))
        data[section][key] = draw(values)
        return data, {f"{section}.{key}"}
    if kind == "drop key":
        key = draw(st.sampled_from(sorted(data[section])))
        del data[section][key]
        return data, {f"{section}."}
    if kind == "section value":
        data[section] = draw(scalars)
        return data, {section}
    if kind == "drop section":
        del data[section]
        return data, {section}
    name = draw(names.filter(lambda k: k not in data))
    data[name] = draw(st.one_of(scalars, st.dictionaries(names, scalars, max_size=3)))
    return data, {name}


def check_outcome(load, path, cited):
    """Loading ``path`` either succeeds or raises a one-line ParameterError naming a cited field."""
    try:
        load(str(path))
    except ParameterError as exc:
        message = str(exc)
        assert "\n" not in message and message.strip(), repr(message)
        assert any(name in message for name in cited), f"{message!r} names none of {sorted(cited)}"


@SETTINGS
@given(case=mutation(VALID))
def test_a_mutated_scenario_loads_or_names_the_field(tmp_path_factory, case):
    data, cited = case
    path = tmp_path_factory.mktemp("fuzz", numbered=True) / "scenario.toml"
    path.write_text(to_toml(data), encoding="utf-8")
    check_outcome(load_scenario, path, cited)


@SETTINGS
@given(case=mutation(VALID_PARAMS))
def test_a_mutated_parameter_file_loads_or_names_the_field(tmp_path_factory, case):
    data, cited = case
    path = tmp_path_factory.mktemp("fuzz", numbered=True) / "params.toml"
    path.write_text(to_toml(data), encoding="utf-8")
    check_outcome(load_params, path, cited)


def test_the_valid_starts_load(tmp_path):
    path = tmp_path / "valid.toml"
    path.write_text(to_toml(VALID))
    scenario = load_scenario(str(path))
    assert scenario.params.hose.links == 6 and scenario.controller == "pid"
    path.write_text(to_toml(VALID_PARAMS))
    assert load_params(str(path)).turbulence.sigma_m_s[0] > 0
