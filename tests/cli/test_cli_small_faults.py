"""The smaller faults: ``study whip-loads --step`` without ``--links`` is refused, not ignored;
``view`` refuses a run folder whose run.json is another run's; the yaw-limit message blames the
paper's zigzag modes (and turbulence) only where they are, and recommends the converged preset
only to runs that do not use it.
"""

import json
import shutil

import pytest

from hosedrogue import cli


def test_whip_loads_step_without_links_is_refused(capsys):
    code = cli.main(["study", "whip-loads", "--step", "0.001"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and "--step = 0.001" in err and "--links" in err, err


def test_view_refuses_another_run_s_run_json(tmp_path, capsys):
    short, long_ = tmp_path / "short", tmp_path / "long"
    for folder, duration in ((short, "0.2"), (long_, "0.4")):
        assert cli.main(["simulate", "swing-release", "--duration", duration, "--out", str(folder)]) == 0
    mixed = shutil.copytree(short, tmp_path / "mixed")
    shutil.copy(long_ / "run.json", mixed / "run.json")
    capsys.readouterr()
    code = cli.main(["view", str(mixed), "--out", str(tmp_path / "v.html")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "files of different runs" in err and "\n" not in err, err
    assert not (tmp_path / "v.html").exists()
    assert cli.main(["view", str(short), "--out", str(tmp_path / "ok.html")]) == 0


DISPLACED = '[scenario]\nduration_s = 3.0\ninitial = "displaced"\ninitial_yaw_offset_deg = 20.0\n' \
            '[numerics]\nmax_yaw_deg = 5.0\n'


@pytest.mark.parametrize("extra, blames_modes, blames_turbulence", [
    ("", True, False),  # the paper's hose, calm air
    ("[turbulence]\nenabled = true\nstart_s = 0.0\nduration_s = 3.0\n", True, True),
    ("[model]\npreset = \"converged\"\n", False, False),  # already the converged preset
])
def test_the_yaw_limit_message_fits_the_run(tmp_path, capsys, extra, blames_modes, blames_turbulence):
    path = tmp_path / "yaw.toml"
    path.write_text(DISPLACED + extra)
    code = cli.main(["simulate", str(path), "--out", str(tmp_path / "out")])
    message = json.loads((tmp_path / "out" / "run.json").read_text())["message"]
    capsys.readouterr()
    assert code == 3 and "yaw passed the limit" in message
    assert ("zigzag" in message) == blames_modes and ("converged" in message) == blames_modes
    assert ("turbulence" in message) == blames_turbulence
