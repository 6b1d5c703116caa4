"""The report's output folder: CSV, figure and JSON files, and the page fragments written so far.

Every file of the report is written through :class:`ReportFolder`, so the CSV format, the
figure resolution and the list of written files are set in one place.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from ..jsonio import plain
from .comparison import Comparison

__all__ = ["DPI", "PageSection", "ReportFolder"]

#: PNG resolution [dots per inch].
DPI = 110


@dataclass(frozen=True)
class PageSection:
    """One ``<section>`` of the page.

    Parameters
    ----------
    anchor : str
        The section's ``id`` (the navigation links to ``#anchor``).
    nav : str
        Its name in the navigation bar.
    html : str
        The ``<section>`` element.
    """

    anchor: str
    nav: str
    html: str


def _no_status(text: str) -> None:
    return None


@dataclass
class ReportFolder:
    """The output folder and what has been written to it so far.

    Only ``dir`` and ``status`` are given; the other fields start empty and collect what the
    sections write and add.

    Parameters
    ----------
    dir : Path
        The folder (must exist before writing).
    status : callable, optional
        ``status(text)`` shows a short progress note (the progress bar's postfix).

    Other Parameters
    ----------------
    files : list of str
        Names of the files written so far, in order (filled by the writing methods).
    comparison : Comparison
        The paper-vs-ours table the sections add rows to (:mod:`.comparison`).
    sections : list of PageSection
        The page's sections added so far (:meth:`section`).
    summary : list of str
        The points of the page's summary added so far (:meth:`summarize`).
    headline : dict
        The headline numbers of ``report.json`` recorded so far (:meth:`record`), in SI units
        named in their keys.
    """

    dir: Path
    status: Callable[[str], None] = _no_status
    files: list[str] = field(default_factory=list)
    comparison: Comparison = field(default_factory=Comparison)
    sections: list[PageSection] = field(default_factory=list)
    summary: list[str] = field(default_factory=list)
    headline: dict[str, Any] = field(default_factory=dict)

    def csv(self, df, name: str) -> str:
        """Write a table as CSV (10 significant digits, no index).

        Parameters
        ----------
        df : pandas.DataFrame
            The table; SI units in the column names.
        name : str
            File name inside the folder.

        Returns
        -------
        str
            ``name``.
        """
        df.to_csv(self.dir / name, index=False, float_format="%.10g")
        self.files.append(name)
        return name

    def figure(self, fig, name: str) -> str:
        """Save a figure as PNG at :data:`DPI`.

        Parameters
        ----------
        fig : matplotlib.figure.Figure
            The figure (from :mod:`hosedrogue.plotting`).
        name : str
            File name inside the folder.

        Returns
        -------
        str
            ``name``.
        """
        from ..plotting.figures import save_figure

        save_figure(fig, self.dir / name, dpi=DPI)
        self.files.append(name)
        return name

    def written(self, path: Path) -> str:
        """Register a file written by other code (e.g. the animation).

        Parameters
        ----------
        path : Path
            The file, inside the folder.

        Returns
        -------
        str
            Its name.
        """
        self.files.append(path.name)
        return path.name

    def section(self, anchor: str, nav: str, html: str) -> None:
        """Add a section of the page (shown in the order added, see :mod:`.page`).

        Parameters
        ----------
        anchor : str
            The section's ``id``.
        nav : str
            Its name in the navigation bar.
        html : str
            The ``<section>`` element.
        """
        self.sections.append(PageSection(anchor, nav, html))

    def summarize(self, text: str) -> None:
        """Add one point (plain text) to the page's summary, in the order the sections run.

        Parameters
        ----------
        text : str
            The point.
        """
        self.summary.append(text)

    def record(self, key: str, value) -> None:
        """Add headline numbers to ``report.json`` under ``key``.

        Parameters
        ----------
        key : str
            Top-level key.
        value : object
            Numbers (nested dicts and lists allowed), in SI units named in the keys.
        """
        self.headline[key] = value

    def write_json(self, headline: dict, name: str = "report.json") -> dict:
        """Write the headline numbers, non-finite values as null.

        Parameters
        ----------
        headline : dict
            The numbers.
        name : str
            File name inside the folder.

        Returns
        -------
        dict
            What was written (plain JSON types).
        """
        data = plain(headline)
        (self.dir / name).write_text(json.dumps(data, indent=2, allow_nan=False) + "\n")
        self.files.append(name)
        return data

    def write_text(self, text: str, name: str) -> str:
        """Write a UTF-8 text file (the page).

        Parameters
        ----------
        text : str
            The content.
        name : str
            File name inside the folder.

        Returns
        -------
        str
            ``name``.
        """
        (self.dir / name).write_text(text, encoding="utf-8")
        self.files.append(name)
        return name
