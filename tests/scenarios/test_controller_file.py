"""A controller named by a Python file relative to the scenario file (``entry = "ctl/law.py:make"``):
imported by its path from any working directory, the run recording the absolute path; through
``extends`` a parent's relative path stays relative to the parent's folder; a missing file is a
one-line error before the run."""

import json

import pytest

from hosedrogue.cli import main
from hosedrogue.errors import ParameterError
from hosedrogue.scenarios import load_scenario

LAW = ("CALLS = []\n"
       "def make(**options):\n"
       "    class C:\n"
       "        def reset(self, m): pass\n"
       "        def __call__(self, t, m):\n"
       "            CALLS.append(t)\n"
       "            return (options.get('force_n', 0.0), 0.0)\n"
       "    return C()\n")


def _layout(tmp_path):
    (tmp_path / "runs" / "ctl").mkdir(parents=True)
    (tmp_path / "runs" / "ctl" / "law.py").write_text(LAW)
    sc = tmp_path / "runs" / "s.toml"
    sc.write_text('[scenario]\nduration_s = 0.05\n[controller]\ntype = "python"\nentry = "ctl/law.py:make"\n'
                  'sample_time_s = 0.01\n[controller.options]\nforce_n = 100.0\n')
    return sc


def test_a_controller_file_relative_to_the_scenario(tmp_path, monkeypatch, capsys):
    sc = _layout(tmp_path)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    out = tmp_path / "o"
    assert main(["simulate", str(sc), "--out", str(out)]) == 0
    doc = json.loads((out / "run.json").read_text())
    law = str((tmp_path / "runs" / "ctl" / "law.py").resolve())
    assert law + ":make" in json.dumps(doc)
    assert "peak control force 100 N" in capsys.readouterr().out  # the force the file's law returned
    assert load_scenario(str(sc)).to_dict()["controller"]["entry"] == law + ":make"


def test_extends_keeps_the_parents_folder(tmp_path):
    _layout(tmp_path)
    child = tmp_path / "child" / "c.toml"
    child.parent.mkdir()
    child.write_text('[scenario]\nextends = "../runs/s.toml"\nduration_s = 0.02\n')
    sc = load_scenario(str(child))
    assert sc.to_dict()["controller"]["entry"] == str((tmp_path / "runs" / "ctl" / "law.py").resolve()) + ":make"


def test_a_missing_controller_file_is_one_line(tmp_path, capsys):
    sc = tmp_path / "s.toml"
    sc.write_text('[scenario]\nduration_s = 0.05\n[controller]\ntype = "python"\nentry = "nowhere.py:make"\n'
                  'sample_time_s = 0.01\n')
    code = main(["simulate", str(sc), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and "no such file" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()
    with pytest.raises(ParameterError, match="must be an entry point"):
        sc.write_text('[scenario]\nduration_s = 0.05\n[controller]\ntype = "python"\nentry = "ctl/law.txt:make"\n'
                      'sample_time_s = 0.01\n')
        load_scenario(str(sc))
