"""Every command that writes checks its --out before the work: a folder that cannot be made or
written, or a file name where a folder is needed, is one line (exit 2) and nothing is computed or
written; a reused ``simulate`` folder keeps no file of the earlier run.

Two unwritable places that hold even for root: a path under a regular file (the folder cannot be
made) and ``/sys`` (sysfs refuses new files: EACCES).
"""

import json
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
        ("margins", ["margins", "--links", "6", "--out", out_file + ".png"]),
        ("reference", ["reference", "--out", out_file + ".md"]),
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


@pytest.mark.parametrize("which", range(len(commands(Path("x"), "d", "f"))),
                         ids=[c[0] for c in commands(Path("x"), "d", "f")])
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


def _earlier_output(out: Path, extra: str) -> None:
    """Make ``out`` look written by an earlier run that also wrote ``extra`` (a figure this run does
    not write), with a file of the user's beside it."""
    from hosedrogue.cli.out_folder import MANIFEST

    (out / extra).write_text("an earlier run's figure\n")
    data = json.loads((out / MANIFEST).read_text())
    data["files"].append(extra)
    (out / MANIFEST).write_text(json.dumps(data))
    (out / "notes.txt").write_text("the user's own file\n")


@pytest.mark.parametrize("which", ["simulate", "sweep", "reproduce", "study"])
def test_a_reused_folder_keeps_no_file_of_an_earlier_run_and_every_file_of_the_user(tmp_path, capsys, which):
    """Each command that writes a folder of results, run twice into one: what the first wrote and
    the second did not is gone, the user's file stays, the second's files are there."""
    (tmp_path / "tiny.toml").write_text(TINY)
    out = tmp_path / "out"
    argv = {"simulate": ["simulate", str(tmp_path / "tiny.toml")],
            "sweep": ["sweep", "--altitudes", "8000", "--airspeeds", "150", "--links", "6"],
            # one process: the section's worker processes (one per core by default) would each import the
            # package again, twice here, for the same files (the report is the same either way)
            "reproduce": ["reproduce", "--fast", "--only", "parameters", "--workers", "1"],
            "study": ["study", "manoeuvres", "--banks-deg", "0", "--paths-deg", "0"]}[which] + ["--out", str(out)]
    assert cli.main(argv) == 0
    first = {p.name for p in out.iterdir()}
    _earlier_output(out, "old-figure.png")
    assert cli.main(argv) == 0
    names = {p.name for p in out.iterdir()}
    assert "old-figure.png" not in names and "notes.txt" in names
    assert names == first | {"notes.txt"}, names ^ (first | {"notes.txt"})


def test_a_page_written_into_a_run_folder_goes_with_the_run(tmp_path, capsys):
    """``view RUN --out RUN/page.html`` joins the run's files: the next run written there removes it."""
    (tmp_path / "tiny.toml").write_text(TINY)
    out = tmp_path / "out"
    assert cli.main(["simulate", str(tmp_path / "tiny.toml"), "--out", str(out)]) == 0
    assert cli.main(["view", str(out), "--out", str(out / "page.html")]) == 0
    assert cli.main(["simulate", str(tmp_path / "tiny.toml"), "--out", str(out)]) == 0
    assert not (out / "page.html").exists() and (out / "run.json").exists()


def test_a_manifest_cannot_remove_anything_outside_its_folder_or_not_listed(tmp_path):
    """A hand-edited (or hostile) manifest naming ../, an absolute path or a folder removes none of them."""
    from hosedrogue.cli.out_folder import MANIFEST, clear_earlier_output

    out = tmp_path / "out"
    (out / "sub").mkdir(parents=True)
    outside = tmp_path / "outside.txt"
    outside.write_text("x")
    for name in ("listed.csv", "sub/deep.png", "kept.txt"):
        (out / name).write_text("x")
    (out / MANIFEST).write_text(json.dumps({"files": ["listed.csv", "sub/deep.png", "../outside.txt",
                                                      str(outside), "sub", "", 7]}))
    removed = clear_earlier_output(out, known=("kept.txt",))
    assert sorted(p.name for p in removed) == ["deep.png", "listed.csv"]
    assert outside.exists() and (out / "kept.txt").exists()
    assert sorted(p.name for p in out.iterdir()) == ["kept.txt"]  # the emptied sub-folder and the manifest gone


def test_a_folder_written_before_manifests_loses_only_the_command_s_own_names(tmp_path):
    from hosedrogue.cli.out_folder import clear_earlier_output

    for name in ("timeseries.csv", "view.html", "mine.csv"):
        (tmp_path / name).write_text("x")
    clear_earlier_output(tmp_path, known=("timeseries.csv", "view.html", "run.json"))
    assert [p.name for p in tmp_path.iterdir()] == ["mine.csv"]


def test_margins_checks_its_out_before_linearizing(tmp_path, capsys, monkeypatch):
    """The check comes before the work: the linearization, were it reached, fails the test."""
    import hosedrogue.analysis.linearize as lin

    def reached(*args, **kwargs):
        raise AssertionError("the model was linearized before --out was checked")

    monkeypatch.setattr(lin, "linearize", reached)
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder\n")
    code = cli.main(["margins", "--links", "6", "--out", str(blocker / "sub" / "m.png")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and "is a file, not a folder" in err, err


def test_only_the_files_a_command_wrote_are_listed(tmp_path):
    """A file of the user's changed while the command writes (an editor saving it) is not the
    command's: neither listed by a command that says what it writes nor found by one that scans."""
    from hosedrogue.cli.out_folder import MANIFEST, output_folder

    for scan in (False, True):
        out = tmp_path / f"scan{scan}"
        out.mkdir()
        (out / "notes.txt").write_text("the user's\n")
        with output_folder(out, "test", scan=scan) as written:
            (out / "sub").mkdir()
            (out / "sub" / "figure.png").write_text("ours\n")
            written.add(out / "sub" / "figure.png", tmp_path / "elsewhere.txt")
            (out / "notes.txt").write_text("the user's, edited meanwhile\n")
        assert json.loads((out / MANIFEST).read_text())["files"] == ["sub/figure.png"]


def test_a_file_the_system_refuses_while_writing_is_one_line(tmp_path, capsys):
    """A folder where the run's hose.npz goes (written on a thread beside the CSV): the system's
    refusal ends the command in one line naming the file, exit 1, not a traceback."""
    scenario = tmp_path / "tiny.toml"
    scenario.write_text(TINY)
    out = tmp_path / "out"
    (out / "hose.npz").mkdir(parents=True)
    code = cli.main(["simulate", str(scenario), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 1, err
    assert "\n" not in err and err.startswith("hosedrogue: error: ") and "hose.npz" in err, err
