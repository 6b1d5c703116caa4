"""The receiver's bow wave: its perturbation velocity around the probe and the drogue's steady
displacement against the probe's distance (data from
:func:`hosedrogue.environment.bow_wave.BowWaveField.velocity` and
:func:`hosedrogue.engagement.bow_wave.bow_wave_displacement`), optionally with the forebody's
outline, the far field's ``1/r^2`` asymptote, a displacement level and a third panel of the far
displacement against the forebody radius (the report's "Docking" section)."""

from __future__ import annotations

import numpy as np
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure
from matplotlib.ticker import NullFormatter, ScalarFormatter

from ..plotting.base import new_figure


def _field_panel(fig, ax, x_m, z_m, velocity_m_s, probe_tip_m, outline_m, stagnation_m) -> None:
    w = np.asarray(velocity_m_s, dtype=np.float64)
    speed = np.linalg.norm(w, axis=-1)
    levels = np.geomspace(0.05, max(float(np.nanmax(speed)), 0.1), 12)
    cs = ax.contourf(x_m, z_m, speed, levels=levels, cmap="viridis", extend="max", norm=LogNorm())
    step = max(1, len(x_m) // 16)
    X, Z = np.meshgrid(x_m, z_m)
    ax.quiver(X[::step, ::step], Z[::step, ::step], w[::step, ::step, 0], w[::step, ::step, 2], color="w")
    if outline_m is not None:
        o = np.asarray(outline_m, dtype=np.float64)
        ax.plot(o[:, 0], o[:, 1], "k-", lw=1.5, label="forebody (dividing streamline)")
    if stagnation_m is not None:
        ax.plot(*stagnation_m, "wo", mec="k", label="stagnation point (nose)")
    ax.plot(*probe_tip_m, "r^", label="probe tip")
    ax.set_xlim(float(np.min(x_m)), float(np.max(x_m)))
    ax.set_ylim(float(np.min(z_m)), float(np.max(z_m)))
    ax.set_xlabel("forward x [m]")
    ax.set_ylabel("down z [m]")
    ax.invert_yaxis()
    ax.set_aspect("equal")
    ax.legend(loc="upper left", fontsize="x-small")
    fig.colorbar(cs, ax=ax, label="perturbation speed [m/s]", ticks=levels[::2], format="%.2g")
    ax.set_title("bow wave around the probe")


def _displacement_panel(ax, distances_m, displacement_m, source_distance_m, level_m) -> None:
    d = np.asarray(distances_m, dtype=np.float64)
    disp = np.asarray(displacement_m, dtype=np.float64)
    for i, name in enumerate(("forward", "right", "down")):
        if np.any(np.abs(disp[:, i]) > 0):
            ax.loglog(d, np.abs(disp[:, i]) * 1e3, "o-", ms=3, label=f"|{name}|")
    total = np.linalg.norm(disp, axis=1)
    ax.loglog(d, total * 1e3, "k-", lw=2, label="total")
    if source_distance_m is not None:  # anchored at the farthest point
        r = np.asarray(source_distance_m, dtype=np.float64)
        ax.loglog(d, total[-1] * (r[-1] / r) ** 2 * 1e3, "k:", label="1/r² (r from the source)")
    if level_m is not None:
        ax.axhline(level_m * 1e3, color="tab:red", ls="--", lw=0.9, label=f"{level_m * 1e3:g} mm")
    ax.set_xlabel("probe tip aft of the drogue [m]")
    ax.set_ylabel("drogue steady displacement [mm]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    ax.set_title("drogue displacement by the bow wave")


def _radius_panel(ax, radii_m, far_displacement_m, far_distance_m, level_m, radius_limit_m) -> None:
    R = np.asarray(radii_m, dtype=np.float64)
    far = np.asarray(far_displacement_m, dtype=np.float64)
    ax.loglog(R, far * 1e3, "ko-", label=f"total at {far_distance_m:g} m")
    ref = int(np.argmin(np.abs(R - np.median(R))))
    ax.loglog(R, far[ref] * (R / R[ref]) ** 2 * 1e3, "k:", label="∝ R² (flux π R² V)")
    if level_m is not None:
        ax.axhline(level_m * 1e3, color="tab:red", ls="--", lw=0.9, label=f"{level_m * 1e3:g} mm")
    if radius_limit_m is not None:
        ax.axvline(radius_limit_m, color="tab:red", lw=0.9, label=f"R = {radius_limit_m:.2f} m")
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_formatter(ScalarFormatter())
        axis.set_minor_formatter(NullFormatter())
    ax.set_xticks(R)
    mm = far * 1e3
    ax.set_yticks([v for v in (0.2, 0.3, 0.5, 1.0, 2.0, 3.0, 5.0, 10.0, 20.0) if 0.9 * mm.min() <= v <= 1.1 * mm.max()])
    ax.set_xlabel("forebody radius R [m]")
    ax.set_ylabel(f"drogue displacement at {far_distance_m:g} m [mm]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    ax.set_title("far displacement against the forebody")


def plot_bow_wave(x_m, z_m, velocity_m_s, distances_m, displacement_m, probe_tip_m=(0.0, 0.0), *,
                  outline_m=None, stagnation_m=None, source_distance_m=None, level_m=None, radii_m=None,
                  far_displacement_m=None, far_distance_m: float = 10.0, radius_limit_m=None) -> Figure:
    """Bow-wave speed around the probe (left), the drogue's steady displacement (middle/right) and,
    with ``radii_m``, the far displacement against the forebody radius (right).

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
    outline_m : array (k, 2), optional
        Forebody outline (x, z) [m] in the field's coordinates, drawn.
    stagnation_m : tuple of float, optional
        Stagnation point (x, z) [m] in the field's coordinates, marked.
    source_distance_m : array (m,), optional
        Distance [m] from the drogue to the source at each of ``distances_m``: draws the ``1/r^2``
        asymptote through the farthest point.
    level_m : float, optional
        A displacement level [m] drawn as a dashed line (e.g. 1 mm).
    radii_m : array (k,), optional
        Forebody radii [m] of the third panel.
    far_displacement_m : array (k,), optional
        Total displacement [m] at ``far_distance_m`` for each of ``radii_m``.
    far_distance_m : float
        Probe distance [m] of the third panel.
    radius_limit_m : float, optional
        Radius [m] at which the far displacement equals ``level_m``, marked.

    Returns
    -------
    Figure
    """
    panels = 3 if radii_m is not None else 2
    fig, axes = new_figure(1, panels, size=(5.5 * panels, 4.2))
    _field_panel(fig, axes[0], x_m, z_m, velocity_m_s, probe_tip_m, outline_m, stagnation_m)
    _displacement_panel(axes[1], distances_m, displacement_m, source_distance_m, level_m)
    if radii_m is not None:
        _radius_panel(axes[2], radii_m, far_displacement_m, far_distance_m, level_m, radius_limit_m)
    return fig
