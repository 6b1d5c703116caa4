"""Figures of the report section "Engagement": time histories of several engagement runs side by
side, a strip of hose-shape snapshots, the tension wave along an elastic hose, and a GIF of the whip. Functions return a Figure (or write
the GIF); they never call ``show()`` nor select a backend."""

from __future__ import annotations

from pathlib import Path
from typing import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure

from .animation import _canvas_pillow_writer
from .base import _grid, new_figure

#: Rows of :func:`plot_engagement_history`: (label with unit, function of the result).
_ROWS = (
    ("hose length [m]", lambda r: r.hose_length_m),
    ("take-up speed [m/s]", lambda r: r.reel_speed_m_s),
    ("exit tension [N]", lambda r: r.exit_tension_n),
    ("drogue-end tension [N]", lambda r: r.drogue_tension_n),
    ("probe load [N]", lambda r: np.linalg.norm(r.probe_force_n, axis=1)),
    ("slack [m]", lambda r: r.slack_m),
    ("drogue x offset [m]", lambda r: r.drogue_offset_m[:, 0]),
    ("coupled [0/1]", lambda r: r.coupled.astype(float)),
)


def _contact_time(r) -> float | None:
    for ev in r.events:
        if ev.get("kind") == "contact":
            return ev["t_s"]
    return None


def plot_engagement_history(results: Mapping[str, object], rows: Sequence[int] | None = None) -> Figure:
    """Time histories of engagement runs side by side (one column per run, shared y per row):
    hose length, take-up speed, exit and drogue-end tension, probe load, slack, drogue x offset,
    coupled flag.
    A dotted line marks the contact.

    Parameters
    ----------
    results : mapping of str to EngagementResult
        Column title -> run (times [s], SI histories).
    rows : sequence of int, optional
        Indices of the rows to draw (of the eight above, in that order); default all.

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = list(results)
    sel = [_ROWS[i] for i in (rows if rows is not None else range(len(_ROWS)))]
    fig, axes = new_figure(len(sel), len(names), size=(3.3 * len(names) + 0.8, 1.45 * len(sel) + 0.6),
                           sharex=True, sharey="row", squeeze=False)
    for j, name in enumerate(names):
        r = results[name]
        tc = _contact_time(r)
        for i, (label, fn) in enumerate(sel):
            ax = axes[i, j]
            ax.plot(r.t_s, fn(r), lw=1.0, color=f"C{j}")
            if tc is not None:
                ax.axvline(tc, color="k", ls=":", lw=0.8)
            _grid(ax)
            if j == 0:
                ax.set_ylabel(label, fontsize=8)
        axes[0, j].set_title(f"{name}: {r.outcome.get('result', '')}", fontsize=8)
        axes[-1, j].set_xlabel("time [s]")
    return fig


def plot_hose_snapshots(result, times_s: Sequence[float], label: str = "") -> Figure:
    """A strip of side views (x-z) of the hose at the given times, with the probe tip.

    Parameters
    ----------
    result : EngagementResult
        The run (joint and probe positions [m] in S_p).
    times_s : sequence of float
        Instants [s]; each panel shows the nearest output time.
    label : str
        Figure title (none if empty).

    Returns
    -------
    matplotlib.figure.Figure
    """
    t = np.asarray(result.t_s)
    idx = [int(np.argmin(np.abs(t - ts))) for ts in times_s]
    shapes = [result.joints_m[i] for i in idx]
    allpts = np.concatenate(shapes + [result.probe_position_m[idx]])
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    fig, axes = new_figure(1, len(idx), size=(2.1 * len(idx) + 0.6, 3.0), sharey=True, squeeze=False)
    for k, (i, j) in enumerate(zip(idx, shapes)):
        ax = axes[0, k]
        ax.plot(j[:, 0], j[:, 2], "-", color="C0", lw=1.2)
        ax.plot(j[-1, 0], j[-1, 2], "o", color="C0", ms=5)
        p = result.probe_position_m[i]
        ax.plot(p[0], p[2], ">", color="C3", ms=6)
        ax.set_xlim(lo[0] - 0.5, hi[0] + 0.5)
        ax.set_ylim(hi[2] + 0.5, lo[2] - 0.5)  # z down
        ax.set_title(f"t = {t[i]:.2f} s", fontsize=8)
        ax.set_xlabel("x forward [m]")
        _grid(ax)
    axes[0, 0].set_ylabel("z down [m]")
    if label:
        fig.suptitle(label, fontsize=9)
    return fig


def plot_drogue_region(results: Mapping[str, object], times_s: Sequence[float]) -> Figure:
    """Side views of the aft 5 m of hose for several runs at the same times (the whip).

    Parameters
    ----------
    results : mapping of str to EngagementResult
        Row label -> run (joint and probe positions [m] in S_p).
    times_s : sequence of float
        Instants [s], one column each; each panel shows the nearest output time.

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = list(results)
    fig, axes = new_figure(len(names), len(times_s), size=(1.9 * len(times_s) + 0.8, 2.0 * len(names) + 0.5),
                           sharex=True, sharey=True, squeeze=False)
    for a, name in enumerate(names):
        r = results[name]
        t = np.asarray(r.t_s)
        for b, ts in enumerate(times_s):
            i = int(np.argmin(np.abs(t - ts)))
            j = r.joints_m[i]
            ax = axes[a, b]
            ax.plot(j[:, 0], j[:, 2], "-", color=f"C{a}", lw=1.2)
            ax.plot(j[-1, 0], j[-1, 2], "o", color=f"C{a}", ms=4)
            ax.plot(*r.probe_position_m[i][[0, 2]], ">", color="k", ms=4)
            _grid(ax)
            if a == 0:
                ax.set_title(f"t = {t[i]:.1f} s", fontsize=8)
            if b == 0:
                ax.set_ylabel(f"{name}\nz down [m]", fontsize=8)
            if a == len(names) - 1:
                ax.set_xlabel("x forward [m]")
    x_end = min(float(np.min(results[n].drogue_position_m[:, 0])) for n in names)
    axes[0, 0].set_xlim(x_end - 0.7, x_end + 5.0)
    z_end = [results[n].drogue_position_m[:, 2] for n in names]
    zmax = max(float(np.max(z)) for z in z_end)
    axes[0, 0].set_ylim(zmax + 0.8, zmax - 2.5)
    return fig


def animate_engagement(results: Mapping[str, object], path: str | Path, fps: int = 20, speed: float = 0.5,
                       window_s=None, dpi: int = 72) -> Path:
    """GIF of the hose (side view x-z) of several engagement runs overlaid, with the probe tip.

    Parameters
    ----------
    results : mapping of str to EngagementResult
        Legend label -> run (joint and probe positions [m] in S_p, times [s]).
    path : str or pathlib.Path
        The GIF to write (its folder is created).
    fps : int
        Frames per real second [1/s].
    speed : float
        Simulated seconds per real second [-] (0.5: half speed, to see the whip).
    window_s : (float, float), optional
        Start and end of the animated interval [s]; default the first run's whole time span.
    dpi : int
        Resolution [dots per inch] of the frames (the figure is 8 x 3.2 inches).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    names = list(results)
    t_ref = np.asarray(results[names[0]].t_s)
    t0, t1 = (t_ref[0], t_ref[-1]) if window_s is None else window_s
    frame_times = np.arange(t0, t1 + 1e-9, speed / fps)
    pts = np.concatenate([np.concatenate(results[n].joints_m) for n in names])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    fig, ax = new_figure(1, 1, size=(8.0, 3.2))
    fig.set_dpi(dpi)
    artists = []
    for a, name in enumerate(names):
        (hose,) = ax.plot([], [], "-", color=f"C{a}", lw=1.4, label=name, animated=True)
        (drogue,) = ax.plot([], [], "o", color=f"C{a}", ms=5, animated=True)
        (probe,) = ax.plot([], [], ">", color=f"C{a}", ms=6, mfc="none", animated=True)
        artists.append((results[name], hose, drogue, probe))
    ax.plot([0.0], [0.0], "k^", ms=6)
    ax.set_xlim(lo[0] - 1.0, hi[0] + 0.5)
    ax.set_ylim(hi[2] + 0.5, lo[2] - 0.5)
    ax.set_xlabel("x forward [m]")
    ax.set_ylabel("z down [m]")
    _grid(ax)
    ax.legend(fontsize=7, loc="upper right")
    stamp = ax.text(0.02, 0.95, "", transform=ax.transAxes, ha="left", va="top", fontsize=9, animated=True)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    fig.set_layout_engine("none")
    background = canvas.copy_from_bbox(fig.bbox)
    writer = _canvas_pillow_writer()(fps=fps)
    with writer.saving(fig, str(path), dpi=dpi):
        for tf in frame_times:
            canvas.restore_region(background)
            for r, hose, drogue, probe in artists:
                i = int(np.clip(np.searchsorted(r.t_s, tf), 0, r.t_s.size - 1))
                j = r.joints_m[i]
                hose.set_data(j[:, 0], j[:, 2])
                drogue.set_data([j[-1, 0]], [j[-1, 2]])
                probe.set_data([r.probe_position_m[i, 0]], [r.probe_position_m[i, 2]])
                for art in (hose, drogue, probe):
                    fig.draw_artist(art)
            stamp.set_text(f"t = {tf:5.2f} s")
            fig.draw_artist(stamp)
            writer.grab_frame()
    return path


__all__ = ["plot_engagement_history", "plot_hose_snapshots", "plot_drogue_region", "animate_engagement"]


def tension_field(result, l_nom: float):
    """Tension along the hose of an elastic engagement run: per output time the material arc
    length of every link's midpoint from the exit [m] and its tension [N].

    Links 1..n-1 have the material length ``l_nom`` (splits cut it, a merge only makes a new exit
    link), so link k's midpoint sits ``(n - k - 1/2) l_nom`` of material before the drogue.

    Parameters
    ----------
    result : EngagementResult
        An elastic run (``link_tensions_n`` set).
    l_nom : float
        The nominal link length [m].

    Returns
    -------
    list of (float, numpy.ndarray, numpy.ndarray)
        (time [s], arc length [m], tension [N]) per output time.
    """
    rows = []
    for t, L, tension in zip(result.t_s, result.hose_length_m, result.link_tensions_n):
        n = tension.size
        s = L - (n - np.arange(n) - 0.5) * l_nom
        s[0] = 0.5 * (L - (n - 1) * l_nom)
        rows.append((float(t), s, np.asarray(tension)))
    return rows


def plot_tension_wave(results: Mapping[str, object], l_nom: float, windows: Mapping[str, tuple],
                      wave_speed_m_s: float | None = None) -> Figure:
    """The tension wave of the whip: tension [kN] along the hose (material arc length from the
    exit) against time, one panel per elastic run (each with its colour scale), in the given
    time windows; dashed lines of
    slope +-``wave_speed_m_s`` (the axial wave speed sqrt(EA / mu)) through each window's peak.

    Parameters
    ----------
    results : mapping of str to EngagementResult
        Panel title -> elastic run with outputs fine enough to resolve the wave (about 1 ms).
    l_nom : float
        Nominal link length [m] (:func:`tension_field`).
    windows : mapping of str to (float, float)
        Panel title -> time window [s].
    wave_speed_m_s : float, optional
        Axial wave speed [m/s] of the reference lines.

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = list(results)
    fig, axes = new_figure(1, len(names), size=(4.3 * len(names), 4.2), squeeze=False)
    for j, name in enumerate(names):
        ax = axes[0, j]
        t0, t1 = windows[name]
        rows = [r for r in tension_field(results[name], l_nom) if t0 <= r[0] <= t1]
        n = min(r[1].size for r in rows)  # the links all rows have (a merge removes one at the exit)
        S = np.array([r[1][-n:] for r in rows])
        T = np.array([[r[0]] * n for r in rows])
        mesh = ax.pcolormesh(S, T, np.array([r[2][-n:] for r in rows]) / 1e3, shading="nearest", cmap="viridis")
        fig.colorbar(mesh, ax=ax, label="tension [kN]" if j == len(names) - 1 else None)
        if wave_speed_m_s:
            k = int(np.argmax([np.max(r[2]) for r in rows]))
            tp, sp = rows[k][0], rows[k][1][int(np.argmax(rows[k][2]))]
            for sign in (1.0, -1.0):
                ss = np.array([0.0, S.max()])
                ax.plot(ss, tp + sign * (ss - sp) / wave_speed_m_s, "w--", lw=0.8)
            ax.set_ylim(T.min(), T.max())
        ax.set_xlim(0.0, S.max())
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("arc length from the exit [m]")
        if j == 0:
            ax.set_ylabel("time [s]")
    return fig
