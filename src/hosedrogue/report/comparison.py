"""Every paper number beside this project's: the comparison table of the report.

Sections add rows while they run (:meth:`Comparison.add`); :func:`build` writes the table
(``comparison.csv`` and the page's first section) after every other section.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .markup import esc, fmt, html_table, ratio

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["CLOSE", "Comparison", "agrees", "build"]

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


def build(out: ReportFolder, settings: ReportSettings) -> None:
    """Write ``comparison.csv`` and the comparison section from every row added so far.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written; its ``comparison`` holds the rows.
    settings : hosedrogue.report.settings.ReportSettings
        Build settings (unused; every section takes them).

    Returns
    -------
    None
    """
    out.csv(out.comparison.dataframe(), "comparison.csv")
    rows = []
    for r in out.comparison.rows:
        cls = "ok" if r["ratio_text"] == "inside range" or agrees(r["ratio"]) else "diff"
        rows.append((r["section"], r["quantity"], r["unit"], r["paper"], fmt(r["ours"]),
                     ("html", f'<span class="{cls}">{esc(r["ratio_text"])}</span>'),
                     "reproduced" if cls == "ok" else r["note"]))
    out.section("comparison", "paper vs ours", (
        '<section id="comparison"><h2>Every paper number beside this project\'s</h2>'
        f"<p>Paper value, this project's value, their ratio (green: within {100 * CLOSE:.0f} % or inside the paper's "
        "range) and, for each large difference, the plain reason. Table 1's inputs are used unchanged "
        "(above); Fig. 3 and Fig. 4 give no numbers in the paper's text and are compared by their stated "
        "trends in their sections. No number has been adjusted to match.</p>"
        + html_table(["source", "quantity", "unit", "paper", "this project", "ratio", "explanation"], rows,
                     table_id="table-comparison")
        + '<p class=data>Data: <a href="comparison.csv">comparison.csv</a>.</p></section>'
    ))
