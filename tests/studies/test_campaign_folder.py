"""A campaign folder owned by one campaign at a time, and every row of it checked on resume.

Faults of a careless or hostile user: two campaigns started together on one folder, rows of
another campaign (run index out of range, another seed, a run twice), bytes that are not text,
a folder of an earlier version that wrote infinities as ``Infinity``. Each must end in one line
naming the file, line and field, with the folder unchanged, or in the uninterrupted campaign's
result; campaign.json and summary.json must be strict JSON.
"""

import fcntl
import json
import os
import shutil
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from hosedrogue.errors import ParameterError
from hosedrogue.studies.campaign import run_campaign
from hosedrogue.studies.seeds import run_seed
from test_campaign import TINY  # 6 links, 3 s, turbulence on from 0.5 s for 2 s

RUNS = 6


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = tmp_path_factory.mktemp("scenarios") / "tiny.toml"
    path.write_text(TINY)
    return str(path)


@pytest.fixture(scope="module")
def references(tiny, tmp_path_factory):
    """Uninterrupted campaigns of seeds 0 and 5, each alone in its folder."""
    refs = {}
    for seed in (0, 5):
        out = tmp_path_factory.mktemp(f"ref{seed}")
        run_campaign(tiny, RUNS, out, seed=seed, scheduler="synchronous", progress=False)
        refs[seed] = out
    return refs


def folder_bytes(out: Path) -> dict:
    return {p.name: p.read_bytes() for p in sorted(Path(out).iterdir()) if p.is_file()}


def strict_json(path: Path):
    def refuse(name):
        raise AssertionError(f"{path.name}: non-standard JSON constant {name}")
    return json.loads(path.read_text(), parse_constant=refuse)


# --- one owner -----------------------------------------------------------------------------------
def test_two_campaigns_started_together_one_runs_one_is_refused(tiny, references, tmp_path):
    """Threads of one process: flock locks belong to open files, so two threads conflict as two
    processes do (tools/campaign_race.py repeats it with processes)."""
    for attempt in range(3):
        out = tmp_path / f"race{attempt}"
        barrier = threading.Barrier(2)
        outcome = {}

        def start(seed):
            barrier.wait()
            try:
                run_campaign(tiny, RUNS, out, seed=seed, scheduler="synchronous", progress=False)
                outcome[seed] = "ran"
            except ParameterError as exc:
                outcome[seed] = str(exc)

        threads = [threading.Thread(target=start, args=(s,)) for s in (0, 5)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        ran = [s for s, o in outcome.items() if o == "ran"]
        assert len(ran) == 1, outcome
        refused = outcome[5 - ran[0]]
        assert "\n" not in refused and ("another campaign" in refused or "different settings" in refused)
        for name in ("campaign.json", "runs.csv", "summary.json", "summary.csv"):
            assert (out / name).read_bytes() == (references[ran[0]] / name).read_bytes(), name


def test_a_held_folder_is_refused_naming_its_owner_and_left_unchanged(tiny, references, tmp_path):
    out = shutil.copytree(references[0], tmp_path / "out")
    before = folder_bytes(out)
    fd = os.open(out / ".lock", os.O_RDWR)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(ParameterError, match=r"another campaign \(pid \d+ on .+\) is using it"):
            run_campaign(tiny, RUNS, out, scheduler="synchronous", progress=False)
    finally:
        os.close(fd)
    assert folder_bytes(out) == before


@pytest.mark.subprocess
def test_a_killed_owner_leaves_no_stuck_lock(tiny, references, tmp_path):
    """The owner is SIGKILLed while it holds the folder: the next campaign takes it at once."""
    out = tmp_path / "out"
    out.mkdir()
    code = ("import fcntl, os, sys, time; fd = os.open(sys.argv[1], os.O_RDWR | os.O_CREAT); "
            "fcntl.flock(fd, fcntl.LOCK_EX); print('held', flush=True); time.sleep(60)")
    proc = subprocess.Popen([sys.executable, "-c", code, str(out / ".lock")], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "held"
        with pytest.raises(ParameterError, match="another campaign"):
            run_campaign(tiny, RUNS, out, scheduler="synchronous", progress=False)
    finally:
        proc.kill()
        proc.wait()
    run_campaign(tiny, RUNS, out, scheduler="synchronous", progress=False)
    assert (out / "summary.json").read_bytes() == (references[0] / "summary.json").read_bytes()


# --- rows checked on resume ----------------------------------------------------------------------
def _rows(out):
    return (Path(out) / "runs.csv").read_bytes().splitlines(keepends=True)


def _foreign(line: bytes, column: int, value: str) -> bytes:
    fields = line.decode().rstrip("\n").split(",")
    fields[column] = value
    return (",".join(fields) + "\n").encode()


FOREIGN = {
    "run index past the end": (lambda rows: rows + [_foreign(rows[1], 0, "999")], "run = 999"),
    "negative run index": (lambda rows: rows + [_foreign(rows[1], 0, "-3")], "run = -3"),
    "a run twice": (lambda rows: rows + [rows[2]], "has a row already"),
    "another seed": (lambda rows: rows[:3] + [_foreign(rows[3], 2, str(run_seed(5, 2)))] + rows[4:], "seed = "),
    "another controller": (lambda rows: rows + [_foreign(rows[1], 1, "lqr")], "controller = 'lqr'"),
    "bytes that are not UTF-8": (lambda rows: rows + [b"\xff\xfe\x00garbage\n"], "not UTF-8"),
}


@pytest.mark.parametrize("case", list(FOREIGN))
def test_a_foreign_or_corrupt_row_is_named_in_one_line_and_never_counted(tiny, references, tmp_path, case):
    edit, words = FOREIGN[case]
    out = shutil.copytree(references[0], tmp_path / "out")
    rows = _rows(out)
    (out / "runs.csv").write_bytes(b"".join(edit(rows)))
    before = folder_bytes(out)
    with pytest.raises(ParameterError) as info:
        run_campaign(tiny, RUNS, out, scheduler="synchronous", progress=False)
    message = str(info.value)
    assert "\n" not in message and "runs.csv, line " in message and words in message, message
    assert folder_bytes(out) == before  # nothing counted, nothing rewritten


def test_rows_of_a_campaign_with_another_seed_are_refused(tiny, references, tmp_path):
    """campaign.json of seed 0 beside rows of seed 5 (the folder two unlocked campaigns left)."""
    out = shutil.copytree(references[5], tmp_path / "out")
    shutil.copy(references[0] / "campaign.json", out / "campaign.json")
    with pytest.raises(ParameterError, match=r"runs.csv, line 2: .*seed = \d+ is not run 0's seed"):
        run_campaign(tiny, RUNS, out, scheduler="synchronous", progress=False)


# --- strict JSON ---------------------------------------------------------------------------------
def test_campaign_and_summary_are_strict_json_and_resume(tiny, references, tmp_path):
    ref = references[0]
    settings = strict_json(ref / "campaign.json")
    strict_json(ref / "summary.json")
    # the paper's case: no limit on the reel's force and rigid links, written null (inf)
    assert settings["scenario"]["hose"]["axial_stiffness_n"] is None
    out = shutil.copytree(ref, tmp_path / "out")
    summary = run_campaign(tiny, RUNS, out, scheduler="synchronous", progress=False)
    assert summary.new_runs == 0
    assert (out / "summary.json").read_bytes() == (ref / "summary.json").read_bytes()


def test_a_folder_of_an_earlier_version_with_infinity_resumes(tiny, references, tmp_path):
    out = shutil.copytree(references[0], tmp_path / "out")
    old = json.loads((out / "campaign.json").read_text())
    old["scenario"]["hose"]["axial_stiffness_n"] = float("inf")
    (out / "campaign.json").write_text(json.dumps(old, indent=2))  # Infinity, as before
    assert "Infinity" in (out / "campaign.json").read_text()
    summary = run_campaign(tiny, RUNS, out, scheduler="synchronous", progress=False)
    assert summary.new_runs == 0


def test_the_viewer_rebuilds_the_scenario_from_strict_json(references):
    from hosedrogue.scenarios import scenario_from_dict, load_scenario

    settings = json.loads((references[0] / "campaign.json").read_text())
    rebuilt = scenario_from_dict(settings["scenario"])  # null reads as inf
    assert rebuilt.params.hose.axial_stiffness_n == float("inf")
    assert rebuilt.params == load_scenario(settings["scenario_source"]).params
