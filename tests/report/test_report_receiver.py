"""Report section "Receiver aircraft" (hosedrogue.report.receiver), built alone in its fast version."""

import json

from hosedrogue.aircraft.published import TABLE_3_6_2
from hosedrogue.studies.receiver import SCENARIOS


def test_receiver_section_alone(fast_report):
    """The fast section: its files, the fast note, both campaigns of FAST.docking_runs runs on the same
    seeds, and report.json strict. (The section as the shared fast build built it: it needs no
    other section, tests/conftest.py.)"""
    from hosedrogue.report import receiver
    from hosedrogue.report.settings import FAST

    out, tmp_path = fast_report.folder, fast_report.dir
    (section,) = [s.html for s in out.sections if s.anchor == "receiver-aircraft"]
    assert "Fast version" in section and "table-receiver-capture" in section
    for name in ("receiver_trim.png", "receiver_trim.csv", "receiver_trim_curve.csv", "receiver_miss_cdf.png",
                 "receiver_runs.csv"):
        assert (tmp_path / name).stat().st_size > 0, name
    rec = out.headline["receiver"]
    assert rec["trim_points_within"] == rec["trim_points"] == len(TABLE_3_6_2)
    assert all(rec["capture"][n]["runs"] == FAST.docking_runs for n in SCENARIOS)
    for n in SCENARIOS:
        assert json.loads((tmp_path / receiver.CAMPAIGNS / n / "campaign.json").read_text())
    json.dumps(rec, allow_nan=False)
