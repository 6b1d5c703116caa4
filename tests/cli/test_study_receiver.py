"""``hosedrogue study receiver`` (hosedrogue.cli.study_receiver): the F-16's trim check and the two
campaigns with the user's approach, and a bad pair refused before anything is written."""

import json

import pytest

from hosedrogue.aircraft.published import TABLE_3_6_2
from hosedrogue.cli import main


def test_the_users_approach_flies_beside_the_point_receiver_on_the_same_seeds(tmp_path, capsys):
    """The user's file (the F-16's approach under another name) and the point receiver, one seed each:
    both campaigns run the same seed, their folders carry the scenarios' names, and the paired
    difference is the two misses' difference. The trim check beside them holds every book point
    (tests/studies/test_receiver_study.py checks its rows); the record is study.json too."""
    mine = tmp_path / "mine.toml"
    mine.write_text('[scenario]\nextends = "approach-f16-moderate"\nname = "my-receiver"\n')
    out = tmp_path / "o"
    assert main(["study", "receiver", "--runs", "1", "--scenario", str(mine), "--trim-points", "2", "--json",
                 "--quiet", "--out", str(out)]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["scenarios"] == ["my-receiver", "approach-moderate-docking"]
    assert {n: c["runs"] for n, c in record["capture"].items()} == {"my-receiver": 1, "approach-moderate-docking": 1}
    assert record["stopped_runs"] == {"my-receiver": 0, "approach-moderate-docking": 0}
    seeds = set()
    misses = []
    for name in record["scenarios"]:
        rows = (out / name / "runs.csv").read_text().splitlines()
        head = rows[0].split(",")
        row = dict(zip(head, rows[1].split(",")))
        seeds.add(row["seed"])
        misses.append(float(row["miss_distance_m"]))
    assert len(seeds) == 1  # the same turbulence seed: the runs pair
    p = record["miss_paired_difference"]
    assert p["runs"] == 1 and p["mean_m"] == pytest.approx(misses[0] - misses[1], abs=1e-12)  # pandas' CSV parser may differ from float() in the last bit
    assert (out / "receiver_miss_cdf.png").stat().st_size > 10_000
    assert record["trim"]["points"] == len(TABLE_3_6_2) == record["trim"]["within_printed_digits"]
    assert (out / "receiver_trim.png").stat().st_size > 10_000
    assert json.loads((out / "study.json").read_text()) == record


@pytest.mark.parametrize("args, says", [
    (["--scenario", "paper-turbulence"], "scenario: 'paper-turbulence' is a fixed-length scenario; the receiver study"),
    (["--against", "approach-f16-moderate"], "against = 'approach-f16-moderate': the same scenario name as the first"),
])
@pytest.mark.parametrize("runs", ["1", "0"])
def test_a_bad_pair_is_refused_before_anything_runs(args, says, runs, tmp_path, capsys):
    """Also without campaigns (--runs 0): a scenario given is checked, not ignored."""
    out = tmp_path / "o"
    assert main(["study", "receiver", "--runs", runs, *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert says in err and len(err.strip().splitlines()) == 1
    assert not out.exists()
