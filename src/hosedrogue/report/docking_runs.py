"""The computations of the report's "Docking" section (:mod:`.docking`): the bow-wave field and
the drogue's steady displacement, the campaigns of the approach scenarios (turbulence level x
controller x bow wave) and one approach seen from behind.

The campaigns run through :func:`hosedrogue.studies.campaign.run_campaign`, which takes a
scenario by name or file: each cell's scenario (the shipped ``approach-LEVEL`` with
``[controller] type`` and ``[bow_wave] enabled`` set) is written as ``scenario.toml`` into the
cell's campaign folder and run from there. Every cell uses the same campaign seed, so run ``i``
sees the same turbulence record in every cell of a level (common random numbers). A cell is a
:class:`CellSpec`: besides the drogue controller and the bow wave it may let the pilot model fly
the probe (:data:`PILOT`) or change the probe's closure speed (with the scenario's duration, and
its turbulence window, following the speed: :func:`approach_duration_s`) or limit the controller's
force (``[actuator] max_force_n``); two cells whose scenarios are the same are run once (:func:`run_grid`).
"""

from __future__ import annotations

import dataclasses
import json
import math
import shutil
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["CONTROLLERS", "LEVELS", "PILOT", "CellSpec", "CampaignCell", "BowWaveStudy", "bow_wave_study", "run_grid",
           "grid_specs", "approach_paths", "APPROACH_RUNS", "cell_name", "scenario_toml", "scenario_data",
           "approach_duration_s"]

#: Controllers of the campaigns and of the approach figure, in the order of the legends (the
#: paper's gains; each acts on the drogue during the approach and is off once coupled).
CONTROLLERS = ("none", "pid", "lqr")

#: The pilot model flying the probe (docs/engagement.md, "Pilot model", its defaults) with no drogue
#: controller: not a drogue controller but a row of the grid beside them, bow wave on only (cells
#: ``<level>-pilot-bow-on``), so the receiver's own chase compares with the drogue's station keeping.
PILOT = "pilot"

#: Runs of the approach figure: label -> (controller, pilot flies the probe). "pilot": no drogue
#: controller, the probe flown by the pilot model's defaults (docs/engagement.md, "Pilot model").
APPROACH_RUNS = {"none": ("none", False), "pid": ("pid", False), "pilot": ("none", True)}

#: Turbulence levels of the shipped approach scenarios (``approach-LEVEL``), in the order of the x axis.
LEVELS = ("light", "moderate", "severe")

#: Probe distances aft of the drogue of the displacement curve [m].
DISTANCES_M = tuple(float(d) for d in np.geomspace(0.3, 20.0, 16))

#: Forebody radii of the far-displacement table [m].
RADII_M = (0.3, 0.45, 0.6, 0.75, 1.0)

#: The near and far probe distances read out [m], and the far displacement's requirement [m].
NEAR_M, FAR_M, LEVEL_M = 0.5, 10.0, 1e-3

#: Campaign seed of every cell (run i uses run_seed(CAMPAIGN_SEED, i)).
CAMPAIGN_SEED = 0

#: Dask workers of the full version's campaigns (the fast version runs them in this process).
WORKERS = 2

#: Turbulence seed of the approach seen from behind (the shipped scenarios' seed).
APPROACH_SEED = 2018


def cell_name(level: str, controller: str, bow_wave: bool, pilot: bool = False,
              closure_speed_m_s: float | None = None, max_force_n: float | None = None) -> str:
    """Folder name of one campaign, e.g. ``moderate-pid-bow-on``, ``moderate-pilot-bow-on``,
    ``moderate-none-bow-on-v0.5`` or ``moderate-pid-bow-on-f100``.

    Parameters
    ----------
    level : str
        Turbulence level ("light", "moderate", "severe").
    controller : str
        Drogue controller type ("none", "pid", "lqr").
    bow_wave : bool
        Bow wave on.
    pilot : bool
        The pilot model flies the probe (named ``pilot`` in place of the controller "none").
    closure_speed_m_s : float or None
        The probe's closure speed [m/s] when it is not the scenario's own (suffix ``-v<speed>``).
    max_force_n : float or None
        The actuator's force limit per axis [N] (suffix ``-f<limit>``); None: unlimited.

    Returns
    -------
    str
    """
    who = (PILOT if controller == "none" else f"{controller}-{PILOT}") if pilot else controller
    name = f"{level}-{who}-bow-{'on' if bow_wave else 'off'}"
    name = name if closure_speed_m_s is None else f"{name}-v{closure_speed_m_s:g}"
    return name if max_force_n is None else f"{name}-f{max_force_n:g}"


@dataclass(frozen=True)
class CellSpec:
    """What one campaign of the grid runs: ``approach-LEVEL`` with these changes."""

    level: str  #: turbulence level
    controller: str = "none"  #: drogue controller type
    bow_wave: bool = True  #: bow wave on
    pilot: bool = False  #: the pilot model flies the probe
    closure_speed_m_s: float | None = None  #: probe closure speed [m/s]; None: the scenario's own
    max_force_n: float | None = None  #: ``[actuator] max_force_n``, per axis [N]; None: unlimited

    @property
    def name(self) -> str:
        """The cell's folder name."""
        return cell_name(self.level, self.controller, self.bow_wave, self.pilot, self.closure_speed_m_s,
                         self.max_force_n)


def grid_specs(levels=LEVELS, controllers=CONTROLLERS, pilot_levels=LEVELS) -> list[CellSpec]:
    """The main grid: level x controller x bow wave (on, off), and the pilot's cell (bow wave on)
    for each of ``pilot_levels``, in table order.

    Parameters
    ----------
    levels : sequence of str
        Turbulence levels.
    controllers : sequence of str
        Drogue controller types.
    pilot_levels : sequence of str
        Levels that get a pilot cell (empty: none).

    Returns
    -------
    list of CellSpec
    """
    specs = []
    for level in levels:
        specs += [CellSpec(level, c, True) for c in controllers]
        if level in pilot_levels:
            specs.append(CellSpec(level, "none", True, pilot=True))
        specs += [CellSpec(level, c, False) for c in controllers]
    return specs


def approach_duration_s(probe, closure_speed_m_s: float) -> float:
    """Scenario duration for a closure speed: the time at which the prescribed probe path stops if
    contact is at the balance position, rounded up to 0.1 s.

    The probe reaches the balance position after ``standoff_m / v``; once coupled it cruises
    ``max(push_m - v stop_time_s / 2, 0)`` and stops over ``stop_time_s`` (the half-cosine ramp
    covers ``v stop_time_s / 2``). The shipped approach scenarios' 4.5 s is this at 1 m/s (3 m, 1 m
    of push, 1 s stop), so the 1 m/s cell is the shipped scenario. The push is the margin for
    contact: a drogue up to ``push_m + v stop_time_s / 2`` (1.5 m at 1 m/s) ahead of its balance
    position is still met; a run that is not would be counted "no contact".

    Parameters
    ----------
    probe : hosedrogue.engagement.spec.Probe
        The scenario's probe: ``standoff_m`` [m], ``push_m`` [m], ``stop_time_s`` [s].
    closure_speed_m_s : float
        Probe closure speed v [m/s], > 0.

    Returns
    -------
    float
        Duration [s].
    """
    v = float(closure_speed_m_s)
    after = max(probe.push_m - 0.5 * v * probe.stop_time_s, 0.0) / v + probe.stop_time_s
    return math.ceil(round((probe.standoff_m / v + after) * 10.0, 6)) / 10.0


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)  # a TOML basic string
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, float) and not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    return repr(v)


def scenario_data(spec: CellSpec) -> dict:
    """The scenario tables of one cell: ``approach-LEVEL`` with the cell's controller, bow wave,
    pilot, closure speed (with the duration and the turbulence window of
    :func:`approach_duration_s`) and force limit, the scenario's name left as shipped.

    Parameters
    ----------
    spec : CellSpec
        The cell.

    Returns
    -------
    dict
        Table name -> {key: value}, as read from a scenario file.
    """
    from ..scenarios import load_scenario, resolve

    _, data = resolve(f"approach-{spec.level}")
    data = {k: dict(v) for k, v in data.items()}
    data["controller"] = {"type": spec.controller}
    data.setdefault("bow_wave", {})["enabled"] = bool(spec.bow_wave)
    if spec.pilot:
        data["pilot"] = {"enabled": True}  # the pilot model's defaults
    if spec.closure_speed_m_s is not None:
        duration = approach_duration_s(load_scenario(f"approach-{spec.level}").engagement.probe, spec.closure_speed_m_s)
        data.setdefault("probe", {})["closure_speed_m_s"] = float(spec.closure_speed_m_s)
        data["scenario"]["duration_s"] = duration
        data["turbulence"]["duration_s"] = duration  # gusts to the end of the run
    if spec.max_force_n is not None:
        data["actuator"] = {"max_force_n": float(spec.max_force_n)}
    return data


def scenario_toml(level: str, controller: str, bow_wave: bool, pilot: bool = False,
                  closure_speed_m_s: float | None = None, max_force_n: float | None = None) -> str:
    """The TOML text of one cell's scenario (:func:`scenario_data`, named after the cell).

    Parameters
    ----------
    level : str
        Turbulence level.
    controller : str
        Drogue controller type.
    bow_wave : bool
        Bow wave on.
    pilot : bool
        The pilot model flies the probe.
    closure_speed_m_s : float or None
        Probe closure speed [m/s]; None: the scenario's own.
    max_force_n : float or None
        The actuator's force limit per axis [N]; None: unlimited.

    Returns
    -------
    str
        A scenario file (tables of scalars and lists only, as the shipped one).
    """
    spec = CellSpec(level, controller, bow_wave, pilot, closure_speed_m_s, max_force_n)
    data = scenario_data(spec)
    data["scenario"]["name"] = f"approach-{spec.name}"
    if closure_speed_m_s is not None:
        data["scenario"]["description"] += f"; here the probe closes at {closure_speed_m_s:g} m/s"
    what = [f"controller {controller!r}", f"the bow wave {'on' if bow_wave else 'off'}"]
    if pilot:
        what.append("the pilot model flying the probe")
    if closure_speed_m_s is not None:
        what.append(f"closure speed {closure_speed_m_s:g} m/s for {data['scenario']['duration_s']:g} s")
    if max_force_n is not None:
        what.append(f"the force limited to {max_force_n:g} N per axis")
    lines = [f"# approach-{level} with {', '.join(what)} (written by hosedrogue reproduce, section Docking)"]
    for name, table in data.items():
        lines.append(f"\n[{name}]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


@dataclass(frozen=True)
class CampaignCell:
    """One campaign of the grid and what it gave."""

    level: str  #: turbulence level
    controller: str  #: controller type
    bow_wave: bool  #: bow wave on
    sigma_m_s: float  #: vertical turbulence intensity of the level at 8000 m [m/s]
    capture: dict  #: the summary's capture block: rate [-], ci95 [-], runs, by_result
    runs: object  #: pandas.DataFrame of the campaign's runs.csv
    folder: Path  #: the campaign folder
    pilot: bool = False  #: the pilot model flew the probe
    closure_speed_m_s: float = 1.0  #: the probe's closure speed [m/s]
    duration_s: float = 4.5  #: the scenario's duration [s]

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


def _same_scenario(a: dict, b: dict) -> bool:
    """Two cells' scenario tables are the same apart from the scenario's name."""
    def strip(d):
        return {k: ({kk: vv for kk, vv in v.items() if kk != "name"} if k == "scenario" else v) for k, v in d.items()}
    return strip(a) == strip(b)


def run_grid(folder: Path, runs: int, specs=None, workers: int | None = WORKERS,
             status=None) -> tuple[list[CampaignCell], float]:
    """Run the campaign of every cell afresh into ``folder/<cell>/``, on one dask cluster.

    A cell whose scenario (:func:`scenario_data`) is that of an earlier cell is not run again:
    it is that cell's campaign (e.g. the closure speed 1 m/s of approach-moderate is the main
    grid's ``moderate-none-bow-on``).

    Parameters
    ----------
    folder : Path
        Parent folder of the campaigns; removed and rewritten.
    runs : int
        Runs (turbulence seeds) per cell.
    specs : sequence of CellSpec, optional
        The cells; default :func:`grid_specs`.
    workers : int or None
        Dask worker processes shared by all cells; None: run in this process (no dask).
    status : callable, optional
        ``status(text)`` shows which cell runs.

    Returns
    -------
    (list of CampaignCell, float)
        One cell per spec, in their order (the same object for cells of the same scenario), and
        the campaigns' wall time [s].
    """
    from ..scenarios import load_scenario
    from ..studies import executor
    from ..studies.campaign import run_campaign

    specs = grid_specs() if specs is None else list(specs)
    shutil.rmtree(folder, ignore_errors=True)
    t0 = time.perf_counter()
    done: list[tuple[dict, CampaignCell]] = []
    cells = []
    with executor.dask_client(None, workers, None, workers is not None) as client:
        for spec in specs:
            data = scenario_data(spec)
            same = next((cell for d, cell in done if _same_scenario(d, data)), None)
            if same is not None:
                cells.append(same)
                continue
            if status:
                status(f"docking campaign {spec.name}")
            cell_dir = folder / spec.name
            cell_dir.mkdir(parents=True)
            (cell_dir / "scenario.toml").write_text(scenario_toml(spec.level, spec.controller, spec.bow_wave,
                                                                  spec.pilot, spec.closure_speed_m_s, spec.max_force_n))
            summary = run_campaign(str(cell_dir / "scenario.toml"), runs, cell_dir, seed=CAMPAIGN_SEED,
                                   progress=False, client=client,
                                   scheduler=None if client is not None else executor.SYNCHRONOUS)
            sc = load_scenario(str(cell_dir / "scenario.toml"))
            cell = CampaignCell(spec.level, spec.controller, spec.bow_wave,
                                float(sc.params.turbulence.sigma_m_s[2]), summary.capture, summary.runs, cell_dir,
                                spec.pilot, float(sc.engagement.probe.closure_speed_m_s), float(sc.duration_s))
            _check_counts(cell, runs)
            done.append((data, cell))
            cells.append(cell)
    return cells, time.perf_counter() - t0


@dataclass(frozen=True)
class BowWaveStudy:
    """The bow-wave field around the probe and the drogue's steady displacement."""

    x_m: np.ndarray  #: (nx,) field grid, forward of the probe tip [m]
    z_m: np.ndarray  #: (nz,) field grid, down [m]
    velocity_m_s: np.ndarray  #: (nz, nx, 3) perturbation velocity [m/s], NaN inside the forebody
    outline_m: np.ndarray  #: (k, 2) forebody outline (x, z) [m]
    stagnation_m: tuple  #: nose (x, z) [m]
    source_ahead_of_tip_m: float  #: distance from the probe tip aft to the source [m]
    distances_m: np.ndarray  #: (m,) probe tip aft of the drogue [m]
    displacement_m: np.ndarray  #: (m, 3) steady displacement (forward, right, down) [m]
    radii_m: np.ndarray  #: (k,) forebody radii [m]
    radii_displacement_m: np.ndarray  #: (k, 2) total displacement at NEAR_M and FAR_M [m]
    radius_limit_m: float  #: forebody radius whose displacement at FAR_M is LEVEL_M [m]
    radius_m: float  #: the scenario's forebody radius [m]
    near_m: float  #: total displacement at NEAR_M with the scenario's forebody [m]
    far_m: float  #: total displacement at FAR_M with it [m]


def _field(sc, bw):
    """The field in the x-z plane through the probe tip (tip at the origin), blanked inside the body."""
    from ..environment.bow_wave import BowWaveField

    field = BowWaveField.of(bw, sc.params.flight.airspeed_m_s)
    x, z = np.linspace(-7.0, 3.0, 101), np.linspace(-2.5, 2.5, 51)
    tip = np.zeros(3)
    pts = np.stack(np.meshgrid(x, [0.0], z, indexing="xy"), axis=-1)[0].transpose(1, 0, 2)
    vel = field.velocity(pts, tip)
    src = field.source_position_m(tip)
    if bw.shape == "rankine":
        rel = pts - src
        r = np.linalg.norm(rel, axis=-1)
        theta = np.arccos(np.clip(rel[..., 0] / np.maximum(r, 1e-12), -1.0, 1.0))
        inside = r < bw.forebody_radius_m / (2.0 * np.maximum(np.cos(theta / 2.0), 1e-9))
        theta_s = np.linspace(1e-3, np.pi - 0.12, 160)
        below, above = (field.rankine_surface_m(theta_s, tip, phi_rad=phi) for phi in (np.pi / 2, -np.pi / 2))
        outline = np.vstack([below[::-1][:, [0, 2]], above[:, [0, 2]]])  # the x-z plane's two halves
    else:
        inside = np.linalg.norm(vel, axis=-1) > sc.params.flight.airspeed_m_s
        outline = None
    vel[inside] = np.nan
    nose = -np.asarray(bw.probe_offset_m)
    return x, z, vel, outline, (float(nose[0]), float(nose[2])), float(-src[0])


def bow_wave_study(level: str = "moderate") -> BowWaveStudy:
    """The field and the steady displacement of the ``approach-LEVEL`` scenario's bow wave (its
    model and flight condition, wake on), and the far displacement against the forebody radius.

    Parameters
    ----------
    level : str
        Which approach scenario (they share the bow wave and the model).

    Returns
    -------
    BowWaveStudy
    """
    import scipy.optimize

    from ..engagement.bow_wave import bow_wave_displacement
    from ..scenarios import load_scenario

    sc = load_scenario(f"approach-{level}")
    bw = sc.engagement.bow_wave
    x, z, vel, outline, stagnation, source_aft = _field(sc, bw)
    d = np.asarray(DISTANCES_M)
    disp = bow_wave_displacement(sc.params, bw, d)

    def total(radius, dist):
        return np.linalg.norm(bow_wave_displacement(sc.params, dataclasses.replace(bw, forebody_radius_m=radius),
                                                    dist), axis=1)

    radii = np.asarray(RADII_M)
    table = np.array([total(R, [NEAR_M, FAR_M]) for R in radii])
    limit = scipy.optimize.brentq(lambda R: total(R, [FAR_M])[0] - LEVEL_M, radii[0], radii[-1], xtol=1e-4)
    near, far = total(bw.forebody_radius_m, [NEAR_M, FAR_M])
    return BowWaveStudy(x, z, vel, outline, stagnation, source_aft, d, disp, radii, table, float(limit),
                        float(bw.forebody_radius_m), float(near), float(far))


def approach_paths(level: str = "moderate", runs=("none", "pid"), seed: int = APPROACH_SEED) -> dict:
    """Probe-tip and drogue paths in the y-z plane of one approach, up to contact.

    Parameters
    ----------
    level : str
        Turbulence level of the ``approach-LEVEL`` scenario.
    runs : sequence of str
        Keys of :data:`APPROACH_RUNS` (a controller type, or "pilot"), one run each.
    seed : int
        Turbulence seed.

    Returns
    -------
    dict
        ``label -> {"probe_yz_m", "drogue_yz_m" (N, 2) [m], "t_s" (N,) [s], "outcome": dict,
        and with contact "contact_probe_yz_m", "contact_drogue_yz_m" (2,) [m]}``.
    """
    from ..scenarios import load_scenario
    from ..scenarios.runner import run
    from ..sections import Pilot

    base = load_scenario(f"approach-{level}").with_overrides(seed=seed)
    out = {}
    for c in runs:
        controller, piloted = APPROACH_RUNS[c]
        sc = base.with_controller(controller)
        if piloted:
            sc = dataclasses.replace(sc, engagement=dataclasses.replace(sc.engagement, pilot=Pilot(enabled=True)))
        r = run(sc)
        tc = r.outcome.get("contact_time_s")
        end = float(tc) if tc is not None else float(r.t_s[-1])
        keep = r.t_s <= end
        path = {"t_s": r.t_s[keep], "probe_yz_m": r.probe_position_m[keep][:, 1:],
                "drogue_yz_m": r.drogue_position_m[keep][:, 1:], "outcome": dict(r.outcome)}
        if tc is not None:
            path["contact_probe_yz_m"] = np.array([np.interp(end, r.t_s, r.probe_position_m[:, j]) for j in (1, 2)])
            path["contact_drogue_yz_m"] = np.array([np.interp(end, r.t_s, r.drogue_position_m[:, j]) for j in (1, 2)])
        out[c] = path
    return out
