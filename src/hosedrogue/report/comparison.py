"""Every paper number beside this project's: the rows of the report's comparison table.

Sections add rows while they run (:meth:`Comparison.add`); :mod:`.paper_table` writes the table
(``comparison.csv`` and the page's first section) after every other section. This module holds
data only: it writes nothing.
"""

from __future__ import annotations

import math

from .markup import fmt, ratio

__all__ = ["CLOSE", "Comparison", "agrees"]

#: A paper value and ours agree "closely" within this relative difference (ratio in [0.9, 1.1]):
#: the paper prints 3-4 significant digits and reads some values off figures.
CLOSE = 0.10


def agrees(r: float, tol: float = CLOSE) -> bool:
    """Whether a ratio ours / paper is within ``tol`` of 1.

    Parameters
    ----------
    r : float
        Ratio ours / paper [-].
    tol : float
        Allowed relative difference [-]; :data:`CLOSE` by default.

    Returns
    -------
    bool
        True if ``r`` is finite and ``|r - 1| <= tol``.
    """
    return math.isfinite(r) and abs(r - 1.0) <= tol


class Comparison:
    """Every paper number beside this project's, collected while the sections run."""

    def __init__(self):
        self.rows: list[dict] = []

    def add(self, section: str, quantity: str, unit: str, paper, ours: float, note: str) -> float:
        """Add one row.

        Parameters
        ----------
        section : str
            Where the paper gives the value (e.g. ``"Table 3"``).
        quantity : str
            What the value is.
        unit : str
            Its unit (``"-"`` or ``""`` if none).
        paper : float or tuple of float
            The paper's value, or its (low, high) range, in ``unit``.
        ours : float
            This project's value, in ``unit``.
        note : str
            The plain reason of a difference (shown when the two do not agree).

        Returns
        -------
        float
            The ratio ours / paper; for a range: 1 inside it, else ours over the nearer end.
        """
        if isinstance(paper, tuple):
            lo, hi = paper
            r = 1.0 if lo <= ours <= hi else (ours / hi if ours > hi else ours / lo)
            paper_txt = f"{fmt(lo)} to {fmt(hi)}"
            ratio_txt = "inside range" if r == 1.0 else f"{fmt(r, 3)} x nearer end"
        else:
            r = ratio(ours, paper)
            paper_txt = fmt(paper)
            ratio_txt = fmt(r, 3)
        self.rows.append(dict(section=section, quantity=quantity, unit=unit, paper=paper_txt,
                              ours=float(ours), ratio=r, ratio_text=ratio_txt, note=note))
        return r

    def dataframe(self):
        """The rows as a table.

        Returns
        -------
        pandas.DataFrame
            Columns section, quantity, unit, paper, ours, ratio, note.
        """
        import pandas as pd

        return pd.DataFrame(self.rows, columns=["section", "quantity", "unit", "paper", "ours", "ratio", "note"])
