"""Docking campaigns: the capture rate of the approach scenarios per cell of a grid (turbulence
level x drogue controller x bow wave, the pilot model, the closure speed, the force limit), each
cell a Monte Carlo campaign of :func:`hosedrogue.studies.campaign.run_campaign` in its own folder,
and one approach seen from behind (docs/engagement.md, "Docking statistics").

The cells and their scenarios are :mod:`.docking_grid`'s; the tables and findings over the cells
:mod:`.docking_statistics`'s; the bow-wave study :mod:`.bow_wave`'s. Every cell uses the same
campaign seed, so run ``i`` sees the same turbulence record in every cell of a level and duration
(common random numbers). Two cells whose scenarios are the same (:func:`.docking_grid.same_scenario`)
are run once: the 1 m/s cell of the closure-speed study *is* the main grid's campaign.

Each cell's folder ``OUT/<cell>/`` is a campaign folder (campaign.json, runs.csv, summary.json,
summary.csv and the figures). Its scenario is recorded in campaign.json (``"scenario"``: the
tables of a scenario file); ``scenario_from_dict(json.load(f)["scenario"])`` rebuilds it. Running
again into the same folder resumes the campaigns (same runs and seed) or is refused (others).

Example
-------
Two controllers in moderate turbulence with the bow wave on and off, 20 runs per cell, in this
process (about a second per run)::

    from hosedrogue.studies.docking import grid_specs, run_grid
    from hosedrogue.studies.docking_statistics import capture_table, compare

    specs = grid_specs(levels=("moderate",), controllers=("none", "pid"), pilot_levels=())
    cells = run_grid(specs, runs=20, out_dir="out/dock")
    table = capture_table(cells)            # one row per cell: rate, Wilson interval, counts
    print(table[["campaign", "rate", "ci95_low", "ci95_high"]])
    print(compare(table, dict(controller="pid", bow_wave=True), dict(controller="none", bow_wave=True)))

From the command line: ``hosedrogue study docking --runs 20 --levels moderate --out out/dock``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from .docking_grid import (CAMPAIGN_SEED, CONTROLLERS, LEVELS, PILOT, CellSpec, cell_scenario, force_specs,
                           grid_specs, same_scenario, speed_specs)

__all__ = ["APPROACH_RUNS", "APPROACH_SEED", "CampaignCell", "run_grid", "approach_runs", "approach_path",
           "approach_paths", "CellSpec", "grid_specs", "speed_specs", "force_specs", "CONTROLLERS", "LEVELS", "PILOT",
           "CAMPAIGN_SEED"]

#: Runs of the approach seen from behind: label -> (controller, pilot flies the probe). "pilot": no
#: drogue controller, the probe flown by the pilot model's defaults (docs/engagement.md, "Pilot model").
APPROACH_RUNS = {"none": ("none", False), "pid": ("pid", False), "pilot": ("none", True)}

#: Turbulence seed of the approach seen from behind (the shipped scenarios' seed).
APPROACH_SEED = 2018


@dataclass(frozen=True)
class CampaignCell:
    """One campaign of the grid and what it gave."""

    level: str  #: turbulence level
    controller: str  #: drogue controller type
    bow_wave: bool  #: bow wave on
    sigma_m_s: float  #: vertical turbulence intensity of the level at the scenario's altitude [m/s]
    capture: dict  #: the summary's capture block: rate [-], ci95 [-], runs, by_result
    runs: object  #: pandas.DataFrame of the campaign's runs.csv, sorted by run
    folder: Path  #: the campaign folder
    pilot: bool = False  #: the pilot model flew the probe
    closure_speed_m_s: float = 1.0  #: the probe's closure speed [m/s]
    duration_s: float = 4.5  #: the scenario's duration [s]
    scenario: object = None  #: the hosedrogue.scenarios.Scenario the campaign ran

    @property
    def name(self) -> str:
        """The campaign's folder name (a cell whose scenario is another cell's shares its campaign)."""
        return self.folder.name


def _check_counts(cell: CampaignCell, runs: int) -> None:
    """Each run counted once: the results add up to the runs, and the rate lies in its interval."""
    cap = cell.capture
    if cap["runs"] != runs or sum(cap["by_result"].values()) != runs or len(cell.runs) != runs:
        raise RuntimeError(f"campaign {cell.name}: by_result {cap['by_result']} does not add up to {runs} runs")
    lo, hi = cap["ci95"]
    if not lo <= cap["rate"] <= hi:
        raise RuntimeError(f"campaign {cell.name}: rate {cap['rate']} outside its interval {cap['ci95']}")


def _check_int(name: str, value, lo: int) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < lo:
        raise ParameterError(f"{name} = {value!r}: must be an integer >= {lo}")


def _check_workers(workers, client) -> None:
    from . import executor

    if workers is not None and client is not None:
        raise ParameterError("workers, client: give at most one of them")
    if workers is None:
        return
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or not 1 <= workers <= 4096:
        raise ParameterError(f"workers = {workers!r}: must be an integer in [1, 4096] or None (this process)")
    if not executor.dask_available():
        raise ParameterError(f"workers = {workers}: needs dask.distributed (pip install 'hosedrogue[dask]')")


def _run_cell(spec: CellSpec, scenario, runs: int, folder: Path, seed: int, client, progress: bool,
              plots: bool = True) -> CampaignCell:
    """One cell's campaign into ``folder`` (on ``client``, or in this process when None), with the
    campaign's own figures or without them (``plots``, :func:`run_grid`)."""
    from . import executor
    from .campaign import run_campaign

    summary = run_campaign(scenario, runs, folder, seed=seed, progress=progress, client=client,
                           scheduler=None if client is not None else executor.SYNCHRONOUS, plots=plots)
    cell = CampaignCell(spec.level, spec.controller, spec.bow_wave, float(scenario.params.turbulence.sigma_m_s[2]),
                        summary.capture, summary.runs, folder, spec.pilot,
                        float(scenario.engagement.probe.closure_speed_m_s), float(scenario.duration_s), scenario)
    _check_counts(cell, runs)
    return cell


def _share_key(scenario, runs: int, seed: int) -> str:
    """What a campaign of the grid is, as a file name: the digest of its scenario (every table of
    it, its name among them), runs and seed."""
    import hashlib
    import json

    from .. import jsonio

    text = json.dumps(jsonio.plain({"scenario": scenario.to_dict(), "runs": runs, "seed": seed}), sort_keys=True,
                      allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _shared_cell(spec: CellSpec, scenario, runs: int, folder: Path, seed: int, client, progress: bool,
                 share: Path, plots: bool = True) -> CampaignCell:
    """:func:`_run_cell`, once per build: under a lock on the campaign's key in ``share``, a campaign
    another grid of the build ran (its folder named in ``share/<key>``) is copied into ``folder``
    and resumed there (nothing left to run: its runs.csv and summary are that campaign's);
    else it runs and is registered. The lock waits for a campaign another process is running."""
    import shutil

    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX: each grid runs its own
        return _run_cell(spec, scenario, runs, folder, seed, client, progress, plots)
    key = share / _share_key(scenario, runs, seed)
    with open(key.with_suffix(".lock"), "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes, also on an error
        done = Path(key.read_text(encoding="utf-8")) if key.exists() else None
        if done is not None and done != folder and not folder.exists():
            shutil.copytree(done, folder, ignore=shutil.ignore_patterns(".lock"))
        cell = _run_cell(spec, scenario, runs, folder, seed, client, progress, plots)
        key.write_text(str(folder), encoding="utf-8")
    return cell


def run_grid(specs, runs: int, out_dir, workers: int | None = None, client=None, seed: int = CAMPAIGN_SEED,
             status=None, progress: bool = False, base=None, share=None, plots: bool = True) -> list[CampaignCell]:
    """Run the campaign of every cell into ``out_dir/<cell>/``, on one dask cluster or in this process.

    A cell whose scenario (:func:`.docking_grid.cell_scenario`) is that of an earlier cell is not
    run again: it is that cell's campaign (e.g. the closure speed 1 m/s of approach-moderate is the
    main grid's ``moderate-none-bow-on``). A folder that already holds a cell's campaign with the
    same settings is resumed (its finished runs kept); with other settings it is an error.

    Parameters
    ----------
    specs : sequence of CellSpec
        The cells (:func:`.docking_grid.grid_specs`, :func:`.docking_grid.speed_specs`,
        :func:`.docking_grid.force_specs`, or any list).
    runs : int
        Runs (turbulence seeds) per cell [-], >= 1.
    out_dir : str or Path
        Parent folder of the campaigns (created if needed).
    workers : int or None
        Dask worker processes of a local cluster shared by all cells [-]; None: run in this
        process (no dask) unless ``client`` is given.
    client : distributed.Client, optional
        Run on this dask client (not closed here) instead.
    seed : int
        Campaign seed of every cell [-], >= 0 (run i uses ``run_seed(seed, i)``).
    status : callable, optional
        ``status(text)`` is told which cell runs.
    progress : bool
        Show each campaign's progress bar on stderr (only when it is a terminal).
    base : hosedrogue.scenarios.Scenario, optional
        The user's approach scenario instead of the shipped ``approach-LEVEL``
        (:func:`.docking_grid.cell_scenario`).
    share : str or Path, optional
        A folder (it exists) where the grids of one job register their campaigns, so that a
        campaign two grids hold is run once: the second grid copies the first's folder (the report
        build's docking and actuated-drogue sections share the ideal-force cells this way, from
        two processes: a grid waits while another runs the campaign it needs). Only for grids run
        afresh within one job: a registered folder must not change afterwards.
    plots : bool
        Draw each cell's campaign figures (``histograms.png``, ``cdf.png``, ``miss_cdf.png``); the
        report's sections, which draw their figures from all the cells, leave them out (about 0.5 s
        of CPU per cell; ``hosedrogue.studies.statistics.summarize_campaign(folder)`` draws them).

    Returns
    -------
    list of CampaignCell
        One cell per spec, in their order (the same object for cells of the same scenario).

    Raises
    ------
    ParameterError
        On bad input (``runs``, ``seed``, ``workers``, ``client``, a cell's level or controller),
        or a cell folder holding a campaign with other settings.
    """
    from . import executor

    _check_int("runs", runs, 1)
    _check_int("seed", seed, 0)
    _check_workers(workers, client)
    if not isinstance(plots, bool):
        raise ParameterError(f"plots = {plots!r}: must be True or False")
    specs = list(specs)
    scenarios = [cell_scenario(spec, base) for spec in specs]  # bad cells fail here, before anything runs
    out = Path(out_dir)
    done: list[CampaignCell] = []
    cells = []
    with executor.dask_client(client, workers, None, client is not None or workers is not None) as dask_client:
        for spec, scenario in zip(specs, scenarios):
            same = next((c for c in done if same_scenario(c.scenario, scenario)), None)
            if same is None:
                if status:
                    status(f"docking campaign {spec.name}")
                if share is None:
                    same = _run_cell(spec, scenario, runs, out / spec.name, seed, dask_client, progress, plots)
                else:
                    same = _shared_cell(spec, scenario, runs, out / spec.name, seed, dask_client, progress, Path(share),
                                        plots)
                done.append(same)
            cells.append(same)
    return cells


def approach_path(r) -> dict:
    """A run's probe-tip and drogue paths in the y-z plane up to contact (the whole run without).

    Parameters
    ----------
    r : hosedrogue.results.run.EngagementResult
        An approach run.

    Returns
    -------
    dict
        As one entry of :func:`approach_paths`.
    """
    tc = r.outcome.get("contact_time_s")
    end = float(tc) if tc is not None else float(r.t_s[-1])
    keep = r.t_s <= end
    path = {"t_s": r.t_s[keep], "probe_yz_m": r.probe_position_m[keep][:, 1:],
            "drogue_yz_m": r.drogue_position_m[keep][:, 1:], "outcome": dict(r.outcome)}
    if tc is not None:
        path["contact_probe_yz_m"] = np.array([np.interp(end, r.t_s, r.probe_position_m[:, j]) for j in (1, 2)])
        path["contact_drogue_yz_m"] = np.array([np.interp(end, r.t_s, r.drogue_position_m[:, j]) for j in (1, 2)])
    return path


def approach_runs(level: str = "moderate", runs=("none", "pid"), seed: int = APPROACH_SEED) -> dict:
    """One approach of ``approach-LEVEL`` per entry of ``runs``, on one turbulence seed.

    Parameters
    ----------
    level : str
        Turbulence level of the ``approach-LEVEL`` scenario.
    runs : sequence of str
        Keys of :data:`APPROACH_RUNS` (a controller type, or "pilot"), one run each.
    seed : int
        Turbulence seed [-], >= 0.

    Returns
    -------
    dict
        ``label -> hosedrogue.results.run.EngagementResult``.
    """
    from ..scenarios import load_scenario
    from ..scenarios.runner import run
    from ..spec.sections import Pilot

    unknown = [c for c in runs if c not in APPROACH_RUNS]
    if unknown:
        raise ParameterError(f"runs = {tuple(runs)!r}: unknown {unknown[0]!r}; allowed: {', '.join(APPROACH_RUNS)}")
    base = load_scenario(f"approach-{level}").with_overrides(seed=seed)
    out = {}
    for c in runs:
        controller, piloted = APPROACH_RUNS[c]
        sc = base.with_controller(controller)
        if piloted:
            sc = dataclasses.replace(sc, engagement=dataclasses.replace(sc.engagement, pilot=Pilot(enabled=True)))
        out[c] = run(sc)
    return out


def approach_paths(level: str = "moderate", runs=("none", "pid"), seed: int = APPROACH_SEED) -> dict:
    """Probe-tip and drogue paths in the y-z plane of one approach, up to contact
    (:func:`approach_path` of each of :func:`approach_runs`).

    Parameters
    ----------
    level : str
        Turbulence level of the ``approach-LEVEL`` scenario.
    runs : sequence of str
        Keys of :data:`APPROACH_RUNS` (a controller type, or "pilot"), one run each.
    seed : int
        Turbulence seed [-], >= 0.

    Returns
    -------
    dict
        ``label -> {"probe_yz_m", "drogue_yz_m" (N, 2) [m], "t_s" (N,) [s], "outcome": dict,
        and with contact "contact_probe_yz_m", "contact_drogue_yz_m" (2,) [m]}``.
    """
    return {c: approach_path(r) for c, r in approach_runs(level, runs, seed).items()}
