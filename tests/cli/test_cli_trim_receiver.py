"""``hosedrogue trim-receiver``: its JSON contract, the linear model's shapes, and the exit status
and one-line message of bad input and of a flight the aircraft cannot trim."""

import json

import numpy as np
import pytest

from hosedrogue.cli import main
from hosedrogue.constants import FT_TO_M, G0


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_json_contract_and_physics(capsys):
    """Level flight: pitch = alpha, no turn, the residuals at the solver's zero; the normal load factor
    the linear model's outputs carry at trim is 1 g (lift carries the weight)."""
    code, out, err = run(capsys, "trim-receiver", "--airspeed", "150", "--altitude", "3000", "--linear", "--json")
    assert code == 0, err
    d = json.loads(out)
    t = d["trim"]
    for key in ("alpha_deg", "beta_deg", "throttle", "elevator_deg", "aileron_deg", "rudder_deg", "residuals"):
        assert key in t
    assert 0 < t["throttle"] < 1 and t["theta_deg"] == pytest.approx(t["alpha_deg"], abs=1e-9)
    assert max(abs(v) for v in t["residuals"].values()) < 1e-9
    lin = d["linear"]
    A, B, C, D = (np.array(lin[k]) for k in "ABCD")
    assert A.shape == (13, 13) and B.shape == (13, 4) and C.shape == (15, 13) and D.shape == (15, 4)
    assert {m["name"] for m in lin["modes"]} >= {"phugoid", "short period", "Dutch roll", "roll", "spiral"}
    # positive elevator (trailing edge down) adds lift at the tail at once (the F-16's CZ falls by
    # 0.19/25 a degree): the normal load factor's direct term rises before the nose drops
    assert D[lin["outputs"].index("nz_g"), 1] > 0


def test_book_speed_in_si(capsys):
    """502 ft/s at sea level in SI: the trim of Table 3.6-3 (alpha 2.115 deg at the book's g; the
    command trims under the standard g, 1.3e-4 heavier: alpha within 0.01 deg)."""
    code, out, _ = run(capsys, "trim-receiver", "--airspeed", str(502 * FT_TO_M), "--altitude", "0", "--json")
    assert code == 0
    assert json.loads(out)["trim"]["alpha_deg"] == pytest.approx(np.degrees(0.03691), abs=0.01)
    assert G0 > 32.17 * FT_TO_M


def test_table_output(capsys):
    code, out, _ = run(capsys, "trim-receiver", "--airspeed", "150", "--altitude", "3000", "--bank-deg", "30",
                       "--linear")
    assert code == 0
    assert "Dutch roll" in out and "throttle" in out and "bank 30 deg" in out


@pytest.mark.parametrize("argv, status, message", [
    (["--airspeed", "-5", "--altitude", "0"], 2, "--airspeed = '-5'"),
    (["--airspeed", "150", "--altitude", "30000"], 2, "--altitude = '30000'"),
    (["--airspeed", "150", "--altitude", "0", "--model", "no-such.toml"], 2, "--model = 'no-such.toml'"),
    (["--airspeed", "150", "--altitude", "0", "--xcg", "2"], 2, "--xcg = '2'"),
    (["--airspeed", "20", "--altitude", "0"], 3, "no trim of f16 at 20 m/s"),
])
def test_bad_input_and_no_trim(capsys, argv, status, message):
    try:
        code = main(["trim-receiver", *argv])
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    out, err = capsys.readouterr()
    assert code == status and message in err and out == "" and err.count("\n") == 1
