"""The receiver aircraft's trim over airspeed (data from :func:`hosedrogue.aircraft.trim.trim`):
throttle, angle of attack and elevator against airspeed, optionally beside published points."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from ..plotting.base import new_figure


def plot_trim_curves(airspeed_m_s, throttle, alpha_deg, elevator_deg, published=None,
                     published_label: str = "published", title: str | None = None) -> Figure:
    """Throttle, angle of attack and elevator of trims against airspeed.

    Parameters
    ----------
    airspeed_m_s : array_like
        (n,) airspeeds [m/s].
    throttle : array_like
        (n,) throttle [-].
    alpha_deg : array_like
        (n,) angle of attack [deg].
    elevator_deg : array_like
        (n,) elevator [deg].
    published : array_like, optional
        (m, 4) points to compare: airspeed [m/s], throttle [-], alpha [deg], elevator [deg].
    published_label : str
        Legend of the published points.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = new_figure(3, 1, size=(7.0, 7.0), sharex=True)
    v = np.asarray(airspeed_m_s, dtype=np.float64)
    pts = None if published is None else np.asarray(published, dtype=np.float64)
    for k, (ax, y, label) in enumerate(zip(axes, (throttle, alpha_deg, elevator_deg),
                                           ("throttle [-]", "angle of attack [deg]", "elevator [deg]"))):
        ax.plot(v, np.asarray(y, dtype=np.float64), "-", lw=1.5, label="hosedrogue trim")
        if pts is not None:
            ax.plot(pts[:, 0], pts[:, k + 1], "o", mfc="none", color="k", label=published_label)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize="small")
    axes[-1].set_xlabel("true airspeed [m/s]")
    if title:
        axes[0].set_title(title)
    return fig
