"""The per-run statistics of hosedrogue.results.statistics: one window rule, and the compiled accumulator
(batch) computing what the numpy pass over a saved series (campaign, report) computes."""

import math

import numpy as np

from hosedrogue.results import statistics as metrics


def test_window_edges_absorb_rounding_of_sample_times():
    # output times t = k h are rounded either way; the rule counts the nominal start, not the end
    t = np.array([10.0 - 1e-14, 10.0 + 1e-14, 20.0, 30.0 - 1e-14, 30.0 + 1e-14])
    assert metrics.in_window(t, (10.0, 30.0)).tolist() == [True, True, True, False, False]
    assert [metrics.in_window_at(x, 10.0, 30.0) for x in t] == [True, True, True, False, False]
    assert metrics.in_window(t, (0.0, math.inf)).all()


def test_accumulator_equals_the_pass_over_a_saved_series():
    """Same formulas; only the summation order differs (time order vs numpy's pairwise sum), so
    the RMS values agree to a few ulps (1e-14 relative) and everything else exactly."""
    rng = np.random.default_rng(5)
    n = 2001
    t = np.arange(n) * 0.01
    off = np.zeros((n, 3))
    off[:, 1:] = 0.08 * rng.standard_normal((n, 2))
    u = 50.0 * rng.standard_normal((n, 2))
    radii = (0.1, 0.305)
    window = (5.0, 15.0)
    expected = metrics.window_statistics(t, off, u, window, radii)

    acc = metrics.new_accumulator(len(radii))
    r = np.asarray(radii)
    for k in np.flatnonzero(metrics.in_window(t, window)):
        metrics.accumulate(acc, off[k, 1], off[k, 2], u[k, 0], u[k, 1], r)
    out = np.empty(len(metrics.statistic_units(radii)))
    metrics.finish(acc, out)
    got = dict(zip(metrics.statistic_units(radii), out))
    assert list(got) == list(expected)
    for column, value in expected.items():
        if column.startswith("rms_"):
            assert abs(got[column] - value) <= 1e-14 * value, column
        else:
            assert got[column] == value, column


def test_empty_window_gives_nan():
    t = np.arange(5) * 0.1
    row = metrics.window_statistics(t, np.zeros((5, 3)), np.zeros((5, 2)), (10.0, 20.0), (0.1,))
    assert all(math.isnan(v) for v in row.values())
    out = np.empty(10)
    metrics.finish(metrics.new_accumulator(1), out)
    assert np.isnan(out).all()
