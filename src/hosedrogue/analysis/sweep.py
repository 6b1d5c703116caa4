"""Steady drag and balance position over a grid of altitudes and airspeeds (paper Fig. 3).

Each grid point is an independent equilibrium solve; along each altitude the previous airspeed's
solution is *not* reused, so every point stands on its own (no path dependence).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

import numpy as np

from ..spec.params import PAPER, ParameterError, Params
from .equilibrium import EquilibriumError, solve_equilibrium

#: Default grid: the paper's Fig. 3 spans these altitudes [m] and airspeeds [m/s].
DEFAULT_ALTITUDES_M = (2000.0, 4000.0, 6000.0, 8000.0, 10000.0)
DEFAULT_AIRSPEEDS_M_S = tuple(float(v) for v in np.arange(100.0, 250.0 + 1e-9, 10.0))

COLUMNS = (
    "altitude_m", "airspeed_m_s", "drogue_x_m", "drogue_y_m", "drogue_z_m", "drogue_drag_n",
    "tow_force_x_n", "tow_force_y_n", "tow_force_z_n", "balance_ratio", "converged",
)


@dataclass(frozen=True)
class SweepResult:
    """Result of :func:`steady_sweep`: one row per (altitude, airspeed) with the columns COLUMNS."""

    altitudes_m: np.ndarray  #: altitudes of the grid [m]
    airspeeds_m_s: np.ndarray  #: airspeeds of the grid [m/s]
    rows: list[dict]  #: one dict per grid point, keys COLUMNS (SI units in the names)

    def to_dataframe(self):
        import pandas as pd

        return pd.DataFrame(self.rows, columns=list(COLUMNS))

    def to_csv(self, path):
        self.to_dataframe().to_csv(path, index=False, float_format="%.10g")
        return path

    def grid(self, column: str) -> np.ndarray:
        """(altitudes, airspeeds) array of one column."""
        df = self.to_dataframe()
        return df.pivot(index="altitude_m", columns="airspeed_m_s", values=column).to_numpy()


def _check_grid(name: str, values: Iterable[float], lo: float, hi: float, unit: str,
                lo_open: bool = False) -> np.ndarray:
    arr = np.asarray(list(values), dtype=float)
    below = arr <= lo if lo_open else arr < lo
    if arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(below) or np.any(arr > hi):
        left = "(" if lo_open else "["
        raise ParameterError(
            f"{name} = {arr.tolist()!r}: must be a non-empty list of numbers in {left}{lo:g}, {hi:g}] {unit}")
    return arr


def steady_sweep(params: Params = PAPER, altitudes_m=DEFAULT_ALTITUDES_M,
                 airspeeds_m_s=DEFAULT_AIRSPEEDS_M_S, progress=None) -> SweepResult:
    """Balance position at every (altitude, airspeed).

    Parameters
    ----------
    params : Params
        Parameter set whose flight condition is replaced at each grid point.
    altitudes_m : sequence of float
        Altitudes [m], 0-20000.
    airspeeds_m_s : sequence of float
        True airspeeds [m/s], > 0 and <= 400.
    progress : callable, optional
        Called with no arguments once per grid point.

    Returns
    -------
    SweepResult
    """
    alts = _check_grid("altitudes", altitudes_m, 0.0, 20000.0, "m")
    vels = _check_grid("airspeeds", airspeeds_m_s, 0.0, 400.0, "m/s", lo_open=True)
    rows = []
    for h in alts:
        for v in vels:
            p = params.replace(flight={"altitude_m": float(h), "airspeed_m_s": float(v)})
            try:
                eq = solve_equilibrium(p)
                x, y, z = eq.drogue_position_m
                fx, fy, fz = eq.tow_force_n
                rows.append(dict(zip(COLUMNS, (h, v, x, y, z, eq.drogue_drag_magnitude_n, fx, fy, fz,
                                               eq.balance_ratio, True))))
            except EquilibriumError:
                rows.append(dict(zip(COLUMNS, (h, v) + (np.nan,) * 8 + (False,))))
            if progress is not None:
                progress()
    return SweepResult(alts, vels, rows)
