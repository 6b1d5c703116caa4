"""The receiver aircraft's study (docs/receiver.md): the F-16's level-flight trim at sea level
against Stevens, Lewis & Johnson (2015) Table 3.6-2 (:func:`trim_check`), and the docking
campaign of the F-16 receiver (``approach-f16-moderate``) beside the point receiver
(``approach-moderate-docking``) on the same seeds (:func:`receiver_campaigns`): capture rates with
their Wilson intervals, the miss distributions and the paired differences of the misses.

Runs from Python without the report, and from ``hosedrogue study receiver`` (your approach beside
another, ``--scenario``/``--against``); the report's section "Receiver aircraft"
(:mod:`hosedrogue.report.receiver`) renders it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from decimal import Decimal
from pathlib import Path

import numpy as np

from ..aircraft.model_file import load_model
from ..aircraft.published import G_BOOK_FT_S2, TABLE_3_6_2
from ..aircraft.trim import trim
from ..constants import FT_TO_M

__all__ = ["SCENARIOS", "CAMPAIGN_SEED", "TrimCheck", "ReceiverCampaigns", "trim_check", "receiver_scenarios",
           "receiver_campaigns"]

#: The two receivers' scenarios, F-16 first: the same approach, controller and turbulence.
SCENARIOS = ("approach-f16-moderate", "approach-moderate-docking")

#: Campaign seed of both campaigns (run i of each flies the turbulence of run_seed(seed, i)).
CAMPAIGN_SEED = 0


def _half_unit(printed: float) -> float:
    """Half a unit of the last printed digit: a value that rounds to the printed one is within it."""
    return 0.5 * 10.0 ** Decimal(repr(printed)).as_tuple().exponent


@dataclass(frozen=True)
class TrimCheck:
    """The F-16's trims at the book's points and along a curve over its speed range."""

    table: object  #: pandas.DataFrame: per book point, printed and trimmed throttle, alpha, elevator, within
    curve: dict  #: ``airspeed_m_s``, ``throttle``, ``alpha_deg``, ``elevator_deg`` (n,) of the curve

    @property
    def within(self) -> int:
        """Book points whose three numbers all round to the printed ones [-]."""
        return int(self.table["within"].sum())

    def figure(self):
        """Throttle, alpha and elevator against airspeed beside the book's points
        (:func:`hosedrogue.studies.receiver_figures.plot_trim_curves`, as docs/img/receiver_trim.png)."""
        from .receiver_figures import plot_trim_curves

        book = np.array(TABLE_3_6_2) * np.array([FT_TO_M, 1.0, 1.0, 1.0])
        t, c = self.table, self.curve  # the line through the curve's trims and those at the book's speeds
        v = np.r_[c["airspeed_m_s"], t["airspeed_ft_s"].to_numpy() * FT_TO_M]
        k = np.argsort(v, kind="stable")
        ys = [np.r_[c[a], t[b].to_numpy()][k] for a, b in (("throttle", "throttle"), ("alpha_deg", "alpha_deg"),
                                                            ("elevator_deg", "elevator_deg"))]
        return plot_trim_curves(v[k], *ys, published=book,
                                published_label="Stevens, Lewis & Johnson (2015), Table 3.6-2",
                                title="F-16 (xcg 0.35) in level flight at sea level")


def trim_check(curve_points: int = 68) -> TrimCheck:
    """Trim the F-16 in level flight at sea level, under the book's g, at every speed of Table
    3.6-2 and at ``curve_points`` speeds over its range (130-800 ft/s).

    Parameters
    ----------
    curve_points : int
        Speeds of the curve [-] (each trim about 0.3 s of CPU, most of it the trim's search for a
        starting point; a speed of the book's is trimmed once).

    Returns
    -------
    TrimCheck
    """
    import pandas as pd

    f16, g = load_model("f16"), G_BOOK_FT_S2 * FT_TO_M
    rows, at_book = [], {}
    for speed, throttle, alpha, elevator in TABLE_3_6_2:
        t = at_book[speed * FT_TO_M] = trim(f16, speed * FT_TO_M, 0.0, gravity=g)
        got = (float(t.controls[0]), math.degrees(t.alpha_rad), float(t.controls[1]))
        ok = all(abs(a - b) <= _half_unit(b) for a, b in zip(got, (throttle, alpha, elevator)))
        rows.append({"airspeed_ft_s": speed, "throttle_book": throttle, "throttle": got[0], "alpha_deg_book": alpha,
                     "alpha_deg": got[1], "elevator_deg_book": elevator, "elevator_deg": got[2], "within": ok})
    speeds = np.linspace(130.0, 800.0, curve_points) * FT_TO_M
    # a speed of the book's on the curve (all 16 of them at 68 points, 10 ft/s apart) is not trimmed twice
    trims = [at_book[float(v)] if float(v) in at_book else trim(f16, v, 0.0, gravity=g) for v in speeds]
    curve = {"airspeed_m_s": speeds, "throttle": np.array([t.controls[0] for t in trims]),
             "alpha_deg": np.degrees([t.alpha_rad for t in trims]), "elevator_deg": np.array([t.controls[1] for t in trims])}
    return TrimCheck(pd.DataFrame(rows), curve)


@dataclass(frozen=True)
class ReceiverCampaigns:
    """Two receivers' campaigns on the same seeds (:func:`receiver_campaigns`; by default the F-16,
    then the point receiver)."""

    capture: dict  #: scenario -> summary.json's ``"capture"`` (rate, ci95 Wilson, runs, by_result)
    runs: object  #: pandas.DataFrame: per run index, seed, each scenario's result and miss [m]
    folders: dict  #: scenario -> campaign folder
    names: tuple = SCENARIOS  #: the two scenarios' names, the one compared first
    #: scenario -> its runs that stopped early (a diverging loop: ``completed`` false in runs.csv) [-]
    stopped: dict = field(default_factory=dict)
    capture_radius_m: float = math.nan  #: the first scenario's ``[probe] capture_radius_m`` [m]

    def miss(self, scenario: str) -> np.ndarray:
        """(runs,) the miss distance [m] of each run of ``scenario`` (NaN where none)."""
        return self.runs[f"miss_{scenario}"].to_numpy(dtype=np.float64)

    def paired(self) -> dict:
        """The first scenario's miss less the second's over the runs where both have one: ``runs``,
        ``mean_m``, its standard error ``se_m`` [m] and ``first_larger`` (runs where the first
        misses by more)."""
        d = self.miss(self.names[0]) - self.miss(self.names[1])
        d = d[np.isfinite(d)]
        n = d.size
        se = float(d.std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan
        return {"runs": int(n), "mean_m": float(d.mean()) if n else math.nan, "se_m": se,
                "first_larger": int((d > 0).sum())}

    def figure(self):
        """The two miss distributions (empirical CDFs) beside the first scenario's capture radius."""
        from ..plotting.base import new_figure
        from ..plotting.campaign import draw_miss_cdf

        fig, ax = new_figure(1, 1, size=(6.0, 4.0))
        for name, style in zip(self.names, ("-", "--")):
            draw_miss_cdf(ax, self.miss(name), label=f"{name} ({{n}} runs)", linestyle=style)
        ax.axvline(self.capture_radius_m, color="0.4", linestyle=":", linewidth=0.8,
                   label=f"capture radius {self.capture_radius_m:g} m")
        ax.set_xlabel("miss distance at the coupler plane [m]")
        ax.set_ylabel("fraction of runs [-]")
        ax.legend(loc="lower right", fontsize="small")
        return fig


def receiver_scenarios(first=SCENARIOS[0], second=SCENARIOS[1]) -> tuple:
    """The two approaches to compare, loaded and checked before anything runs.

    Parameters
    ----------
    first, second : str, Path or Scenario
        Shipped scenario names, TOML files or scenarios built in Python: engagements with a probe's
        approach (default the F-16's ``approach-f16-moderate``, then the point receiver's
        ``approach-moderate-docking``).

    Returns
    -------
    tuple of Scenario

    Raises
    ------
    ParameterError
        A scenario that is not an engagement, or the two of the same name (their campaign folders
        would be one).
    """
    from ..errors import ParameterError
    from ..scenarios import Scenario, load_scenario

    out = []
    for option, s in (("scenario", first), ("against", second)):
        sc = s if isinstance(s, Scenario) else load_scenario(s)
        out.append(sc.require_model("engagement", option, "the receiver study flies approaches (a [probe])"))
    if out[0].name == out[1].name:
        raise ParameterError(f"against = {out[1].name!r}: the same scenario name as the first; the two campaigns "
                             "need two names (their folders)")
    return tuple(out)


def receiver_campaigns(runs: int, out_dir, seed: int = CAMPAIGN_SEED, workers: int | None = None,
                       progress: bool = False, client=None, scenarios=SCENARIOS) -> ReceiverCampaigns:
    """Run (or resume) the campaigns of two approaches with ``runs`` seeds each into ``out_dir/<name>/``.

    Parameters
    ----------
    runs : int
        Runs per campaign [-], >= 1.
    out_dir : str or Path
        Parent folder of the two campaign folders.
    seed : int
        Campaign seed of both [-] (the same seeds: the runs pair).
    workers : int, optional
        Dask worker processes; None: run in this process.
    progress : bool
        Show the campaigns' progress bars (on a terminal).
    client : distributed.Client, optional
        Run on this dask client (not closed here) instead; not with ``workers``.
    scenarios : pair of str, Path or Scenario
        The two approaches (:func:`receiver_scenarios`; default :data:`SCENARIOS`, the F-16 then the
        point receiver).

    Returns
    -------
    ReceiverCampaigns
    """
    import pandas as pd

    from . import executor
    from .campaign import run_campaign

    pair = receiver_scenarios(*scenarios)
    capture, folders, frames, stopped = {}, {}, [], {}
    for spec, sc in zip(scenarios, pair):  # the campaign takes the name or file as given (its campaign.json)
        name = sc.name
        folder = Path(out_dir) / name
        summary = run_campaign(spec, runs, folder, seed=seed, workers=workers, progress=progress, client=client,
                               scheduler=None if workers or client is not None else executor.SYNCHRONOUS)
        capture[name], folders[name] = summary.capture, folder
        df = pd.read_csv(folder / "runs.csv").sort_values("run")
        stopped[name] = int((~df["completed"].astype(bool)).sum())
        frames.append(df[["run", "seed", "result", "miss_distance_m"]].rename(
            columns={"result": f"result_{name}", "miss_distance_m": f"miss_{name}"}).set_index(["run", "seed"]))
    table = frames[0].join(frames[1], how="inner").reset_index()
    return ReceiverCampaigns(capture, table, folders, tuple(sc.name for sc in pair), stopped,
                             pair[0].engagement.probe.capture_radius_m)
