"""Engagement figures: they return Figures (never show), label axes with units, and the GIF is written."""

import pytest
from matplotlib.figure import Figure

from hosedrogue.engagement import Probe, Reel, simulate_engagement
from hosedrogue.spec.params import PAPER
from hosedrogue.plotting.engagement import (animate_engagement, plot_drogue_region, plot_engagement_history,
                                            plot_hose_snapshots)


@pytest.fixture(scope="module")
def runs():
    p = PAPER.replace(hose={"links": 20, "link_inertia": "rod", "bending": "moment", "mass_lumping": "split"},
                      numerics={"step_s": 0.0025, "output_every": 8})
    return {law: simulate_engagement(p, 3.0, reel=Reel(law=law), probe=Probe()) for law in ("locked", "constant-tension")}


def test_history_and_snapshots_are_figures(runs):
    fig = plot_engagement_history(runs)
    assert isinstance(fig, Figure)
    for ax in fig.axes:
        if ax.get_ylabel():
            assert "[" in ax.get_ylabel()
    assert isinstance(plot_hose_snapshots(runs["locked"], [0.0, 2.0, 3.0]), Figure)
    assert isinstance(plot_drogue_region(runs, [2.0, 3.0]), Figure)


def test_animation_written(runs, tmp_path):
    path = animate_engagement(runs, tmp_path / "whip.gif", fps=5, speed=1.0, window_s=(1.8, 3.0))
    assert path.exists() and path.stat().st_size > 1000
