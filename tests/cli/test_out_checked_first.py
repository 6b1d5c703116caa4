"""Every command that writes checks its --out before the work: a folder that cannot be made or
written, or a file name where a folder is needed, is one line (exit 2) and nothing is computed or
written; a reused ``simulate`` folder keeps no file of the earlier run.

Two unwritable places that hold even for root: a path under a regular file (the folder cannot be
made) and ``/sys`` (sysfs refuses new files: EACCES).
"""

import os
from pathlib import Path

import pytest

from hosedrogue import cli

TINY = '[scenario]\nname = "tiny"\nduration_s = 0.1\n[hose]\nlinks = 6\n'


def commands(tmp_path, out_dir, out_file):
    """(name, argv) of every writing command, ``out_dir``/``out_file`` as its --out."""
    scenario = tmp_path / "tiny.toml"
    run_folder = tmp_path / "run"
    return [
        ("simulate", ["simulate", str(scenario), "--out", out_dir]),
        ("montecarlo", ["montecarlo", str(scenario), "--runs", "1", "--scheduler", "synchronous", "--quiet",
                        "--out", out_dir]),
        ("sweep", ["sweep", "--altitudes", "8000", "--airspeeds", "150", "--links", "6", "--out", out_dir]),
        ("reproduce", ["reproduce", "--fast", "--only", "parameters", "--out", out_dir]),
        ("study docking", ["study", "docking", "--runs", "1", "--out", out_dir]),
        ("study long-runs", ["study", "long-runs", "--out", out_dir]),
        ("fly", ["fly", "approach-moderate", "--out", out_dir, "--port", "0"]),
        ("linearize", ["linearize", "--links", "6", "--format", "mat", "--out", out_file + ".mat"]),
        ("design", ["design", "pid", "--format", "mat", "--out", out_file + ".mat"]),
        ("export-fmu", ["export-fmu", "--links", "6", "--out", out_file + ".fmu"]),
        ("view", ["view", str(run_folder), "--out", out_file + ".html"]),
    ]


def unwritable(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder\n")
    places = [(str(blocker / "sub"), "is a file, not a folder")]
    if Path("/sys").is_dir():
        places.append(("/sys/hosedrogue-out", "cannot be written"))
    return places


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("views")
    (tmp / "tiny.toml").write_text(TINY)
    assert cli.main(["simulate", str(tmp / "tiny.toml"), "--out", str(tmp / "run")]) == 0
    return tmp


@pytest.mark.parametrize("which", range(11), ids=[c[0] for c in commands(Path("x"), "d", "f")])
def test_an_unwritable_out_is_one_line_before_the_work(run_folder, tmp_path, capsys, monkeypatch, which):
    import shutil

    shutil.copytree(run_folder / "run", tmp_path / "run")
    (tmp_path / "tiny.toml").write_text(TINY)
    for place, why in unwritable(tmp_path):
        name, argv = commands(tmp_path, place, place + "/file")[which]
        before = sorted(os.listdir(tmp_path))
        code = cli.main(argv)
        err = capsys.readouterr().err.strip()
        assert code == 2, (name, place, err)
        assert "\n" not in err and "--out = " in err and why in err, (name, err)
        assert sorted(os.listdir(tmp_path)) == before


def test_a_reused_simulate_folder_keeps_no_file_of_the_earlier_run(tmp_path, capsys):
    scenario = tmp_path / "tiny.toml"
    scenario.write_text(TINY)
    out = tmp_path / "out"
    assert cli.main(["simulate", str(scenario), "--out", str(out), "--format", "mat", "--view"]) == 0
    assert (out / "view.html").exists() and (out / "timeseries.mat").exists()
    (out / "notes.txt").write_text("the user's own file\n")
    assert cli.main(["simulate", str(scenario), "--out", str(out)]) == 0
    names = sorted(p.name for p in out.iterdir())
    assert "view.html" not in names and "timeseries.mat" not in names
    assert "notes.txt" in names and "timeseries.csv" in names
