"""Formatting of numbers and HTML fragments for the report page (no file writing here)."""

from __future__ import annotations

import html
import math

import numpy as np

__all__ = ["fmt", "ratio", "esc", "html_table", "figure_html", "viewer_html", "slash_join"]


def fmt(x, digits: int = 4) -> str:
    """A number for the page.

    Parameters
    ----------
    x : float, str or None
        The value; a string is returned unchanged, None and non-finite numbers as ``"n/a"``.
    digits : int
        Significant digits.

    Returns
    -------
    str
        ``digits`` significant digits, scientific notation outside [1e-3, 1e5).
    """
    if x is None:
        return "n/a"
    if isinstance(x, str):
        return x
    x = float(x)
    if not math.isfinite(x):
        return "n/a"
    if x == 0.0:
        return "0"
    if 1e-3 <= abs(x) < 1e5:
        return f"{x:.{digits}g}"
    return f"{x:.{digits - 1}e}"


def ratio(ours: float, paper: float) -> float:
    """Ratio ours / paper.

    Parameters
    ----------
    ours : float
        This project's value.
    paper : float
        The paper's value, same unit.

    Returns
    -------
    float
        ``ours / paper``; NaN if ``paper`` is zero.
    """
    return float(ours) / float(paper) if paper not in (0, 0.0) else float("nan")


def esc(x) -> str:
    """``str(x)`` escaped for HTML.

    Parameters
    ----------
    x : object
        Anything with a string form.

    Returns
    -------
    str
        The escaped text.
    """
    return html.escape(str(x))


def slash_join(values, spec: str) -> str:
    """Values formatted with ``spec`` and joined by ``"/"`` (e.g. ``5.61/5.53/5.50``).

    Parameters
    ----------
    values : iterable of float
        The values.
    spec : str
        A format spec such as ``".2f"``.

    Returns
    -------
    str
        The joined text.
    """
    return "/".join(f"{v:{spec}}" for v in values)


def html_table(headers, rows, table_id: str | None = None, caption: str | None = None) -> str:
    """An HTML table.

    Parameters
    ----------
    headers : sequence
        Column headings.
    rows : sequence of sequence
        Cells; floats are formatted with :func:`fmt`, everything is escaped unless given as
        ``("html", text)``.
    table_id : str, optional
        The table's ``id`` attribute.
    caption : str, optional
        Caption (HTML, not escaped).

    Returns
    -------
    str
        The ``<table>`` element.
    """
    def cell(v, tag):
        if isinstance(v, tuple) and len(v) == 2 and v[0] == "html":
            return f"<{tag}>{v[1]}</{tag}>"
        return f"<{tag}>{esc(fmt(v) if isinstance(v, (float, np.floating)) else v)}</{tag}>"

    tid = f' id="{table_id}"' if table_id else ""
    cap = f"<caption>{caption}</caption>" if caption else ""
    head = "".join(cell(h, "th") for h in headers)
    body = "".join("<tr>" + "".join(cell(v, "td") for v in r) + "</tr>" for r in rows)
    return f'<table{tid}>{cap}<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>'


def viewer_html(fig_id: str, page: str, title: str, text: str, size_mb: float) -> str:
    """A ``<figure>`` holding a viewer page (:mod:`hosedrogue.viewer`) in a frame, with a link to
    open it on its own and its size.

    Parameters
    ----------
    fig_id : str
        The figure's ``id`` attribute.
    page : str
        The viewer's HTML file, relative to the report's page.
    title : str
        Bold first words of the caption (escaped).
    text : str
        Caption text (HTML, not escaped).
    size_mb : float
        The viewer file's size [MB].

    Returns
    -------
    str
        The ``<figure>`` element.
    """
    return (f'<figure id="{fig_id}" class=viewer><iframe src="{esc(page)}" title="{esc(title)}" loading="lazy" '
            'style="width:100%;height:720px;border:1px solid #ccc"></iframe>'
            f"<figcaption><b>{esc(title)}.</b> {text} <span class=data>Open it on its own: "
            f'<a href="{esc(page)}">{esc(page)}</a> ({size_mb:.1f} MB, self-contained).</span></figcaption></figure>')


def figure_html(fig_id: str, png: str, title: str, text: str, csvs: tuple[str, ...]) -> str:
    """A ``<figure>`` with its image, caption and links to the data behind it.

    Parameters
    ----------
    fig_id : str
        The figure's ``id`` attribute.
    png : str
        Image file, relative to the page.
    title : str
        Bold first words of the caption (escaped).
    text : str
        Caption text (HTML, not escaped).
    csvs : tuple of str
        Data files, relative to the page.

    Returns
    -------
    str
        The ``<figure>`` element.
    """
    data = ", ".join(f'<a href="{esc(c)}">{esc(c)}</a>' for c in csvs)
    return (f'<figure id="{fig_id}"><img src="{esc(png)}" alt="{esc(title)}">'
            f"<figcaption><b>{esc(title)}.</b> {text} <span class=data>Data: {data}.</span>"
            f"</figcaption></figure>")
