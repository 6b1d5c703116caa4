"""The tanker's manoeuvres as studies (docs/model.md §9): the balance position against the bank and
flight-path angles, a turn taken apart, the transient of a turn entry with and without the paper's
PID, and the capture rate of the receiver's approach in a turn against level flight.

Every part is a library call the report presents (:mod:`hosedrogue.report.manoeuvres`):

* :func:`steady_flight_study` - :func:`hosedrogue.analysis.steady_flight.sweep_steady` over the
  bank and the flight-path angle and :func:`~hosedrogue.analysis.steady_flight.turn_breakdown`;
* :func:`turn_entry_study` - the shipped ``turn-entry-30`` open loop and with the paper's PID,
  its figures of merit (:class:`TurnEntry`);
* :func:`turn_capture_study` - Monte Carlo campaigns (:func:`hosedrogue.studies.campaign.run_campaign`)
  of ``approach-moderate`` and ``approach-turn-moderate`` with the same campaign seed (common
  random numbers: run i sees the same turbulence record in both), their capture rates with Wilson
  intervals.

Example
-------
::

    from hosedrogue.studies.manoeuvres import turn_entry_study
    entry = turn_entry_study()
    print(entry.settling_time_s, entry.pid_peak_offset_m)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..analysis.equilibrium import solve_equilibrium
from ..analysis.steady_flight import SteadySweep, TurnBreakdown, steady_params, sweep_steady, turn_breakdown
from ..spec.params import PAPER, Params

#: The shipped scenario of the turn entry, and the approach campaigns: (label, scenario).
TURN_ENTRY = "turn-entry-30"
CAPTURE_SCENARIOS = (("level flight", "approach-moderate"), ("25-degree turn", "approach-turn-moderate"))
#: Bank angle [deg] of the turn taken apart (the approach's turn).
BREAKDOWN_BANK_DEG = 25.0
#: Bands [m] of the settling times: the drogue within them of the turn's balance position for good.
SETTLING_BANDS_M = (0.01, 0.001)
#: Campaign seed of the capture campaigns [-].
CAMPAIGN_SEED = 2024


@dataclass(frozen=True)
class SteadyFlightStudy:
    """The balance position in steady turns and climbs."""

    bank: SteadySweep  #: over the bank angle [deg], level
    flight_path: SteadySweep  #: over the flight-path angle [deg], wings level
    breakdown: TurnBreakdown  #: the turn of :data:`BREAKDOWN_BANK_DEG` taken apart (continuous hose)

    def figures(self) -> dict:
        """The study's figure (:func:`hosedrogue.studies.manoeuvres_figures.plot_steady_flight`).

        Returns
        -------
        dict
            ``{"steady_flight": matplotlib.figure.Figure}``.
        """
        from .manoeuvres_figures import plot_steady_flight

        return {"steady_flight": plot_steady_flight(self.bank, self.flight_path)}


def steady_flight_study(params: Params = PAPER, banks_deg=(0, 15, 30, 45), paths_deg=(-10, 0, 10),
                        breakdown_bank_deg: float = BREAKDOWN_BANK_DEG) -> SteadyFlightStudy:
    """Balance positions over the bank and flight-path angles, and one turn taken apart.

    Parameters
    ----------
    params : Params
        The model and flight condition (the paper's by default).
    banks_deg : sequence of float
        Bank angles [deg].
    paths_deg : sequence of float
        Flight-path angles [deg].
    breakdown_bank_deg : float
        Bank angle [deg] of :func:`~hosedrogue.analysis.steady_flight.turn_breakdown`.

    Returns
    -------
    SteadyFlightStudy
    """
    return SteadyFlightStudy(sweep_steady(params, "bank_deg", banks_deg),
                             sweep_steady(params, "flight_path_deg", paths_deg),
                             turn_breakdown(params, breakdown_bank_deg))


@dataclass(frozen=True)
class TurnEntry:
    """The turn entry ``turn-entry-30`` open loop and with the paper's PID (tanker body axes)."""

    t_s: np.ndarray  #: time [s] (k,)
    bank_deg: np.ndarray  #: the tanker's bank angle [deg] (k,)
    open_loop_m: np.ndarray  #: drogue position without control (k, 3) [m]
    pid_m: np.ndarray  #: drogue position with the paper's PID (k, 3) [m]
    pid_force_n: np.ndarray  #: the PID's force on the drogue [u_y, u_z] (k, 2) [N]
    level_m: np.ndarray  #: the level balance position (3,) [m] (the PID's reference)
    turn_m: np.ndarray  #: the turn's balance position (3,) [m]
    roll_start_s: float  #: when the roll begins [s]
    roll_end_s: float  #: when the bank reaches its target [s]
    settling_time_s: dict  #: band [m] -> time after the roll's end the drogue stays within it [s] (NaN: not in the run)
    peak_offset_m: np.ndarray  #: largest |dy|, |dz| from the level position, open loop (2,) [m]
    overshoot_m: float  #: largest distance from the turn's balance position after the roll's end, open loop [m]
    pid_peak_offset_m: float  #: largest radial offset from the reference with the PID [m]
    pid_final_force_n: np.ndarray  #: the PID's force at the end, holding the drogue in the turn (2,) [N]
    completed: bool  #: both runs completed


def settling_time(t_s: np.ndarray, distance_m: np.ndarray, band_m: float, after_s: float) -> float:
    """Time after ``after_s`` from which the distance stays within ``band_m`` to the end [s]; NaN if
    it is outside at the end.

    Parameters
    ----------
    t_s : array
        Times [s].
    distance_m : array
        Distance from the target [m].
    band_m : float
        The band [m].
    after_s : float
        Reference time [s] (the manoeuvre's end).

    Returns
    -------
    float
    """
    outside = np.nonzero(distance_m > band_m)[0]
    if outside.size and outside[-1] == t_s.size - 1:
        return float("nan")
    last = t_s[outside[-1] + 1] if outside.size else t_s[0]
    return max(float(last) - after_s, 0.0)


def _bank_history(params: Params, t_s: np.ndarray) -> np.ndarray:
    """The bank angle [deg] at the given times, from the compiled flight state."""
    from ..model.frame import flight_state
    from ..model.system import HoseModel

    model = HoseModel(params)
    at = model.env.size - model.motion_table.size
    return np.degrees([flight_state(float(t), model.env, at)[0] for t in t_s])


def turn_entry_study(duration_s: float | None = None) -> TurnEntry:
    """Run ``turn-entry-30`` open loop and with the paper's PID; its figures of merit.

    Parameters
    ----------
    duration_s : float, optional
        Simulated time [s] (default the scenario's).

    Returns
    -------
    TurnEntry
    """
    from ..scenarios import load_scenario
    from ..scenarios.runner import run

    sc = load_scenario(TURN_ENTRY).with_overrides(duration_s=duration_s)
    open_loop, pid = run(sc), run(sc.with_controller("pid"))
    motion = sc.params.tanker_motion
    ramp = motion.ramps(sc.params.flight.airspeed_m_s)[0]
    final_bank, final_path, _ = motion.final(sc.params.flight.airspeed_m_s)
    turn = solve_equilibrium(steady_params(sc.params, np.degrees(final_bank), np.degrees(final_path))).drogue_position_m
    level = open_loop.equilibrium_m
    t = open_loop.t_s
    dist = np.linalg.norm(open_loop.drogue_position_m - turn, axis=1)
    after = t >= ramp.end_s
    settle = {band: settling_time(t, dist, band, ramp.end_s) for band in SETTLING_BANDS_M}
    pid_off = np.linalg.norm(pid.drogue_position_m[:, 1:] - level[1:], axis=1)
    return TurnEntry(t, _bank_history(sc.params, t), open_loop.drogue_position_m, pid.drogue_position_m,
                     pid.control_force_n, level, turn, ramp.start_s, ramp.end_s, settle,
                     np.max(np.abs(open_loop.drogue_position_m[:, 1:] - level[1:]), axis=0),
                     float(np.max(dist[after])), float(np.max(pid_off)), pid.control_force_n[-1].copy(),
                     bool(open_loop.completed and pid.completed))


@dataclass(frozen=True)
class TurnCapture:
    """Capture rates of the approach in level flight and in the turn (the same seeds)."""

    labels: tuple  #: e.g. ("level flight", "25-degree turn")
    scenarios: tuple  #: the shipped scenarios' names
    capture: tuple  #: per label: the campaign's capture block (rate [-], ci95 [-], runs, by_result)
    runs: tuple  #: per label: pandas.DataFrame of the campaign's runs.csv
    folders: tuple  #: the campaign folders

    def overlap(self) -> bool:
        """Whether the two 95 % Wilson intervals overlap."""
        (a0, a1), (b0, b1) = (c["ci95"] for c in self.capture)
        return a0 <= b1 and b0 <= a1


def turn_capture_study(runs: int, out_dir, workers: int | None = None, seed: int = CAMPAIGN_SEED,
                       progress: bool = False, client=None) -> TurnCapture:
    """Campaigns of the approach in moderate turbulence in level flight and in a 25-degree turn.

    Parameters
    ----------
    runs : int
        Runs per campaign [-], >= 1.
    out_dir : str or Path
        Parent folder of the two campaign folders (created; a folder holding the same campaign is
        resumed).
    workers : int, optional
        Dask worker processes [-]; None: in this process.
    seed : int
        Campaign seed [-] (the same for both: common random numbers).
    progress : bool
        Show the campaigns' progress bars on stderr.
    client : distributed.Client, optional
        Run on this dask client (not closed here) instead; not with ``workers``.

    Returns
    -------
    TurnCapture
    """
    from .campaign import run_campaign
    from .executor import SYNCHRONOUS

    out = Path(out_dir)
    local = workers is None and client is None
    summaries = [run_campaign(name, runs, out / name, workers=workers, seed=seed, progress=progress, client=client,
                              scheduler=SYNCHRONOUS if local else None)
                 for _, name in CAPTURE_SCENARIOS]
    return TurnCapture(tuple(lbl for lbl, _ in CAPTURE_SCENARIOS), tuple(n for _, n in CAPTURE_SCENARIOS),
                       tuple(s.capture for s in summaries), tuple(s.runs for s in summaries),
                       tuple(out / n for _, n in CAPTURE_SCENARIOS))
