"""The computations of the report's "Docking" section (:mod:`.docking`): the bow-wave field and
the drogue's steady displacement, the campaigns of the approach scenarios (turbulence level x
controller x bow wave) and one approach seen from behind.

The campaigns run through :func:`hosedrogue.studies.campaign.run_campaign`, which takes a
scenario by name or file: each cell's scenario (the shipped ``approach-LEVEL`` with
``[controller] type`` and ``[bow_wave] enabled`` set) is written as ``scenario.toml`` into the
cell's campaign folder and run from there. Every cell uses the same campaign seed, so run ``i``
sees the same turbulence record in every cell of a level (common random numbers).
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

__all__ = ["CONTROLLERS", "LEVELS", "CampaignCell", "BowWaveStudy", "bow_wave_study", "run_grid",
           "approach_paths", "APPROACH_RUNS", "cell_name", "scenario_toml"]

#: Controllers of the campaigns and of the approach figure, in the order of the legends (the
#: paper's gains; each acts on the drogue during the approach and is off once coupled).
CONTROLLERS = ("none", "pid", "lqr")

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


def cell_name(level: str, controller: str, bow_wave: bool) -> str:
    """Folder name of one campaign, e.g. ``moderate-pid-bow-on``.

    Parameters
    ----------
    level : str
        Turbulence level ("light", "moderate", "severe").
    controller : str
        Controller type ("none", "pid", "lqr").
    bow_wave : bool
        Bow wave on.

    Returns
    -------
    str
    """
    return f"{level}-{controller}-bow-{'on' if bow_wave else 'off'}"


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


def scenario_toml(level: str, controller: str, bow_wave: bool) -> str:
    """The TOML text of one cell's scenario: ``approach-LEVEL`` with the controller and the bow wave set.

    Parameters
    ----------
    level : str
        Turbulence level.
    controller : str
        Controller type.
    bow_wave : bool
        Bow wave on.

    Returns
    -------
    str
        A scenario file (tables of scalars and lists only, as the shipped one).
    """
    from ..scenarios import resolve

    _, data = resolve(f"approach-{level}")
    data = {k: dict(v) for k, v in data.items()}
    data["scenario"]["name"] = f"approach-{cell_name(level, controller, bow_wave)}"
    data["controller"] = {"type": controller}
    data.setdefault("bow_wave", {})["enabled"] = bool(bow_wave)
    lines = [f"# approach-{level} with controller {controller!r} and the bow wave "
             f"{'on' if bow_wave else 'off'} (written by hosedrogue reproduce, section Docking)"]
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

    @property
    def name(self) -> str:
        """The cell's folder name."""
        return cell_name(self.level, self.controller, self.bow_wave)


def _check_counts(cell: CampaignCell, runs: int) -> None:
    """Each run counted once: the results add up to the runs, and the rate lies in its interval."""
    cap = cell.capture
    if cap["runs"] != runs or sum(cap["by_result"].values()) != runs or len(cell.runs) != runs:
        raise RuntimeError(f"campaign {cell.name}: by_result {cap['by_result']} does not add up to {runs} runs")
    lo, hi = cap["ci95"]
    if not lo <= cap["rate"] <= hi:
        raise RuntimeError(f"campaign {cell.name}: rate {cap['rate']} outside its interval {cap['ci95']}")


def run_grid(folder: Path, runs: int, levels=LEVELS, controllers=CONTROLLERS, workers: int | None = WORKERS,
             status=None) -> tuple[list[CampaignCell], float]:
    """Run the campaigns of every (level, controller, bow wave) cell afresh into ``folder/<cell>/``.

    Parameters
    ----------
    folder : Path
        Parent folder of the campaigns; removed and rewritten.
    runs : int
        Runs (turbulence seeds) per cell.
    levels : sequence of str
        Turbulence levels.
    controllers : sequence of str
        Controller types.
    workers : int or None
        Dask worker processes shared by all cells; None: run in this process (no dask).
    status : callable, optional
        ``status(text)`` shows which cell runs.

    Returns
    -------
    (list of CampaignCell, float)
        The cells, and the campaigns' wall time [s].
    """
    from ..scenarios import load_scenario
    from ..studies import executor
    from ..studies.campaign import run_campaign

    shutil.rmtree(folder, ignore_errors=True)
    t0 = time.perf_counter()
    cells = []
    with executor.dask_client(None, workers, None, workers is not None) as client:
        for level in levels:
            sigma = float(load_scenario(f"approach-{level}").params.turbulence.sigma_m_s[2])
            for bow in (True, False):
                for c in controllers:
                    name = cell_name(level, c, bow)
                    if status:
                        status(f"docking campaign {name}")
                    cell_dir = folder / name
                    cell_dir.mkdir(parents=True)
                    (cell_dir / "scenario.toml").write_text(scenario_toml(level, c, bow))
                    summary = run_campaign(str(cell_dir / "scenario.toml"), runs, cell_dir, seed=CAMPAIGN_SEED,
                                           progress=False, client=client,
                                           scheduler=None if client is not None else executor.SYNCHRONOUS)
                    cell = CampaignCell(level, c, bow, sigma, summary.capture, summary.runs, cell_dir)
                    _check_counts(cell, runs)
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
    from ..environment.bow_wave import BowWave

    field = BowWave(sc.params.flight.airspeed_m_s, bw.forebody_radius_m, tuple(bw.probe_offset_m), bw.shape,
                    bw.nose_length_m)
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
    bw = sc.extra["bow_wave"]
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
    from ..engagement.run import run_engagement
    from ..engagement.spec import Pilot
    from ..scenarios import load_scenario

    base = load_scenario(f"approach-{level}").with_overrides(seed=seed)
    out = {}
    for c in runs:
        controller, piloted = APPROACH_RUNS[c]
        extra = {**base.extra, "pilot": Pilot(enabled=True)} if piloted else base.extra
        r = run_engagement(dataclasses.replace(base, controller=controller, extra=extra))
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
