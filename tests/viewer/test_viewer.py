"""The viewer's data path without a browser: the hose's shape a run writes (hose.npz) for both hose
models, reading run folders and refusing what is not one, the page's self-containment and the
arrays it carries, the command line, and a campaign's runs run again for the page.
(The page in a real browser: tests/viewer/test_viewer_browser.py.)"""

import base64
import hashlib
import json
import re

import numpy as np
import pytest

import hosedrogue as hd
from hosedrogue import cli, viewer
from hosedrogue.results.hose_file import read_hose_npz, split_joints, stack_joints
from hosedrogue.viewer.page import envelope_indices, frame_indices
from viewer_cases import ENGAGE, TINY


@pytest.fixture(scope="module")
def fixed(tmp_path_factory):
    path = tmp_path_factory.mktemp("scenarios") / "tiny.toml"
    path.write_text(TINY)
    return hd.run(hd.load_scenario(str(path)))


@pytest.fixture(scope="module")
def engaged(tmp_path_factory):
    path = tmp_path_factory.mktemp("scenarios") / "engage20.toml"
    path.write_text(ENGAGE)
    return hd.run(hd.load_scenario(str(path)))


@pytest.fixture(scope="module")
def folders(fixed, engaged, tmp_path_factory):
    root = tmp_path_factory.mktemp("runs")
    (root / "tiny.toml").write_text(TINY)
    hd.write(fixed, root / "fixed", plot=False)
    hd.write(engaged, root / "engaged", plot=False)
    return root


def _link_lengths(counts, joints):
    """Per output time, the sum of the link lengths [m] of the stored joints."""
    offsets = np.concatenate([[0], np.cumsum(counts)])
    return np.array([np.linalg.norm(np.diff(joints[a:b], axis=0), axis=1).sum()
                     for a, b in zip(offsets[:-1], offsets[1:])])


def test_the_hose_file_holds_every_joint_of_the_fixed_length_hose(fixed, folders):
    """hose.npz is the run's joints at full precision (the same bits), one row per output time; its
    links keep their length (rigid links: the sum is the hose length to rounding, 1e-12 m)."""
    t, counts, joints = read_hose_npz(folders / "fixed" / "hose.npz")
    n = 6  # TINY's links
    assert np.array_equal(t, fixed.t_s) and np.all(counts == n + 1)
    assert np.array_equal(joints.reshape(t.size, n + 1, 3), np.asarray(fixed.joints_m))
    assert np.allclose(joints[::n + 1], 0.0, atol=0.0)  # row 0 of each time: the tow point, the origin of S_p
    length = hd.PAPER.hose.length_m
    assert np.allclose(_link_lengths(counts, joints), length, rtol=0.0, atol=1e-12)


def test_the_hose_file_follows_the_engagements_remeshes(engaged, folders):
    """The engagement's link count changes where links merge; each time's joints are the run's, and
    the sum of their link lengths is the free hose length the run reports (hose_length_m) to 1e-9 m
    (the chain is the hose: a remesh conserves the length up to the merge loss the run books)."""
    t, counts, joints = read_hose_npz(folders / "engaged" / "hose.npz")
    merges = [e for e in engaged.events if e["kind"] == "merge"]
    assert merges and counts[0] == 21 and counts[-1] == 21 - len(merges)
    offsets = np.concatenate([[0], np.cumsum(counts)])
    for i in (0, t.size // 2, t.size - 1):
        assert np.array_equal(joints[offsets[i]:offsets[i + 1]], engaged.joints_m[i])
    assert np.allclose(_link_lengths(counts, joints), engaged.hose_length_m, rtol=0.0, atol=1e-9)


def test_stacking_and_splitting_the_joints_are_inverse(engaged):
    counts, joints = engaged.hose_shapes()
    again = split_joints(counts, joints)
    assert len(again) == engaged.t_s.size and all(np.array_equal(a, b) for a, b in zip(again, engaged.joints_m))
    assert all(np.array_equal(a, b) for a, b in zip(stack_joints(again), (counts, joints)))


def test_write_adds_the_hose_file_and_keeps_the_others(fixed, tmp_path):
    """write() adds hose.npz after run.json; the time series and run.json are what they were
    (the same text as to_csv and run_document give; run.json strict, an infinity as null)."""
    paths = hd.write(fixed, tmp_path / "run", plot=False)
    assert [p.name for p in paths] == ["timeseries.csv", "run.json", "hose.npz"]
    fixed.to_csv(tmp_path / "alone.csv")
    assert (tmp_path / "run" / "timeseries.csv").read_bytes() == (tmp_path / "alone.csv").read_bytes()
    from hosedrogue.jsonio import dumps

    doc = json.loads((tmp_path / "run" / "run.json").read_text())
    digests = doc.pop("data_sha256")  # beside the run's document: the SHA-256 of the files' data
    assert doc == json.loads(dumps(fixed.run_document()))
    assert digests["timeseries.csv"] == hashlib.sha256((tmp_path / "alone.csv").read_bytes()).hexdigest()
    with np.load(tmp_path / "run" / "hose.npz") as data:
        h = hashlib.sha256()
        for name in ("t_s", "joint_count", "joints_m"):
            h.update(f"{data[name].dtype.str} {data[name].shape}".encode() + data[name].tobytes())
    assert digests["hose.npz"] == h.hexdigest()


def test_a_folder_reads_as_the_result_it_was_written_from(engaged, folders):
    """read_run (files) and ViewRun.from_result (memory) give the same view, to the CSV's 10
    significant digits for the series and exactly for the hose."""
    a = viewer.read_run(folders / "engaged")
    b = viewer.ViewRun.from_result(engaged)
    assert a.label == b.label == "engage-response-20"
    assert np.array_equal(a.joints_m, b.joints_m) and np.array_equal(a.joint_count, b.joint_count)
    assert set(a.columns) == set(b.columns) >= {"t_s", "drogue_dy_m", "exit_tension_n", "probe_load_n", "coupled"}
    for name in a.columns:
        assert np.allclose(a.columns[name], b.columns[name], rtol=1e-9, atol=1e-9), name


def _not_a_run(tmp_path, folders):
    """Folders that are not runs, by name -> (path, words the message must hold)."""
    import shutil

    (tmp_path / "empty").mkdir()
    (tmp_path / "file.txt").write_text("x")
    old = tmp_path / "old"
    shutil.copytree(folders / "fixed", old)
    (old / "hose.npz").unlink()
    mixed = tmp_path / "mixed"
    shutil.copytree(folders / "fixed", mixed)
    shutil.copy(folders / "engaged" / "hose.npz", mixed / "hose.npz")
    broken = tmp_path / "broken"
    shutil.copytree(folders / "fixed", broken)
    (broken / "hose.npz").write_bytes(b"not a numpy file")
    another = tmp_path / "another"  # the run.json of the same scenario run with another seed: same times
    shutil.copytree(folders / "fixed", another)
    hd.write(hd.run(hd.load_scenario(str(folders / "tiny.toml")).with_overrides(seed=5)), tmp_path / "seed5", plot=False)
    shutil.copy(tmp_path / "seed5" / "run.json", another / "run.json")
    return {"missing": (tmp_path / "missing", "not a folder"), "file": (tmp_path / "file.txt", "not a folder"),
            "empty": (tmp_path / "empty", "not a run folder"), "old": (old, "run the scenario again"),
            "mixed": (mixed, "different runs"), "broken": (broken, "not a run's hose file"),
            "another": (another, "run.json is of another run")}


@pytest.mark.parametrize("case", ["missing", "file", "empty", "old", "mixed", "broken", "another"])
def test_what_is_not_a_run_is_refused_in_one_line(case, tmp_path, folders, capsys):
    """hosedrogue view on a folder that is not a run: one line naming it, exit 2, nothing written."""
    path, words = _not_a_run(tmp_path, folders)[case]
    out = tmp_path / "view.html"
    code = cli.main(["view", str(folders / "fixed"), str(path), "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and words in err and str(path) in err and "Traceback" not in err
    assert not out.exists()


def test_frames_are_thinned_to_the_rate_asked_for():
    t = np.arange(0.0, 10.0 + 1e-9, 0.01)
    assert np.array_equal(frame_indices(t, None), np.arange(t.size))
    keep = frame_indices(t, 25.0)
    assert keep[0] == 0 and keep[-1] == t.size - 1
    gaps = np.diff(t[keep])
    # 25 frames per simulated second out of 100 Hz samples: every 4th, the last gap possibly shorter
    assert np.allclose(gaps[:-1], 0.04, atol=1e-9) and gaps[-1] <= 0.04 + 1e-9


def test_chart_decimation_keeps_the_peaks():
    """A 1-sample spike in 10^5 samples survives the envelope (a tension snap must stay visible)."""
    rng = np.random.default_rng(7)
    y = rng.normal(size=100_000)
    y[31_337], y[77_001] = 50.0, -60.0
    keep = envelope_indices(y, 2000)
    assert keep.size <= 2002 and {31_337, 77_001} <= set(keep) and np.all(np.diff(keep) > 0)


def _payload(page: str) -> dict:
    text = re.search(r'<script id="hd-data" type="application/json">(.*?)</script>', page, re.S).group(1)
    return json.loads(text.replace("<\\/", "</"))


def test_the_page_is_self_contained_and_carries_the_runs(folders):
    """No address outside the page (no src/href but data:, a policy that forbids loading anything),
    the bundled libraries' licences inside, and the run's joints and series as float32 of the run's
    values (2 micrometres at 25 m from the tow point)."""
    run = viewer.read_run(folders / "engaged", label="a </script> label")
    page = viewer.view_html([run])
    assert not [m for m in re.findall(r'(?:src|href)\s*=\s*"([^"]*)"', page) if not m.startswith("data:")]
    assert "default-src 'none'" in page
    assert "Copyright © 2010-2026 three.js authors" in page and "Leon Sorokin" in page
    assert page.count("</script>") == 3  # the data, the libraries, the viewer: the label's is escaped
    data = _payload(page)
    (r,) = data["runs"]
    assert r["label"] == "a </script> label" and r["model"] == "engagement" and r["outcome"]["result"] == "captured"
    joints = np.frombuffer(base64.b64decode(r["frames"]["joints"]), "<f4").reshape(-1, 3)
    count = np.frombuffer(base64.b64decode(r["frames"]["count"]), "<u2")
    assert np.array_equal(count, run.joint_count) and np.allclose(joints, run.joints_m, rtol=0, atol=2e-6)
    load = np.frombuffer(base64.b64decode(r["series"]["probe_load_n"]), "<f4")
    assert np.allclose(load, run.columns["probe_load_n"], rtol=1e-6, atol=1e-3)


def test_view_command_writes_one_page_of_several_runs(folders, tmp_path, capsys):
    out = tmp_path / "both.html"
    code = cli.main(["view", str(folders / "fixed"), str(folders / "engaged"), "--out", str(out), "--layout", "side",
                     "--frame-rate", "20", "--json"])
    report = json.loads(capsys.readouterr().out)
    assert code == 0 and report["bytes"] == out.stat().st_size and [r["max_links"] for r in report["runs"]] == [6, 20]
    data = _payload(out.read_text())
    assert data["layout"] == "side" and [r["label"] for r in data["runs"]] == ["tiny-swing", "engage-response-20"]
    frames = np.frombuffer(base64.b64decode(data["runs"][1]["frames"]["t"]), "<f8")
    assert np.allclose(np.diff(frames)[:-1], 0.05, atol=1e-9)  # 20 frames per simulated second


def test_a_window_keeps_the_output_times_inside_it(folders, tmp_path, capsys):
    """--start/--end keep the output times in [start, end] with their own joints (the window
    crosses the first merge at 2.68 s: 21 joints, then 20)."""
    run = viewer.read_run(folders / "engaged")
    part = run.between(2.5, 3.0)
    inside = (run.t_s >= 2.5) & (run.t_s <= 3.0)
    assert np.array_equal(part.t_s, run.t_s[inside]) and set(part.joint_count) == {21, 20}
    offsets = np.concatenate([[0], np.cumsum(run.joint_count)])
    i = int(np.flatnonzero(inside)[-1])
    assert np.array_equal(part.joints_m[-part.joint_count[-1]:], run.joints_m[offsets[i]:offsets[i + 1]])
    out = tmp_path / "part.html"
    assert cli.main(["view", str(folders / "engaged"), "--start", "2.5", "--end", "3", "--out", str(out), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)["runs"][0]
    assert (report["t_start_s"], report["t_end_s"], report["output_times"]) == (2.5, 3.0, int(inside.sum()))
    code = cli.main(["view", str(folders / "engaged"), "--start", "9", "--out", str(tmp_path / "none.html")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "holds no output time" in err and not (tmp_path / "none.html").exists()


def test_simulate_view_writes_the_page_with_the_run(tmp_path, capsys):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    code = cli.main(["simulate", str(path), "--out", str(tmp_path / "run"), "--view"])
    assert code == 0 and f"wrote {tmp_path / 'run' / 'view.html'}" in capsys.readouterr().out
    assert _payload((tmp_path / "run" / "view.html").read_text())["runs"][0]["label"] == "tiny-swing"


def test_a_campaigns_runs_run_again_are_its_runs(tmp_path):
    """montecarlo --view runs the smallest, median and largest peak offset again from campaign.json
    and the seeds: their statistics are runs.csv's (10 significant digits in the file)."""
    from hosedrogue.studies.campaign import run_campaign
    from hosedrogue.viewer.campaign import representative_runs, rerun, write_campaign_view

    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    summary = run_campaign(str(path), 5, tmp_path / "mc", scheduler="synchronous", progress=False)
    picks = representative_runs(summary)
    values = sorted(summary.runs["peak_radial_m"])
    assert [p["why"] for p in picks] == ["smallest", "median", "largest"]
    assert [p["value"] for p in picks] == [values[0], values[2], values[4]]
    again = rerun(summary.settings, picks[2]["seed"], picks[2]["controller"])
    assert again.statistics()["peak_radial_m"] == pytest.approx(values[4], rel=1e-9)
    page, shown = write_campaign_view(summary, tmp_path / "mc" / "view.html", tmp_path / "mc" / "view")
    assert len(_payload(page.read_text())["runs"]) == 3
    assert all(viewer.read_run(p["folder"]).label == "tiny-swing" for p in shown)


def test_montecarlo_view_writes_the_campaigns_page(tmp_path, capsys):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    out = tmp_path / "mc"
    code = cli.main(["montecarlo", str(path), "--runs", "3", "--scheduler", "synchronous", "--quiet", "--out", str(out),
                     "--view"])
    assert code == 0 and f"wrote {out / 'view.html'} (run " in capsys.readouterr().out
    labels = [r["label"] for r in _payload((out / "view.html").read_text())["runs"]]
    assert len(labels) == 3 and all(label.startswith("run ") for label in labels)
    assert len(list((out / "view").glob("run_*_none/hose.npz"))) == 3
