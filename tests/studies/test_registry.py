"""The study registry (hosedrogue.studies.registry): every study is one ``hosedrogue study NAME``,
each names the report section that renders it, and a study that runs a scenario takes the
user's file."""

import argparse
import json
import math

import pytest

from hosedrogue.cli import build_parser, main
from hosedrogue.report.plan import SECTIONS
from hosedrogue.jsonio import plain
from hosedrogue.studies.registry import STUDIES


def _study_commands():
    parser = build_parser()
    top = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    study = top.choices["study"]
    sub = next(a for a in study._actions if isinstance(a, argparse._SubParsersAction))
    return set(sub.choices)


def test_every_study_is_a_command_and_every_command_a_study():
    assert _study_commands() == set(STUDIES)


def test_every_study_names_its_module_and_section():
    import importlib

    sections = {s.key for s in SECTIONS}
    for study in STUDIES.values():
        importlib.import_module(f"hosedrogue.studies.{study.module}")
        assert study.section in sections, study.name
        assert (study.run is None) == study.custom_cli, study.name
        assert bool(study.kind) == bool(study.takes) or study.custom_cli, study.name


def test_plain_is_strict_json():
    record = plain({"a": float("nan"), "b": (1, 2.5), "c": [float("inf")], "d": {"e": True}})
    assert json.loads(json.dumps(record, allow_nan=False)) == {"a": None, "b": [1, 2.5], "c": [None], "d": {"e": True}}


def test_manoeuvres_takes_the_users_hose(tmp_path, capsys):
    """A scenario file with a hose twice as heavy: the drogue hangs lower and less far aft in
    level flight (its weight against the same drag turns the hose toward the vertical)."""
    mine = tmp_path / "heavy.toml"
    mine.write_text('[scenario]\nextends = "swing-release"\nname = "heavy-hose"\n[hose]\nmass_per_length_kg_m = 8.8\n')
    out = {}
    for name, scenario in (("shipped", "swing-release"), ("mine", str(mine))):
        assert main(["study", "manoeuvres", "--banks-deg", "0", "--paths-deg", "0", "--scenario", scenario,
                     "--json"]) == 0
        out[name] = json.loads(capsys.readouterr().out)
    assert out["mine"]["scenario"] == "heavy-hose"
    (x0, _, z0), = out["shipped"]["bank"]["drogue_position_m"]
    (x1, _, z1), = out["mine"]["bank"]["drogue_position_m"]
    assert z1 > z0 + 0.5 and x1 > x0


def test_bow_wave_far_displacement_grows_as_the_forebody_area(tmp_path, capsys):
    """A forebody of radius 1.2 m instead of 0.75 m: far from the nose the bow wave is the field of
    a source of strength pi R^2 V, so the drogue's small displacement there grows as R^2 (2.56);
    10 % allows for the probe tip's 10 m from the drogue not being quite far."""
    mine = tmp_path / "big.toml"
    mine.write_text('[scenario]\nextends = "approach-moderate"\nname = "big-nose"\n[bow_wave]\nforebody_radius_m = 1.2\n')
    far = {}
    for name, args in (("shipped", []), ("mine", ["--scenario", str(mine)])):
        assert main(["study", "bow-wave", *args, "--json", "--out", str(tmp_path / name)]) == 0
        record = json.loads(capsys.readouterr().out)
        assert json.loads((tmp_path / name / "study.json").read_text()) == record
        assert (tmp_path / name / "bow_wave.png").stat().st_size > 10_000  # the study's figure
        far[name] = (record["radius_m"], record["far_m"])
    (r0, d0), (r1, d1) = far["shipped"], far["mine"]
    assert (r0, r1) == (0.75, 1.2)
    assert d1 / d0 == pytest.approx((r1 / r0) ** 2, rel=0.10)


@pytest.mark.parametrize("args, says", [
    (["manoeuvres", "--scenario", "engage-response"], "'engage-response' is an engagement; the manoeuvres study"),
    (["bow-wave", "--scenario", "swing-release"], "'swing-release' is a fixed-length scenario; the bow-wave study"),
    (["accuracy", "--scenario", "nope.toml"], "no such file or shipped scenario"),
])
def test_a_scenario_of_the_wrong_kind_is_refused_before_anything_runs(args, says, tmp_path, capsys):
    assert main(["study", *args, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert says in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_a_setting_out_of_range_names_the_option(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["study", "manoeuvres", "--banks-deg", "100"])
    assert exc.value.code == 2
    assert "--banks-deg = '100': must be a number in [-80, 80] deg" in capsys.readouterr().err


def test_accuracy_study_shows_rk4s_order_on_the_users_scenario(tmp_path, capsys):
    """The user's 20 s run (gusts from 10 s) at 0.01 s and 0.005 s against 0.00125 s: halving an
    RK4 step cuts its error by 2^4 = 16 in the asymptotic range. The observed order is held to
    3.3-4.7: the gust record is interpolated between samples and its smoothed onset at 10 s has a
    kink in a higher derivative (over only 4 s of gusts, where the onset dominates, the order
    measured 3.0), and the reference carries (0.00125/0.005)^4 = 0.4 % of the finer run's error.
    The study's figure is written."""
    mine = tmp_path / "short.toml"
    mine.write_text('[scenario]\nextends = "paper-turbulence"\nname = "short"\nduration_s = 20.0\n')
    assert main(["study", "accuracy", "--scenario", str(mine), "--steps-s", "0.01", "0.005",
                 "--reference-step-s", "0.00125", "--json", "--out", str(tmp_path / "out")]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["scenario"] == "short" and record["duration_s"] == 20.0
    coarse, fine = record["max_error_m"]
    assert 3.3 < math.log2(coarse / fine) < 4.7
    assert (tmp_path / "out" / "steps.png").stat().st_size > 10_000  # the study's figure
