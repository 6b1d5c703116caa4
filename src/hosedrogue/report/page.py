"""The HTML page of the report: one self-contained file (inline CSS, no scripts, no external
resources; figures are files beside it, referenced by relative paths)."""

from __future__ import annotations

import datetime as _dt

from ..version import __version__
from .markup import esc

__all__ = ["CSS", "FRONT", "render_page"]

#: Sections shown first, in this order (by anchor); every other section follows in the order
#: the sections were built.
FRONT = ("comparison", "table1", "differences")

CSS = """
body{font-family:Helvetica,Arial,sans-serif;max-width:1180px;margin:0 auto;padding:0 18px 60px;color:#222;line-height:1.45}
h1{font-size:1.6em;margin-bottom:.2em} h2{border-bottom:2px solid #ccd;padding-bottom:.15em;margin-top:1.8em}
table{border-collapse:collapse;margin:.6em 0 1em;font-size:.86em} th,td{border:1px solid #ccc;padding:3px 7px;text-align:left;vertical-align:top}
th{background:#eef} tr:nth-child(even) td{background:#fafafa} caption{text-align:left;font-weight:bold}
figure{margin:1em 0 1.6em} figure img{max-width:100%;border:1px solid #ddd} figcaption{font-size:.9em;color:#333}
.data{color:#666;font-size:.9em} .ok{color:#176b1e;font-weight:bold} .diff{color:#a33;font-weight:bold}
.banner{background:#fff3cd;border:2px solid #d39e00;padding:10px 14px;font-size:1.1em;margin:1em 0}
.meta{color:#555;font-size:.9em} code{background:#f3f3f3;padding:0 3px} nav a{margin-right:.8em}
"""


def _banner(settings) -> str:
    if not settings.fast:
        return ""
    return ('<div class="banner" id="fast-banner"><b>FAST VERSION.</b> This report was built with '
            "<code>--fast</code>: coarser Fig. 3 grid, shorter turbulence runs "
            f"({settings.run_duration_s:g} s), fewer convergence steps and link counts, "
            f"{settings.spread_seeds} turbulence realisations, a coarser animation, the accuracy study up to "
            f"{max(settings.accuracy_links)} links and the long-runs study with {len(settings.long_run_seeds)} seed(s) "
            f"capped at {settings.long_run_cap_s:g} s. Numbers differ "
            "slightly from the full report; run <code>hosedrogue reproduce</code> without "
            "<code>--fast</code> for the reference version.</div>")


def _ordered(sections) -> list:
    front = [s for anchor in FRONT for s in sections if s.anchor == anchor]
    return front + [s for s in sections if s.anchor not in FRONT]


def _partial_banner(partial) -> str:
    if partial is None:
        return ""
    return ('<div class="banner" id="partial-banner"><b>PARTIAL REPORT.</b> Built with <code>--only</code>: '
            f"only the sections {esc(', '.join(partial))} (and those they need); run <code>hosedrogue "
            "reproduce</code> without <code>--only</code> for the whole report.</div>")


def render_page(out, settings, elapsed_s: float, partial=None) -> str:
    """The whole page.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report: its sections and summary points.
    settings : hosedrogue.report.settings.ReportSettings
        Build settings (the fast version gets a banner and a marked title).
    elapsed_s : float
        Wall-clock time of the build [s], shown in the header.
    partial : sequence of str, optional
        The keys of the sections built when only some were (``reproduce --only``): a banner says so.

    Returns
    -------
    str
        The HTML document.
    """
    sections = _ordered(out.sections)
    nav = "".join(f'<a href="#{s.anchor}">{s.nav}</a>' for s in sections)
    body = "".join(s.html for s in sections)
    when = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    title = "hosedrogue: reproduction of Wu et al. (2018), Sec. 2.3 and 3" + (" (FAST VERSION)" if settings.fast else "")
    return (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        f"<title>{esc(title)}</title><style>{CSS}</style></head><body>"
        f"<h1>{esc(title)}</h1>"
        f"<p class=meta>Wu L., Sun Y., Huang B., Liu J., <i>Modeling Method and Control Strategy for Hose-Drogue "
        f"Aerial Refueling System</i>, Trans. Nanjing Univ. Aeronaut. Astronaut. 35(2), 2018. Every result below is "
        f"regenerated from this project's own model (hosedrogue {esc(__version__)}, {esc(settings.name)} build, "
        f"{elapsed_s:.0f} s, {when}). Frame S_p: origin at the tow point, x forward, y right, z down; SI units.</p>"
        f"{_banner(settings)}{_partial_banner(partial)}"
        '<section id="summary"><h2>Summary</h2><ul>' + "".join(f"<li>{esc(s)}</li>" for s in out.summary) + "</ul>"
        '<p class=meta>Headline numbers: <a href="report.json">report.json</a>.</p></section>'
        f"<nav>{nav}</nav>{body}</body></html>\n"
    )
