"""The actuated-drogue study on the user's own scenario (hosedrogue.studies.drogue_actuator,
``hosedrogue study actuator --scenario/--approach``): the claims cases take the user's model,
flight condition and control surfaces; a scenario of the wrong kind is refused before any run."""

import json

import pytest

from hosedrogue.cli import main
from hosedrogue.scenarios import load_scenario
from hosedrogue.spec.standards import standard_intensity
from hosedrogue.studies.drogue_actuator import VARIANTS, claims_scenario

MINE = """[scenario]
extends = "paper-turbulence"
name = "mine"
duration_s = 10.48
[flight]
airspeed_m_s = 128.0
altitude_m = 6100.0
[drogue_actuator]
max_deflection_deg = 15.0
[numerics]
step_s = 0.0025
output_every = 16
"""


@pytest.fixture
def mine(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(MINE)
    return path


def test_claims_cases_fly_the_users_scenario_and_surfaces(mine):
    base = load_scenario(mine)
    for variant in VARIANTS:
        sc = claims_scenario("moderate", "lqr", variant, base=base)
        assert sc.name == "mine-lqr-moderate"
        assert sc.loop.controller.type == "lqr"
        assert (sc.params.flight.airspeed_m_s, sc.params.flight.altitude_m) == (128.0, 6100.0)
        # moderate turbulence at the user's 6100 m, not at the paper's 8000 m
        assert tuple(sc.params.turbulence.sigma_m_s) == pytest.approx(standard_intensity("moderate", 6100.0))
        surfaces = sc.loop.drogue_actuator
        if variant == "ideal":
            assert surfaces is None
            continue
        # the variants start from the user's 15 deg surfaces, not the defaults' 20 deg
        assert surfaces.max_deflection_deg == (5.0 if variant == "actuated-5deg" else 15.0)
        assert surfaces.bandwidth_hz == (12.0 if variant == "actuated-12hz" else base.loop.drogue_actuator.bandwidth_hz)
        assert sc.params.numerics.step_s <= surfaces.max_step_s
    # level "paper" keeps the scenario's own turbulence
    assert claims_scenario("paper", "pid", base=base).params.turbulence == base.params.turbulence


def test_study_actuator_runs_the_users_file(mine, capsys):
    assert main(["study", "actuator", "--scenario", str(mine), "--levels", "paper", "--margins", "30",
                 "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    claims = record["claims"]
    assert {(r["controller"], r["force"]) for r in claims} == {(c, v) for c in ("pid", "lqr") for v in VARIANTS}
    assert all(r["completed_fraction"] == 1.0 for r in claims)
    assert [m["bandwidth_hz"] for m in record["servo_margins"]] == [30.0, 30.0]


@pytest.mark.parametrize("args, says", [
    (["--scenario", "engage-response"], "--scenario: 'engage-response' is an engagement"),
    (["--approach", "swing-release", "--runs", "1"], "'swing-release' is a fixed-length scenario"),
])
def test_a_scenario_of_the_wrong_kind_is_refused_before_anything_runs(args, says, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["study", "actuator", *args, "--out", str(out)]) == 2
    assert says in capsys.readouterr().err
    assert not out.exists()
