"""A chaotic response as a distribution (docs/engagement.md, "Chaotic peaks as distributions";
issue 32): the perturbations, the statistics, the ensemble and its command."""

import json
import math

import numpy as np
import pytest

from hosedrogue.cli import main
from hosedrogue.errors import ParameterError
from hosedrogue.scenarios import load_scenario
from hosedrogue.studies.convergence import with_links
from hosedrogue.studies.ensemble import distribution, parse_perturbation, perturbed, run_ensemble


@pytest.mark.parametrize("text, parsed", [("seed", ("seed", 0.0)), ("probe-offset=1e-6", ("probe-offset", 1e-6))])
def test_perturbations_parse(text, parsed):
    assert parse_perturbation(text) == parsed


@pytest.mark.parametrize("bad", ["seeds", "probe-offset", "probe-offset=0", "probe-offset=-1", "probe-offset=x",
                                 "probe-offset=11", "seed=3"])
def test_bad_perturbations_are_one_line(bad):
    with pytest.raises(ParameterError, match="perturb") as exc:
        parse_perturbation(bad)
    assert "\n" not in str(exc.value)


def test_probe_offsets_fill_their_disc_and_are_reproducible():
    """200 copies' probe offsets: every one inside the 1 mm disc, the same on a second draw (the
    copies do not depend on the process), and uniform over the disc's area: the fraction inside
    half the radius is 1/4 (binomial standard deviation sqrt(0.25 0.75 / 200) = 0.031; bound 4 of
    them, 0.12)."""
    sc = load_scenario("engage-response")
    p0 = sc.engagement.probe
    offsets = np.array([[c.engagement.probe.offset_y_m - p0.offset_y_m, c.engagement.probe.offset_z_m - p0.offset_z_m]
                        for c in (perturbed(sc, "probe-offset", 1e-3, i) for i in range(200))])
    again = perturbed(sc, "probe-offset", 1e-3, 17).engagement.probe
    assert (again.offset_y_m, again.offset_z_m) == tuple(offsets[17] + [p0.offset_y_m, p0.offset_z_m])
    r = np.hypot(*offsets.T)
    assert r.max() <= 1e-3 and abs(np.mean(r < 0.5e-3) - 0.25) < 0.12


def test_seed_copies_follow_the_campaigns_rule():
    from hosedrogue.studies.seeds import run_seed

    sc = load_scenario("paper-turbulence")
    assert [perturbed(sc, "seed", 0.0, i).params.turbulence.seed for i in range(3)] == [
        run_seed(sc.params.turbulence.seed, i) for i in range(3)]


def test_distribution_of_a_known_sample():
    """0..99: median 49.5, numpy's linear 5 % and 95 % points 4.95 and 94.05; the bootstrap
    interval of the median holds it and lies within the sample's central half; a copy without the
    figure is counted, not used."""
    d = distribution([float(x) for x in range(100)] + [None])
    assert (d["median"], d["copies"], d["missing"]) == (49.5, 100, 1)
    assert d["p05"] == pytest.approx(4.95, rel=1e-12) and d["p95"] == pytest.approx(94.05, rel=1e-12)
    lo, hi = d["median_interval"]
    assert 25 < lo < 49.5 < hi < 75
    assert distribution([None, None])["median"] is None
    assert distribution([2.0, 2.0, 2.0])["median_interval"] is None


def test_ensemble_checks_its_input():
    sc = load_scenario("engage-response")
    with pytest.raises(ParameterError, match="no turbulence"):
        run_ensemble(sc, 4, "seed")
    with pytest.raises(ParameterError, match="no probe"):
        run_ensemble(load_scenario("paper-turbulence"), 4, "probe-offset=1e-6")
    with pytest.raises(ParameterError, match="ensemble"):
        run_ensemble(sc, 1)


def test_an_engagement_ensemble_and_its_verification():
    """Three copies of the responsive reel on 20 links for 4 s (contact at 2 s), probes displaced
    by up to 1 um, verified on 40 links: every figure's quantiles are within the copies' range,
    and the verification compares the median, 5 % and 95 % points of each figure."""
    sc = with_links(load_scenario("engage-response"), 20).with_overrides(duration_s=4.0)
    ens = run_ensemble(sc, 3, "probe-offset=1e-6", verify=True)
    assert ens.links == 20 and len(ens.figures) == 3 and all(ens.completed)
    for key, d in ens.distributions.items():
        if d["median"] is not None:
            assert d["min"] <= d["p05"] <= d["median"] <= d["p95"] <= d["max"], key
    v = ens.verification
    assert v["refined"]["links"] == 40
    assert set(v["figures"]) == {f"{q}.{k}" for q in ("median", "p05", "p95") for k in ens.distributions}
    json.dumps(ens.to_dict(), allow_nan=False)


@pytest.mark.subprocess
def test_ensemble_figures_do_not_depend_on_the_processes(tmp_path, capsys):
    """Four seeds of the paper's turbulence case for 11 s, in this process and in two worker
    processes: the same figures, bit for bit; ensemble.json is strict JSON."""
    args = ["simulate", "paper-turbulence", "--duration", "11", "--ensemble", "4", "--perturb", "seed", "--json"]
    assert main([*args, "--out", str(tmp_path / "one")]) == 0
    one = json.loads(capsys.readouterr().out)
    assert main([*args, "--workers", "2", "--out", str(tmp_path / "two")]) == 0
    two = json.loads(capsys.readouterr().out)
    assert one["figures"] == two["figures"] and one["distributions"] == two["distributions"]
    text = (tmp_path / "two" / "ensemble.json").read_text()
    assert "NaN" not in text and not math.isnan(json.loads(text)["distributions"]["statistics.rms_dy_m"]["median"])
