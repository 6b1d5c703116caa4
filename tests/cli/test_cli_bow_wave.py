"""``hosedrogue bow-wave``: the steady displacement of the drogue by the receiver's bow wave."""

from __future__ import annotations

import json

import pytest

from hosedrogue.cli import main


def _json(capsys, *argv):
    code = main(["bow-wave", *argv, "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    return json.loads(out)


def test_far_displacement_scales_with_the_source_flux(capsys):
    """Far from the receiver the drogue answers linearly to the bow wave, whose speed is
    Q / (4 pi r^2) with the flux Q = pi R^2 V and r the distance from the source, which sits R/2
    behind the nose (Rankine half-body). Doubling R multiplies the flux by 4 and moves the source
    R/2 further aft, so at the drogue the speed grows by 4 (r(R) / r(2R))^2; the hose points further
    forward see the source shift less, so the displacement's ratio lies between that and 4. The
    bracket is widened by 0.2 %: the drag's quadratic term makes the response nonlinear by about
    u / V < 0.1 % at 10 m (0.13 m/s of 150 m/s)."""
    d = (10.0, 20.0)
    small = _json(capsys, "--radius", "0.5", "--distances", *map(str, d))
    large = _json(capsys, "--radius", "1.0", "--distances", *map(str, d))
    tip = small["probe_offset_m"][0]
    for i, dist in enumerate(d):
        ratio = large["rows"][i]["displacement_magnitude_m"] / small["rows"][i]["displacement_magnitude_m"]
        drogue_only = 4.0 * ((dist + tip + 0.25) / (dist + tip + 0.5)) ** 2
        assert drogue_only * (1 - 2e-3) < ratio < 4.0 * (1 + 2e-3), (dist, ratio, drogue_only)


def test_displacement_falls_with_distance_and_json_matches_table(capsys):
    doc = _json(capsys, "--distances", "0.5", "2", "10")
    mags = [r["displacement_magnitude_m"] for r in doc["rows"]]
    speeds = [r["bow_wave_speed_at_drogue_m_s"] for r in doc["rows"]]
    assert mags[0] > mags[1] > mags[2] > 0 and speeds[0] > speeds[1] > speeds[2] > 0
    assert doc["forebody_radius_m"] == 0.75 and doc["scenario"] == "approach-moderate"
    assert main(["bow-wave", "--distances", "0.5", "2", "10"]) == 0
    table = capsys.readouterr().out.splitlines()[2:]
    for line, m in zip(table, mags):
        assert float(line.split()[4]) == pytest.approx(1e3 * m, abs=1e-3)  # printed to 1 um


@pytest.mark.parametrize("argv, field", [(["--radius", "0"], "--radius"), (["--distances", "-1"], "--distances"),
                                         (["--offset", "1", "2"], "--offset"), (["no-such-scenario"], "no-such")])
def test_bad_input_is_one_line_and_exit_2(capsys, argv, field):
    with pytest.raises(SystemExit) as exc:
        code = main(["bow-wave", *argv])
        raise SystemExit(code)
    err = capsys.readouterr().err.strip()
    assert exc.value.code == 2 and "\n" not in err and field in err and "Traceback" not in err
