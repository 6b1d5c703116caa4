"""The campaign figures of a campaign none of whose runs completed: drawn without a warning (matplotlib's
"No artists with labels found to put in legend"), saying so on the figure; the figures of a
campaign with runs are drawn as before.
"""

import warnings

import numpy as np
import pandas as pd
import pytest

from hosedrogue import cli
from hosedrogue.plotting.campaign import plot_cdf, plot_histograms, plot_miss_cdf

#: 6 links, 1 s, the yaw limit so low (0.001 deg) that the turbulence from 0.1 s stops every run.
NONE_COMPLETES = """\
[scenario]
name = "none-completes"
duration_s = 1.0

[turbulence]
enabled = true
start_s = 0.1
duration_s = 0.9

[hose]
links = 6

[numerics]
max_yaw_deg = 0.001
"""


def _table(completed: bool) -> pd.DataFrame:
    values = [0.4, 0.5, 0.6] if completed else [np.nan] * 3
    cols = ("peak_radial_m", "rms_radial_m", "peak_dy_m", "peak_dz_m", "peak_u_n", "inside_0_3m")
    return pd.DataFrame({"run": [0, 1, 2], "controller": ["pid"] * 3, "completed": [completed] * 3,
                         **{c: values for c in cols}})


def _texts(fig) -> list[str]:
    return [t.get_text() for ax in fig.axes for t in ax.texts]


@pytest.mark.parametrize("plot", [plot_histograms, plot_cdf])
def test_no_completed_run_draws_a_note_and_no_warning(plot):
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        fig = plot(_table(False), ["pid"], [0.3])
        fig.canvas.draw()  # the whole figure rendered
    assert "no completed run" in _texts(fig)
    assert all(ax.get_legend() is None for ax in fig.axes)


@pytest.mark.parametrize("plot", [plot_histograms, plot_cdf])
def test_completed_runs_keep_their_legend(plot):
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        fig = plot(_table(True), ["pid"], [0.3])
    assert "no completed run" not in _texts(fig)
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == ["controller pid"]


def test_no_miss_draws_the_capture_radius_alone():
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        fig = plot_miss_cdf(np.full(3, np.nan), 0.3)
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == ["capture radius 0.3 m"]


@pytest.mark.filterwarnings("error::UserWarning")
def test_a_campaign_of_which_no_run_completes_writes_its_figures_without_a_warning(tmp_path, capsys):
    """montecarlo end to end: every run stops at the yaw limit (exit 3), the figures are written,
    and no UserWarning is raised anywhere on the way (an error here)."""
    path = tmp_path / "none.toml"
    path.write_text(NONE_COMPLETES)
    out = tmp_path / "out"
    code = cli.main(["montecarlo", str(path), "--runs", "2", "--scheduler", "synchronous", "--quiet",
                     "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 3, err
    assert (out / "histograms.png").exists() and (out / "cdf.png").exists()
