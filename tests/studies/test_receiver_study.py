"""The receiver aircraft's study (hosedrogue.studies.receiver): the trim check's table and the paired
comparison of the two receivers' misses."""

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from hosedrogue.aircraft.published import TABLE_3_6_2
from hosedrogue.studies.receiver import SCENARIOS, ReceiverCampaigns, trim_check


def test_trim_check_holds_every_book_point():
    """Every point of Table 3.6-2 rounds to the printed digits (tests/aircraft/test_trim.py checks
    the trim itself); the table carries the book's numbers unchanged and the curve spans its range."""
    check = trim_check(5)
    assert check.within == len(TABLE_3_6_2) == len(check.table)
    book = check.table[["airspeed_ft_s", "throttle_book", "alpha_deg_book", "elevator_deg_book"]].to_numpy()
    assert np.array_equal(book, np.array(TABLE_3_6_2))
    v = check.curve["airspeed_m_s"]
    assert v.size == 5 and v[0] == pytest.approx(130 * 0.3048) and v[-1] == pytest.approx(800 * 0.3048)
    # the curve at 130 ft/s is the book's first point's trim
    assert check.curve["throttle"][0] == pytest.approx(check.table["throttle"][0], abs=1e-9)


def test_paired_difference_is_the_paired_t_statistics():
    """mean / se of the paired misses is scipy's paired t statistic; a run without a miss on either side drops out."""
    rng = np.random.default_rng(1)
    a, b = rng.uniform(0.0, 0.2, 30), rng.uniform(0.0, 0.1, 30)
    a[3] = np.nan
    runs = pd.DataFrame({"run": range(30), "seed": range(30), f"miss_{SCENARIOS[0]}": a, f"miss_{SCENARIOS[1]}": b})
    p = ReceiverCampaigns({}, runs, {}).paired()
    keep = np.isfinite(a)
    t = stats.ttest_rel(a[keep], b[keep])
    assert p["runs"] == 29 and p["first_larger"] == int((a[keep] > b[keep]).sum())
    assert p["mean_m"] / p["se_m"] == pytest.approx(t.statistic, rel=1e-12)  # round-off
    assert p["mean_m"] == pytest.approx(np.mean(a[keep] - b[keep]), rel=1e-12)
    assert math.isnan(ReceiverCampaigns({}, runs.iloc[:1], {}).paired()["se_m"])
