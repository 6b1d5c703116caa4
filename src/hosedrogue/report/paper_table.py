"""The report's closing section "paper vs ours": every row the sections added to the comparison
(:class:`.comparison.Comparison`), written as ``comparison.csv`` and as the page's first section."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .comparison import CLOSE, agrees
from .markup import esc, fmt, html_table

if TYPE_CHECKING:
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["build"]


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
