"""GIF animation of the hose and drogue in turbulence, controller off and on."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .base import _grid, new_figure


def _canvas_pillow_writer():
    """A PillowWriter that grabs the Agg canvas as the caller left it (static background plus
    blitted moving artists) instead of re-rendering the whole figure through ``savefig`` for
    every frame (two full draws per frame, mostly tick-label layout: ~50x slower)."""
    from matplotlib.animation import PillowWriter
    from PIL import Image

    class CanvasPillowWriter(PillowWriter):
        def setup(self, fig, outfile, dpi=None):
            super().setup(fig, outfile, dpi=dpi)
            self.images = []

        def grab_frame(self, **savefig_kwargs):
            canvas = self.fig.canvas
            size = canvas.get_width_height(physical=True)
            im = Image.frombuffer("RGBA", size, bytes(canvas.buffer_rgba()), "raw", "RGBA", 0, 1)
            self.images.append(im.convert("RGB"))

        def finish(self):
            self.images[0].save(self.outfile, save_all=True, append_images=self.images[1:],
                                duration=int(1000 / self.fps), loop=0)

    return CanvasPillowWriter


def _animation_axes(lo, hi, pad, labels, dpi):
    """The static part of the animation: side and rear axes with fixed limits [m], the (empty)
    animated hose and drogue lines of both runs and the time stamp.

    Returns (figure, [(run key, hose line, drogue line, x index, y index)], time-stamp text).
    """
    fig, (ax_side, ax_rear) = new_figure(1, 2, size=(9.0, 3.4), gridspec_kw={"width_ratios": [2.2, 1.0]})
    fig.set_dpi(dpi)
    lines = []
    for ax, (a, b) in ((ax_side, (0, 2)), (ax_rear, (1, 2))):
        for key, color, lab in (("off", "C3", labels[0]), ("on", "C0", labels[1])):
            (hose,) = ax.plot([], [], "-", color=color, lw=1.6, label=lab, animated=True)
            (drogue,) = ax.plot([], [], "o", color=color, ms=6, animated=True)
            lines.append((key, hose, drogue, a, b))
        ax.plot([0.0], [0.0], "k^", ms=6)
        ax.set_xlim(lo[a] - pad[a], hi[a] + pad[a])
        ax.set_ylim(hi[b] + pad[b], lo[b] - pad[b])  # z down
        _grid(ax)
    ax_side.set_xlabel("x forward [m]")
    ax_side.set_ylabel("z down [m]")
    ax_side.set_title("side view", fontsize=9)
    ax_rear.set_xlabel("y right [m]")
    ax_rear.set_ylabel("z down [m]")
    ax_rear.set_title("rear view (from behind)", fontsize=9)
    ax_side.legend(fontsize=7, loc="lower left")
    stamp = ax_side.text(0.5, 0.95, "", transform=ax_side.transAxes, ha="center", va="top", fontsize=9,
                         animated=True)
    return fig, lines, stamp


def animate_hose(result_off, result_on, path: str | Path, fps: int = 10, window_s=None,
                 labels: tuple[str, str] = ("controller off", "controller on"), dpi: int = 72) -> Path:
    """GIF of the hose and drogue in turbulence, controller off and on: side view (x-z) and rear
    view (y-z, looking forward from behind the drogue).

    Parameters
    ----------
    result_off, result_on : SimulationResult
        Two runs of the same turbulence, controller off and on.
    path : str or Path
        Output GIF file.
    fps : int
        Frames per second of both the GIF and the simulated time (one frame per 1/fps s of
        simulated time: the animation runs in real time).
    window_s : (float, float), optional
        Time span to animate [s]; default the whole run.
    labels : (str, str)
        Legend labels of the two runs.
    dpi : int
        Resolution; the default keeps a 20 s animation at 10 fps near 1-2 MB.

    Returns
    -------
    Path
        The written file.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    t = np.asarray(result_off.t_s)
    t0, t1 = (t[0], t[-1]) if window_s is None else window_s
    frame_times = np.arange(t0, t1 + 1e-9, 1.0 / fps)
    idx_off = np.clip(np.searchsorted(t, frame_times), 0, t.size - 1)
    t_on = np.asarray(result_on.t_s)
    idx_on = np.clip(np.searchsorted(t_on, frame_times), 0, t_on.size - 1)
    j_off = np.asarray(result_off.joints_m)
    j_on = np.asarray(result_on.joints_m)
    both = np.concatenate([j_off[idx_off].reshape(-1, 3), j_on[idx_on].reshape(-1, 3)])
    lo, hi = both.min(axis=0), both.max(axis=0)
    pad = 0.08 * np.maximum(hi - lo, 0.5)

    fig, lines, stamp = _animation_axes(lo, hi, pad, labels, dpi)

    # Draw (and lay out) the static parts once, then freeze the layout and blit the moving
    # artists onto a copy of that background for every frame.
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    fig.set_layout_engine("none")
    background = canvas.copy_from_bbox(fig.bbox)
    writer = _canvas_pillow_writer()(fps=fps)
    with writer.saving(fig, str(path), dpi=dpi):
        for k, tf in enumerate(frame_times):
            canvas.restore_region(background)
            for key, hose, drogue, a, b in lines:
                j = j_off[idx_off[k]] if key == "off" else j_on[idx_on[k]]
                hose.set_data(j[:, a], j[:, b])
                drogue.set_data([j[-1, a]], [j[-1, b]])
                fig.draw_artist(hose)
                fig.draw_artist(drogue)
            stamp.set_text(f"t = {tf:5.1f} s")
            fig.draw_artist(stamp)
            writer.grab_frame()
    return path
