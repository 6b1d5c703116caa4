"""The viewer's page: one self-contained HTML file (no network request; the data, the page's
script and the bundled libraries inline).

The runs' data go into the page as JSON with the arrays base64-encoded (little-endian):
frame times float64 [s], joints per frame uint16, joint positions float32 [m] (float32 holds a
position 25 m from the tow point to 2 micrometres), the charted time series float32 (times
float64). :func:`view_html` builds the page and :func:`write_view` writes it.
"""

from __future__ import annotations

import base64
import html
import json
import math
import re
from importlib.resources import files
from pathlib import Path
from typing import Sequence

import numpy as np

from ..errors import ParameterError
from ..results.hose_file import split_joints
from ..version import __version__
from .runs import AIRCRAFT, SERIES, ViewRun

__all__ = ["view_html", "write_view", "frame_indices", "envelope_indices", "LAYOUTS", "MAX_SERIES_POINTS"]

#: How several runs are shown: in one scene, or side by side (one view each, one camera).
LAYOUTS = ("overlay", "side")

#: Samples per run above which a chart keeps, per bucket of samples, its smallest and largest
#: value (peaks survive): a chart is at most a few thousand pixels wide.
MAX_SERIES_POINTS = 20000

#: Largest joint count a frame may have (the page stores counts as uint16).
MAX_JOINTS = 65535


def frame_indices(t_s: np.ndarray, rate_hz: float | None) -> np.ndarray:
    """The output samples kept as 3D frames: all of them, or about ``rate_hz`` per simulated second.

    Parameters
    ----------
    t_s : numpy.ndarray
        (N,) increasing output times [s].
    rate_hz : float or None
        Frames per simulated second [1/s]; None keeps every output time.

    Returns
    -------
    numpy.ndarray
        Increasing sample indices, the first and the last always among them.
    """
    n = t_s.size
    if rate_hz is None or n < 3:
        return np.arange(n)
    if not (math.isfinite(rate_hz) and rate_hz > 0):
        raise ParameterError(f"frame rate = {rate_hz!r}: must be a number > 0 [1/s]")
    grid = np.arange(t_s[0], t_s[-1], 1.0 / rate_hz)
    right = np.clip(np.searchsorted(t_s, grid), 1, n - 1)
    left = right - 1
    nearest = np.where(grid - t_s[left] <= t_s[right] - grid, left, right)  # the sample nearest each instant
    return np.unique(np.concatenate([nearest, [n - 1]]))


def envelope_indices(y: np.ndarray, max_points: int) -> np.ndarray:
    """Samples a chart keeps: all if there are at most ``max_points``, else the smallest and the
    largest of each of ``max_points // 2`` consecutive buckets (in time order), so peaks stay.

    Parameters
    ----------
    y : numpy.ndarray
        (N,) the series.
    max_points : int
        Most samples kept [-], >= 2.

    Returns
    -------
    numpy.ndarray
        Increasing sample indices.
    """
    n = y.size
    if n <= max_points:
        return np.arange(n)
    buckets = max(1, max_points // 2)
    edges = np.linspace(0, n, buckets + 1).astype(int)
    keep = [0, n - 1]
    for a, b in zip(edges[:-1], edges[1:]):
        if b > a:
            seg = np.nan_to_num(y[a:b], nan=0.0)
            keep += [a + int(np.argmin(seg)), a + int(np.argmax(seg))]
    return np.unique(keep)


def _b64(array: np.ndarray, dtype: str) -> str:
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode("ascii")


def _frames(run: ViewRun, rate_hz: float | None) -> dict:
    """The run's 3D frames: times [s], joints per frame, positions [m], probe tip [m], coupled flag,
    the receiver aircraft's position [m] and attitude [rad] (runs with one)."""
    t = run.t_s
    keep = frame_indices(t, rate_hz)
    if run.joint_count.max(initial=0) > MAX_JOINTS:
        raise ParameterError(f"run {run.label!r}: {int(run.joint_count.max())} joints: the viewer draws at most {MAX_JOINTS}")
    shapes = split_joints(run.joint_count, run.joints_m)
    out = {"t": _b64(t[keep], "<f8"), "count": _b64(run.joint_count[keep], "<u2"),
           "joints": _b64(np.concatenate([shapes[i] for i in keep]), "<f4"), "probe": None, "coupled": None}
    cols = run.columns
    if all(c in cols for c in ("probe_x_m", "probe_y_m", "probe_z_m")):
        probe = np.column_stack([cols["probe_x_m"], cols["probe_y_m"], cols["probe_z_m"]])[keep]
        out["probe"] = _b64(probe, "<f4")
    if "coupled" in cols:
        out["coupled"] = _b64(np.asarray(cols["coupled"])[keep] != 0, "u1")
    if all(c in cols for c in AIRCRAFT):  # the receiver aircraft: x, y, z [m], roll, pitch, yaw [rad] per frame
        out["aircraft"] = _b64(np.column_stack([cols[c] for c in AIRCRAFT])[keep], "<f4")
    return out


def _series(run: ViewRun, max_points: int) -> dict:
    """The charted columns (envelope-decimated together: the union of each column's extremes)."""
    cols = {c: run.columns[c] for c in SERIES if c in run.columns}
    t = run.t_s
    keep = np.unique(np.concatenate([envelope_indices(v, max_points // max(1, len(cols))) for v in cols.values()]
                                    or [np.arange(t.size)]))
    return {"t": _b64(t[keep], "<f8"), **{c: _b64(v[keep], "<f4") for c, v in cols.items()}}


def _facts(run: ViewRun) -> dict:
    """What the page says and draws of the run besides its arrays (from run.json)."""
    doc = run.document
    params = doc.get("params") or {}
    probe = doc.get("probe") or {}
    eng = doc.get("engagement") or {}
    return {
        "label": run.label, "source": run.source, "model": doc.get("model"), "scenario": doc.get("scenario"),
        "completed": doc.get("completed", True), "message": doc.get("message", ""),
        "hose_diameter_m": (params.get("hose") or {}).get("outer_diameter_m", 0.067),
        "drogue_diameter_m": (params.get("drogue") or {}).get("diameter_m", 0.61),
        "capture_radius_m": probe.get("capture_radius_m"),
        "outcome": {k: eng.get(k) for k in ("result", "miss_distance_m", "contact_time_s", "peak_probe_load_n",
                                            "peak_exit_tension_n") if k in eng},
    }


def _asset(name: str) -> str:
    return files("hosedrogue.viewer").joinpath("assets", name).read_text(encoding="utf-8")


def _script_json(payload: dict) -> str:
    """JSON safe inside a <script> element (no "</" sequence can close it)."""
    return json.dumps(payload, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")


def view_html(runs: Sequence[ViewRun], *, layout: str = "overlay", frame_rate_hz: float | None = None,
              window_s: tuple | None = None, title: str | None = None,
              max_series_points: int = MAX_SERIES_POINTS) -> str:
    """The viewer page of one or more runs.

    Parameters
    ----------
    runs : sequence of ViewRun
        The runs (:func:`hosedrogue.viewer.read_run`, :meth:`ViewRun.from_result`), at least one.
    layout : {"overlay", "side"}
        Several runs in one scene, or side by side; the page switches between them.
    frame_rate_hz : float, optional
        3D frames kept per simulated second [1/s] (default: every output time); the page
        interpolates between frames of the same link count.
    window_s : (float or None, float or None), optional
        Show only the output times in [start, end] [s] (:meth:`ViewRun.between`; None: that end
        of each run).
    title : str, optional
        The page's title (default: the runs' labels).
    max_series_points : int
        Most chart samples per run [-] (:func:`envelope_indices`).

    Returns
    -------
    str
        The HTML text.
    """
    runs = list(runs)
    if not runs:
        raise ParameterError("runs: give at least one run")
    if layout not in LAYOUTS:
        raise ParameterError(f"layout = {layout!r}: must be one of {', '.join(map(repr, LAYOUTS))}")
    if window_s is not None:
        runs = [r.between(*window_s) for r in runs]
    title = title or "hosedrogue viewer: " + ", ".join(r.label for r in runs)
    payload = {"version": __version__, "title": title, "layout": layout,
               "runs": [{**_facts(r), "frames": _frames(r, frame_rate_hz), "series": _series(r, max_series_points)}
                        for r in runs]}
    parts = {"TITLE": html.escape(title), "VENDOR_CSS": _asset("vendor.min.css"), "VIEWER_CSS": _asset("viewer.css"),
             "LICENSES": html.escape(_asset("THIRD-PARTY-LICENSES.txt")), "VERSION": __version__,
             "DATA": _script_json(payload), "VENDOR_JS": _asset("vendor.min.js"), "VIEWER_JS": _asset("viewer.js")}
    # one pass over the template: text put in is not searched again for placeholders
    return re.sub(r"\{\{([A-Z_]+)\}\}", lambda m: parts[m.group(1)], _asset("page.html"))


def write_view(runs: Sequence[ViewRun], out: str | Path, **options) -> Path:
    """Write the viewer page of ``runs`` to ``out`` (see :func:`view_html` for the options).

    Parameters
    ----------
    runs : sequence of ViewRun
        The runs.
    out : str or pathlib.Path
        The HTML file to write; its folder is created if missing.
    **options
        ``layout``, ``frame_rate_hz``, ``window_s``, ``title``, ``max_series_points`` of
        :func:`view_html`.

    Returns
    -------
    pathlib.Path
        ``out``.
    """
    text = view_html(runs, **options)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text, encoding="utf-8")
    return out
