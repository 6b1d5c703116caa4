"""Shared pieces of the figures: figure creation outside pyplot's global state, saving, grids and
the turbulence-window band. Nothing here selects a backend or touches pyplot, so importing the
package leaves a user's matplotlib backend as it was; ``Figure.savefig`` renders files with Agg."""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

#: Channel names, in the order of the plant's inputs and outputs.
CHANNELS = ("lateral", "vertical")
_CHANNEL_TITLE = {"lateral": "lateral channel (u_hor -> P_ny)", "vertical": "vertical channel (u_ver -> P_nz)"}


def new_figure(nrows: int = 1, ncols: int = 1, size=(7.0, 4.0), constrained: bool = True, **kw):
    """A figure not registered with pyplot's global state (safe in long-running processes).

    Parameters
    ----------
    nrows, ncols : int
        Grid of axes.
    size : tuple of float
        Figure width and height [inch].
    constrained : bool
        Matplotlib's constrained layout; False: none (the caller places the axes, e.g. with
        ``subplots_adjust``, and saves the layout solver's CPU).
    **kw
        Passed to ``Figure.subplots`` (e.g. ``sharex``, ``subplot_kw``).

    Returns
    -------
    tuple
        ``(figure, axes)`` as from ``Figure.subplots``.
    """
    fig = Figure(figsize=size, constrained_layout=True) if constrained else Figure(figsize=size)
    axes = fig.subplots(nrows, ncols, **kw)
    return fig, axes


def save_figure(fig: Figure, path: str | Path, dpi: int = 120) -> Path:
    """Save a figure, creating the folder if needed.

    Parameters
    ----------
    fig : Figure
        The figure.
    path : str or Path
        Output file; the format follows the suffix.
    dpi : int
        Resolution [dots per inch].

    Returns
    -------
    Path
        The written file.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    return path


def legend_or_note(ax, note: str, **kw) -> None:
    """The axes' legend, or, when nothing on them has a label (a campaign none of whose runs
    completed), ``note`` written in their middle instead (matplotlib would warn "No artists with
    labels found to put in legend").

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes.
    note : str
        What to write when there is nothing to show ("no completed run").
    **kw
        Passed to ``Axes.legend`` (``loc``, ``fontsize``).
    """
    handles, _ = ax.get_legend_handles_labels()
    if handles:
        ax.legend(**kw)
    else:
        ax.text(0.5, 0.5, note, transform=ax.transAxes, ha="center", va="center", color="0.4")


def _grid(ax, **kw):
    ax.grid(True, alpha=0.3, **kw)


def _shade_window(ax, window_s):
    """Grey band over the turbulence window (start, end) [s], if given."""
    if window_s is not None:
        ax.axvspan(window_s[0], window_s[1], color="0.85", alpha=0.5, lw=0, zorder=0)
