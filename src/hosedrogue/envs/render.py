"""The docking environment's picture (``render_mode="rgb_array"``): the approach seen from behind
(the drogue with its capture circle, the probe tip) and from the side (the hose from the tanker's
exit to the drogue, the probe), drawn on matplotlib's Agg canvas into an RGB array (no display,
no pyplot; the user's backend stays as it was)."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Circle

#: Size of the picture [pixel] and its resolution [dots per inch].
WIDTH_PX, HEIGHT_PX, DPI = 720, 320, 80
#: Half-width of the view from behind around the drogue's balance position [m].
BEHIND_HALF_WIDTH_M = 1.2
#: Length of the probe drawn aft of its tip [m] (a picture of the receiver's probe, not a model of it).
PROBE_DRAWN_M = 1.5


class DockingRenderer:
    """One figure, drawn again at every call with the current hose and probe.

    Parameters
    ----------
    balance_m : array_like (3,)
        The drogue's balance position [m] (S_p): the centre of the view from behind.
    standoff_m : float
        The probe's start distance aft of the drogue [m] (the side view's extent).
    capture_radius_m : float
        The capture test's radius [m] (the circle around the drogue).
    """

    def __init__(self, balance_m, standoff_m: float, capture_radius_m: float):
        b = np.asarray(balance_m, dtype=np.float64)
        fig = Figure(figsize=(WIDTH_PX / DPI, HEIGHT_PX / DPI), dpi=DPI, constrained_layout=True)
        self.canvas = FigureCanvasAgg(fig)
        behind, side = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.0, 1.8]})
        w = BEHIND_HALF_WIDTH_M
        behind.set(xlim=(b[1] - w, b[1] + w), ylim=(b[2] + w, b[2] - w), aspect="equal",
                   xlabel="y, right [m]", ylabel="z, down [m]", title="from behind")
        behind.plot([b[1]], [b[2]], "+", color="0.5", ms=8, label="drogue's balance position")
        self.circle = Circle((b[1], b[2]), capture_radius_m, fill=False, color="tab:blue", lw=1.5,
                             label=f"capture radius ({capture_radius_m:g} m)")
        behind.add_patch(self.circle)
        self.tip_behind, = behind.plot([], [], "o", color="tab:red", ms=6, label="probe tip")
        x_aft = b[0] - standoff_m - PROBE_DRAWN_M - 0.5
        side.set(xlim=(x_aft, 0.5), ylim=(b[2] + 2.0, -1.0), xlabel="x, forward [m]", ylabel="z, down [m]",
                 title="from the side")
        side.plot([0.0], [0.0], "s", color="0.3", ms=6, label="tanker's hose exit")
        self.hose, = side.plot([], [], "-", color="0.2", lw=1.5, label="hose")
        self.drogue, = side.plot([], [], "o", color="tab:blue", ms=7, label="drogue")
        self.probe, = side.plot([], [], "-", color="tab:red", lw=2.5, label="receiver's probe")
        # one legend for both views, in the side view's empty corner (above the probe, aft of the hose)
        handles = [*behind.get_legend_handles_labels()[0], *side.get_legend_handles_labels()[0]]
        side.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.8, ncols=2)
        for ax in (behind, side):
            ax.grid(True, alpha=0.3)
        self.title = fig.suptitle("")
        self.figure = fig

    def draw(self, t_s: float, joints_m: np.ndarray, probe_m: np.ndarray, outcome: str) -> np.ndarray:
        """The picture of one instant.

        Parameters
        ----------
        t_s : float
            Time [s].
        joints_m : numpy.ndarray (n+1, 3)
            The hose's joints [m], exit to drogue.
        probe_m : numpy.ndarray (3,)
            The probe tip [m].
        outcome : str
            The episode's outcome so far (the title).

        Returns
        -------
        numpy.ndarray (HEIGHT_PX, WIDTH_PX, 3) uint8
        """
        d = joints_m[-1]
        self.circle.center = (d[1], d[2])
        self.tip_behind.set_data([probe_m[1]], [probe_m[2]])
        self.hose.set_data(joints_m[:, 0], joints_m[:, 2])
        self.drogue.set_data([d[0]], [d[2]])
        self.probe.set_data([probe_m[0] - PROBE_DRAWN_M, probe_m[0]], [probe_m[2], probe_m[2]])
        self.title.set_text(f"t = {t_s:5.2f} s   {outcome}")
        self.canvas.draw()
        # the layout of the first picture serves every later one: the axes' limits are fixed
        self.figure.set_layout_engine("none")
        return np.asarray(self.canvas.buffer_rgba())[:, :, :3].copy()
