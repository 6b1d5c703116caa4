"""The receiver's bow wave: its perturbation velocity around the probe and the drogue's steady
displacement against the probe's distance (data from
:func:`hosedrogue.environment.bow_wave.BowWave.velocity` and
:func:`hosedrogue.engagement.bow_wave.bow_wave_displacement`)."""

from __future__ import annotations

import numpy as np
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

from .base import new_figure


def plot_bow_wave(x_m, z_m, velocity_m_s, distances_m, displacement_m, probe_tip_m=(0.0, 0.0)) -> Figure:
    """Bow-wave speed around the probe (left) and the drogue's steady displacement (right).

    Parameters
    ----------
    x_m, z_m : array (nx,), (nz,)
        Grid of the field [m]: forward (S_p x) and down (S_p z) in the vertical plane of the probe.
    velocity_m_s : array (nz, nx, 3)
        Perturbation velocity [m/s] on the grid (NaN inside the body to blank it).
    distances_m : array (m,)
        Probe tip's distance aft of the drogue [m].
    displacement_m : array (m, 3)
        Drogue's steady displacement [m] (forward, right, down) at each distance.
    probe_tip_m : tuple of float
        Probe tip (x, z) [m] in the field's coordinates, marked.

    Returns
    -------
    Figure
    """
    fig, (ax0, ax1) = new_figure(1, 2, size=(11.0, 4.2))
    w = np.asarray(velocity_m_s, dtype=np.float64)
    speed = np.linalg.norm(w, axis=-1)
    levels = np.geomspace(0.05, max(float(np.nanmax(speed)), 0.1), 12)
    cs = ax0.contourf(x_m, z_m, speed, levels=levels, cmap="viridis", extend="max", norm=LogNorm())
    step = max(1, len(x_m) // 16)
    X, Z = np.meshgrid(x_m, z_m)
    ax0.quiver(X[::step, ::step], Z[::step, ::step], w[::step, ::step, 0], w[::step, ::step, 2], color="w")
    ax0.plot(*probe_tip_m, "r^", label="probe tip")
    ax0.set_xlabel("forward x [m]")
    ax0.set_ylabel("down z [m]")
    ax0.invert_yaxis()
    ax0.set_aspect("equal")
    ax0.legend(loc="upper left")
    fig.colorbar(cs, ax=ax0, label="perturbation speed [m/s]")
    ax0.set_title("bow wave around the probe")
    d = np.asarray(distances_m, dtype=np.float64)
    disp = np.asarray(displacement_m, dtype=np.float64)
    for i, name in enumerate(("forward", "right", "down")):
        ax1.loglog(d, np.abs(disp[:, i]) * 1e3, "o-", label=f"|{name}|")
    ax1.loglog(d, np.linalg.norm(disp, axis=1) * 1e3, "k-", lw=2, label="total")
    ax1.set_xlabel("probe tip aft of the drogue [m]")
    ax1.set_ylabel("drogue steady displacement [mm]")
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend()
    ax1.set_title("drogue displacement by the bow wave")
    return fig
