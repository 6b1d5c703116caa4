"""Figures of simulation results. Every function returns a matplotlib Figure (no ``show()``,
no backend selected); axes carry units. Import cost stays out of the model: matplotlib loads here only.

Figures are built on :func:`new_figure`, which creates figures outside pyplot's global state, so
a long-running process (or a test suite) never accumulates pyplot figures. The functions take
*data* (arrays, result objects, mappings of labelled curves) and do no physics: the reproduction
report (:mod:`hosedrogue.report`) computes the data, writes it to CSV and hands it to these.

Conventions shared by the functions below:

- channels are ``"lateral"`` (u_hor [N] -> P_ny [m], drogue y, right positive) and
  ``"vertical"`` (u_ver [N] -> P_nz [m], drogue z, down positive);
- a *curve mapping* is ``{label: {"lateral": array, "vertical": array}}``; each label becomes
  one line in both channel panels, in the mapping's order;
- ``reference`` arguments (the paper's published models) are drawn dashed.

This module gathers the figure functions, which live by topic in :mod:`.base` (figure creation
and saving), :mod:`.steady` (Figs. 3-4), :mod:`.linear` (Figs. 5-8, 10-11), :mod:`.nonlinear`
(Figs. 12-13, 3-D view) and :mod:`.animation`; a study's own figures are beside it in
:mod:`hosedrogue.studies` (``<study>_figures``).
"""

from __future__ import annotations

from .animation import animate_hose
from .base import CHANNELS, new_figure, save_figure
from .linear import plot_bode_compare, plot_closed_loop_steps, plot_linear_steps, plot_pole_zero, plot_step_compare
from .nonlinear import plot_control_forces, plot_controller_on_off, plot_hose_3d
from .steady import plot_displacement, plot_sweep, plot_turbulence_speeds

__all__ = [
    "new_figure", "save_figure", "plot_displacement", "plot_sweep", "plot_turbulence_speeds",
    "plot_linear_steps", "plot_pole_zero", "plot_bode_compare", "plot_step_compare",
    "plot_closed_loop_steps", "plot_controller_on_off", "plot_control_forces", "plot_hose_3d",
    "animate_hose", "CHANNELS",
]
