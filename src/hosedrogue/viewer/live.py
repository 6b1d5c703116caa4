"""The live page of ``hosedrogue fly`` (docs/fly.md): the viewer's bundled libraries (three.js,
uPlot) and look, with a script that draws the frames a server streams (Server-Sent Events)
instead of a run baked into the page, a head-up display for the pilot, and the keyboard and
gamepad input it sends back (:mod:`hosedrogue.fly.server`).
"""

from __future__ import annotations

import html
import re

from ..version import __version__
from .page import _asset, _script_json

__all__ = ["live_html"]


def live_html(facts: dict) -> str:
    """The live page, served by the flight's server (it loads nothing from elsewhere).

    Parameters
    ----------
    facts : dict
        What the page shows besides the frames (:meth:`hosedrogue.fly.LiveFlight.facts`):
        scenario, duration [s], the receiver's sample time [s] and bounds, the probe's closure
        speed [m/s], capture radius [m] and closure window [m/s], the hose's and drogue's
        diameters [m].

    Returns
    -------
    str
        The HTML text.
    """
    title = f"hosedrogue fly: {facts.get('scenario', 'flight')}"
    parts = {"TITLE": html.escape(title), "VENDOR_CSS": _asset("vendor.min.css"), "VIEWER_CSS": _asset("viewer.css"),
             "LIVE_CSS": _asset("live.css"), "LICENSES": html.escape(_asset("THIRD-PARTY-LICENSES.txt")),
             "VERSION": __version__, "FACTS": _script_json({**facts, "title": title, "version": __version__}),
             "VENDOR_JS": _asset("vendor.min.js"), "LIVE_JS": _asset("live.js")}
    return re.sub(r"\{\{([A-Z_]+)\}\}", lambda m: parts[m.group(1)], _asset("live.html"))
