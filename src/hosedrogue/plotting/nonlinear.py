"""Figures of the controllers on the nonlinear model (paper Sec. 3.3: Figs. 12 and 13) and of
the hose in 3D."""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from matplotlib.figure import Figure

from .base import _grid, _shade_window, new_figure


def plot_controller_on_off(result_off, results_on: Mapping[str, object], window_s=None) -> Figure:
    """Paper Fig. 12: drogue displacement with the controller off and on, and the y-z trajectory.

    One row per controller. Columns: lateral displacement [m] off vs on; vertical displacement
    [m] off vs on; the controlled displacements alone in millimetres (they are invisible on the
    metre scale); the drogue's y-z trajectory about its balance position [m].

    Parameters
    ----------
    result_off : SimulationResult
        Controller off.
    results_on : mapping
        ``{controller label: SimulationResult}`` with the controller on (same turbulence).
    window_s : (float, float), optional
        Turbulence window [s], shaded.

    Returns
    -------
    Figure
    """
    names = list(results_on)
    fig, axes = new_figure(len(names), 4, size=(15.0, 3.4 * len(names)), squeeze=False)
    off = result_off.drogue_offset_m
    for r, name in enumerate(names):
        res = results_on[name]
        on = res.drogue_offset_m
        for c, (k, what) in enumerate(((1, "lateral dy"), (2, "vertical dz"))):
            ax = axes[r, c]
            _shade_window(ax, window_s)
            ax.plot(result_off.t_s, off[:, k], lw=0.9, color="C3", label="off")
            ax.plot(res.t_s, on[:, k], lw=1.1, color="C0", label=f"on ({name})")
            ax.set_xlabel("time t [s]")
            ax.set_ylabel(f"{what} [m]")
            ax.set_title(f"{name}: {what.split()[0]} displacement", fontsize=9)
            _grid(ax)
            ax.legend(fontsize=7, loc="upper left")
        ax = axes[r, 2]
        _shade_window(ax, window_s)
        ax.plot(res.t_s, 1000.0 * on[:, 1], lw=1.0, color="C0", label="lateral dy")
        ax.plot(res.t_s, 1000.0 * on[:, 2], lw=1.0, color="C2", label="vertical dz")
        ax.set_xlabel("time t [s]")
        ax.set_ylabel("displacement [mm]")
        ax.set_title(f"{name} on: displacement in millimetres", fontsize=9)
        _grid(ax)
        ax.legend(fontsize=7, loc="upper left")
        ax = axes[r, 3]
        ax.plot(off[:, 1], off[:, 2], lw=0.7, color="C3", label="off")
        ax.plot(on[:, 1], on[:, 2], lw=1.0, color="C0", label=f"on ({name})")
        ax.plot([0.0], [0.0], "k+", ms=10)
        ax.invert_yaxis()
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("lateral dy [m] (right)")
        ax.set_ylabel("vertical dz [m] (down)")
        ax.set_title(f"{name}: y-z trajectory, seen from behind", fontsize=9)
        _grid(ax)
        ax.legend(fontsize=7, loc="upper left")
    return fig


def plot_control_forces(results: Mapping[str, object], window_s=None) -> Figure:
    """Paper Fig. 13: control forces u_hor and u_ver [N] against time [s], one curve per
    controller.

    Parameters
    ----------
    results : mapping
        ``{controller label: SimulationResult}``.
    window_s : (float, float), optional
        Turbulence window [s], shaded.

    Returns
    -------
    Figure
    """
    fig, (ax_h, ax_v) = new_figure(2, 1, size=(8.0, 5.5), sharex=True)
    for k, (name, res) in enumerate(results.items()):
        ax_h.plot(res.t_s, res.control_force_n[:, 0], lw=0.9, color=f"C{k}", label=name)
        ax_v.plot(res.t_s, res.control_force_n[:, 1], lw=0.9, color=f"C{k}", label=name)
    for ax, what in ((ax_h, "lateral force u_hor [N]"), (ax_v, "vertical force u_ver [N]\n(positive down)")):
        _shade_window(ax, window_s)
        ax.set_xlabel("time t [s]")
        ax.set_ylabel(what)
        _grid(ax)
    ax_h.legend(fontsize=8)
    return fig


def plot_hose_3d(joints_list: Sequence[np.ndarray], labels: Sequence[str]) -> Figure:
    """The hose in 3D (S_p: x forward, y right, z down, origin at the tow point).

    Parameters
    ----------
    joints_list : sequence of arrays, each (n+1, 3)
        Joint positions [m] (joint 0 = tow point, joint n = drogue). The first shape is drawn
        black and dashed (the reference, e.g. the balance position).
    labels : sequence of str
        One label per shape.

    The axes are scaled independently (the hose is 15 m long and swings by about 1 m), so the
    lateral and vertical excursions are exaggerated relative to the length. The view is from
    behind and to the left of the hose, above it.

    Returns
    -------
    Figure
    """
    from matplotlib.ticker import MaxNLocator

    fig, ax = new_figure(1, 1, size=(9.0, 5.5), subplot_kw={"projection": "3d"})
    allj = np.concatenate([np.asarray(j) for j in joints_list])
    for k, (joints, label) in enumerate(zip(joints_list, labels)):
        j = np.asarray(joints)
        style = dict(color="k", ls="--", lw=2.0) if k == 0 else dict(color=f"C{k - 1}", ls="-", lw=1.3)
        ax.plot(j[:, 0], j[:, 1], j[:, 2], marker=".", ms=3, label=label, **style)
        ax.plot([j[-1, 0]], [j[-1, 1]], [j[-1, 2]], "o", ms=7, color=style["color"])
    ax.plot([0.0], [0.0], [0.0], "k^", ms=7, label="tow point")
    ax.set_box_aspect((1.6, 1.0, 0.8))
    ax.set_zlim(allj[:, 2].max() + 0.2, allj[:, 2].min() - 0.2)  # z down: draw down as down
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(5))
    ax.set_xlabel("x forward [m]")
    ax.set_ylabel("y right [m]")
    ax.set_zlabel("z down [m]")
    ax.view_init(elev=20.0, azim=-125.0)
    fig.legend(loc="outside right upper", fontsize=8)
    return fig
