"""The tables' interpolation against scipy's RegularGridInterpolator (the same linear
interpolation and extrapolation, written independently), on every table of the F-16."""

import numpy as np
from scipy.interpolate import RegularGridInterpolator

from hosedrogue.aircraft.model_file import load_model


def _tables(model):
    seen = {}
    for terms in model.coefficients.values():
        for term in terms:
            if term.table is not None:
                seen[term.table.name] = term.table
    for name in ("idle", "military", "maximum"):
        seen[name] = getattr(model.engine, name)
    return seen.values()


def test_interpolation_and_extrapolation_match_scipy(rng):
    for table in _tables(load_model("f16")):
        ref = RegularGridInterpolator(table.breakpoints, table.values, method="linear", bounds_error=False,
                                      fill_value=None)
        lo = np.array([b[0] for b in table.breakpoints])
        hi = np.array([b[-1] for b in table.breakpoints])
        span = hi - lo
        for point in rng.uniform(lo - 0.2 * span, hi + 0.2 * span, size=(200, len(lo))):
            if table.odd_in is not None:
                point = np.abs(point)
            got = table(dict(zip(table.axes, point)))
            # 1e-12 of the table's values: two orders of operations in double precision
            assert abs(got - ref(point)[0]) <= 1e-12 * max(1.0, np.abs(table.values).max()), table.name


def test_odd_tables_are_odd_in_sideslip(rng):
    model = load_model("f16")
    cl = next(t.table for t in model.coefficients["Cl"] if t.table is not None and t.table.name == "cl")
    for alpha, beta in rng.uniform([-10, -30], [45, 30], size=(50, 2)):
        assert cl({"alpha": alpha, "beta": -beta}) == -cl({"alpha": alpha, "beta": beta})
