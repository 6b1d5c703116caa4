"""Every shipped scenario's run.json is strict JSON: a brief run of each (0.1 s past the start of
its turbulence, so that the window is inside the run, which `simulate` requires) parsed by a parser that refuses NaN and Infinity, the way
JavaScript's JSON.parse does; and a value that is not finite is written as null. The same for the
``meta_json`` string of a run's ``timeseries.mat``."""

import json
import math

import pytest

from hosedrogue.cli import main
from hosedrogue.scenarios import load_scenario, shipped_scenarios
from hosedrogue.simulation.budget import on_step_grid
from hosedrogue.jsonio import fallback as _json_value


def _refuse(constant):
    raise ValueError(f"not strict JSON: {constant}")


def strict_loads(text: str):
    """json.loads that refuses NaN, Infinity and -Infinity."""
    return json.loads(text, parse_constant=_refuse)


@pytest.mark.parametrize("name", shipped_scenarios())
def test_every_shipped_scenarios_run_json_is_strict(name, tmp_path, capsys):
    sc = load_scenario(name)
    gusts = sc.params.turbulence
    num = sc.params.numerics  # on the run's output grid, as every run must be
    duration = min(sc.duration_s, on_step_grid((gusts.start_s if gusts.enabled else 0.0) + 0.1, num.step_s,
                                               num.output_every))
    code = main(["simulate", name, "--duration", repr(duration), "--out", str(tmp_path / "o")])
    capsys.readouterr()
    assert code in (0, 3)  # 3: a run that stopped early still writes its run.json, marked
    doc = strict_loads((tmp_path / "o" / "run.json").read_text())
    assert isinstance(doc, dict) and doc


def test_a_value_that_is_not_finite_is_null():
    import numpy as np

    assert _json_value(np.float32("inf")) is None and _json_value(np.float64("nan")) is None
    assert _json_value(np.float32(1.5)) == 1.5 and _json_value(object).startswith("<class")
    with pytest.raises(ValueError):
        strict_loads('{"a": Infinity}')
    assert not math.isnan(strict_loads('{"a": 1.0}')["a"])


def test_the_mat_files_meta_json_is_strict(tmp_path, capsys):
    """A turbulence window without an end (turbulence.duration_s = inf, the default) was
    ``Infinity`` in meta_json; it is null, as in run.json."""
    from scipy.io import loadmat

    path = tmp_path / "endless.toml"
    path.write_text('[scenario]\nname = "endless"\nduration_s = 0.1\n[turbulence]\nenabled = true\n'
                    'start_s = 0.0\n[hose]\nlinks = 6\n')
    assert main(["simulate", str(path), "--format", "mat", "--out", str(tmp_path / "o")]) == 0
    capsys.readouterr()
    text = str(loadmat(tmp_path / "o" / "timeseries.mat")["meta_json"][0])
    meta = strict_loads(text)
    assert meta["params"]["turbulence"]["duration_s"] is None
    doc = strict_loads((tmp_path / "o" / "run.json").read_text())  # run.json holds the meta's keys
    assert meta["params"] == doc["params"] and meta["scenario"] == doc["scenario"]
