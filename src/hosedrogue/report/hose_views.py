"""Report sections "The hose in 3D" and "Animation": the hose shape in the turbulence runs of
the closed-loop section, controller off and PID on."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..spec.params import PAPER
from .markup import figure_html

if TYPE_CHECKING:
    from .closed_loop import ClosedLoopResult
    from .settings import ReportSettings
    from .writer import ReportFolder

__all__ = ["build_3d", "build_animation"]


def _shapes(off, on, window) -> list[tuple[np.ndarray, str]]:
    """Joint positions [m] at the balance position and at telling moments of the runs, with labels."""
    t = off.t_s
    m = (t >= window[0]) & (t <= window[1])
    k_lat = int(np.flatnonzero(m)[np.argmax(np.abs(off.drogue_offset_m[m, 1]))])
    k_ver = int(np.flatnonzero(m)[np.argmax(np.abs(off.drogue_offset_m[m, 2]))])
    k_mid = int(np.argmin(np.abs(t - 0.5 * (window[0] + window[1]))))
    return [(off.joints_m[0], "equilibrium (t = 0 s)"),
            (off.joints_m[k_lat], f"off, t = {t[k_lat]:.1f} s (largest lateral)"),
            (off.joints_m[k_ver], f"off, t = {t[k_ver]:.1f} s (largest vertical)"),
            (off.joints_m[k_mid], f"off, t = {t[k_mid]:.1f} s"),
            (on.joints_m[min(k_lat, on.t_s.size - 1)], f"PID on, t = {t[k_lat]:.1f} s")]


def build_3d(out: ReportFolder, settings: ReportSettings, *, closed_loop: ClosedLoopResult) -> None:
    """Write the 3-D view of the hose (PNG, CSV) and its section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Build settings (unused).
    closed_loop : hosedrogue.report.closed_loop.ClosedLoopResult
        The turbulence runs (controller off and PID are shown) and the turbulence window [s].

    Returns
    -------
    None
    """
    import pandas as pd

    from ..plotting.figures import plot_hose_3d

    shapes = _shapes(closed_loop.runs["off"], closed_loop.runs["PID"], closed_loop.window_s)
    rows = []
    for joints, label in shapes:
        for j, (x, y, z) in enumerate(joints):
            rows.append(dict(shape=label, joint=j, x_m=x, y_m=y, z_m=z))
    out.csv(pd.DataFrame(rows), "fig_hose3d.csv")
    out.figure(plot_hose_3d([s[0] for s in shapes], [s[1] for s in shapes]), "fig_hose3d.png")
    out.section("hose3d", "3D", (
        '<section id="hose3d"><h2>The hose in 3D</h2>'
        + figure_html("fig-hose3d", "fig_hose3d.png", "Hose shape",
                      f"The hose ({PAPER.hose.links} links, dots at the joints, big dot the drogue) at its balance "
                      "position and "
                      "at moments in the turbulence with the controller off, and with the PID on at the moment "
                      "of the largest lateral excursion. The axes are scaled independently: the lateral and "
                      "vertical excursions (about 1 m) are exaggerated relative to the 15 m length.",
                      ("fig_hose3d.csv",))
        + "</section>"
    ))
    return None


def _frames(runs: dict, window, fps: int) -> list[dict]:
    """Joint positions [m] of each run at the animation's frame times (the data behind the GIF)."""
    frame_t = np.arange(window[0], window[1] + 1e-9, 1.0 / fps)
    rows = []
    for key, r in runs.items():
        idx = np.clip(np.searchsorted(r.t_s, frame_t), 0, r.t_s.size - 1)
        for i in idx:
            for j, (x, y, z) in enumerate(r.joints_m[i]):
                rows.append(dict(run=key, t_s=r.t_s[i], joint=j, x_m=x, y_m=y, z_m=z))
    return rows


def build_animation(out: ReportFolder, settings: ReportSettings, *, closed_loop: ClosedLoopResult) -> None:
    """Write the GIF of the hose in turbulence (controller off and PID on), its data and section.

    Parameters
    ----------
    out : hosedrogue.report.writer.ReportFolder
        The report being written.
    settings : hosedrogue.report.settings.ReportSettings
        Frames per simulated second of the GIF [1/s].
    closed_loop : hosedrogue.report.closed_loop.ClosedLoopResult
        The turbulence runs and the turbulence window [s].

    Returns
    -------
    None
    """
    import pandas as pd

    from ..plotting.figures import animate_hose

    off, on = closed_loop.runs["off"], closed_loop.runs["PID"]
    window = closed_loop.window_s
    path = animate_hose(off, on, out.dir / "anim_turbulence.gif", fps=settings.anim_fps, window_s=window,
                        labels=("controller off", "PID on"))
    out.written(path)
    out.csv(pd.DataFrame(_frames({"off": off, "PID": on}, window, settings.anim_fps)), "anim_turbulence.csv")
    size_mb = path.stat().st_size / 1e6
    out.section("animation", "animation", (
        '<section id="animation"><h2>Animation: the hose in turbulence, controller off and on</h2>'
        f'<figure id="anim"><img src="anim_turbulence.gif" alt="hose animation">'
        f"<figcaption><b>Animation.</b> Side view (x-z) and rear view (y-z, from behind) of the hose and "
        f"drogue during the turbulence window ({window[0]:g}-{window[1]:g} s, {settings.anim_fps} frames per "
        f"simulated second, real time), controller off (red) and PID on (blue), same turbulence. "
        f"({size_mb:.1f} MB) <span class=data>Data: <a href=\"anim_turbulence.csv\">anim_turbulence.csv</a>."
        f"</span></figcaption></figure></section>"
    ))
    out.record("animation_size_mb", size_mb)
    return None
