"""Table cells and report.json entries of one docking campaign, shared by the Docking section's
tables (the main grid, the closure-speed and the force-limit studies)."""

from __future__ import annotations

from .markup import esc

__all__ = ["CAMPAIGNS", "by_result_text", "capture_cells", "capture_record"]

#: The campaigns' folder inside the report folder (one subfolder per cell).
CAMPAIGNS = "docking/campaigns"


def by_result_text(row, columns) -> str:
    """The non-zero ``n_<result>`` counts of one table row, e.g. "captured 87, miss 113".

    Parameters
    ----------
    row : mapping
        One row of a capture table (counts in columns ``n_captured``, ``n_miss``, ...).
    columns : iterable of str
        The table's columns.

    Returns
    -------
    str
    """
    return ", ".join(f"{k[2:].replace('_', ' ')} {int(row[k])}" for k in columns if k.startswith("n_") and row[k])


def capture_cells(row, columns) -> tuple:
    """The HTML table cells campaign (a link to its summary.json), runs, capture rate [-], Wilson
    95 % interval [-] and the counts by result of one campaign row.

    Parameters
    ----------
    row : mapping
        One row of a capture table: ``campaign``, ``runs``, ``rate``, ``ci95_low``, ``ci95_high``
        and ``n_<result>`` counts.
    columns : iterable of str
        The table's columns.

    Returns
    -------
    tuple
        Five cells for :func:`hosedrogue.report.markup.html_table`.
    """
    link = f'<a href="{CAMPAIGNS}/{row["campaign"]}/summary.json">{esc(row["campaign"])}</a>'
    return (("html", link), int(row["runs"]), f"{row['rate']:.3f}", f"{row['ci95_low']:.3f} - {row['ci95_high']:.3f}",
            by_result_text(row, columns))


def capture_record(row, columns) -> dict:
    """A campaign row's capture block for report.json: campaign, rate, ci95, runs, by_result.

    Parameters
    ----------
    row : mapping
        One row of a capture table (as for :func:`capture_cells`).
    columns : iterable of str
        The table's columns.

    Returns
    -------
    dict
    """
    return {"campaign": row["campaign"], "rate": float(row["rate"]),
            "ci95": [float(row["ci95_low"]), float(row["ci95_high"])], "runs": int(row["runs"]),
            "by_result": {k[2:].replace("_", " "): int(row[k]) for k in columns if k.startswith("n_")}}
