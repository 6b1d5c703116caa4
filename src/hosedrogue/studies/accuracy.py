"""Accuracy against the number of links, for both mass lumpings (docs/convergence.md).

For a mass lumping (``aft``: the paper's, each link's mass at its aft joint; ``split``: half at
each end) and a list of link counts this measures

* the balance position of the drogue against the continuum limit
  (:func:`hosedrogue.analysis.continuum.solve_continuum`), bending off (the continuum neglects
  it), wake as configured;
* the lowest lateral and vertical mode frequencies of the linearized hose (they converge only
  when the link inertia is the link's own, ``link_inertia = "rod"``; the paper's fixed 2.816
  kg m^2 per link adds inertia with every link);
* the RMS drogue response (lateral, vertical offset from the balance position) in the paper's
  turbulence case, and the wall time of that run;

with observed orders ``log2(e(n) / e(2n))`` for errors against a known limit, and
``log2(|f(n) - f(2n)| / |f(2n) - f(4n)|)`` for quantities whose limit is unknown.

Library functions return dataclasses; :mod:`hosedrogue.studies.accuracy_figures` draws them.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..analysis.continuum import ContinuumShape, solve_continuum
from ..analysis.equilibrium import solve_equilibrium
from ..spec.paper import SEC233_TURBULENCE_WINDOW
from ..spec.params import PAPER, Params

#: Link counts of the study (each a doubling, so that observed orders are log2 of ratios).
LINKS = (5, 10, 20, 40, 80, 160)

#: The study's base case: the paper's flight condition with the wake on, bending off (the continuum
#: neglects it) and the links' own rotational inertia (m l^2 / 12), so that every measured
#: quantity has a limit as the links get shorter.
STUDY_BASE = PAPER.replace(hose={"bending": "off", "link_inertia": "rod"})

#: The paper's turbulence case (scenario ``paper-turbulence``): isotropic 1.5 m/s, 530 m, on at
#: 10 s for 20 s, seed 2018; RMS over a 60 s run.
TURBULENCE = {"enabled": True, **SEC233_TURBULENCE_WINDOW, "seed": 2018}
TURBULENCE_DURATION_S = 60.0


def observed_orders(errors) -> np.ndarray:
    """log2 of successive ratios of errors against a known limit, for link counts that double.

    Parameters
    ----------
    errors : array_like (k,)
        Errors at link counts n, 2n, 4n, ... (any unit; signs are dropped).

    Returns
    -------
    numpy.ndarray (k - 1,)
        Observed orders [-].
    """
    e = np.abs(np.asarray(errors, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.log2(e[:-1] / e[1:])


def difference_orders(values) -> np.ndarray:
    """Observed orders from three successive doublings when the limit is unknown:
    ``log2(|f(n) - f(2n)| / |f(2n) - f(4n)|)``; shape (k - 2,) for k values (rows for arrays).

    Parameters
    ----------
    values : array_like (k,) or (k, m)
        A quantity at link counts n, 2n, 4n, ... (any unit); rows are compared by their
        Euclidean distance.

    Returns
    -------
    numpy.ndarray (k - 2,)
        Observed orders [-].
    """
    v = np.asarray(values, dtype=float)
    d = np.abs(np.diff(v, axis=0))
    if d.ndim > 1:
        d = np.linalg.norm(d, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.log2(d[:-1] / d[1:])


def richardson(coarse, fine, order: float):
    """Richardson extrapolation of a quantity from links n (coarse) and 2n (fine) at the given
    order: ``fine + (fine - coarse) / (2^order - 1)``.

    Parameters
    ----------
    coarse, fine : array_like
        The quantity at n and 2n links (same shape, any unit).
    order : float
        Order of convergence in 1/n [-].

    Returns
    -------
    numpy.ndarray
        The extrapolated limit, in the unit of the inputs.
    """
    coarse = np.asarray(coarse, dtype=float)
    fine = np.asarray(fine, dtype=float)
    return fine + (fine - coarse) / (2.0**order - 1.0)


@dataclass(frozen=True)
class FrequencyStudy:
    """Lowest lateral and vertical mode frequencies [rad/s] against link count."""

    links: np.ndarray  #: (k,) link counts
    lateral_rad_s: np.ndarray  #: (k,) damped frequency of the lowest mode seen in P_ny
    vertical_rad_s: np.ndarray  #: (k,) same for P_nz

    @property
    def lateral_orders(self) -> np.ndarray:
        """Observed orders of the lateral frequency (k - 2,)."""
        return difference_orders(self.lateral_rad_s)

    @property
    def vertical_orders(self) -> np.ndarray:
        return difference_orders(self.vertical_rad_s)


def frequency_convergence(base: Params = STUDY_BASE, links=LINKS) -> FrequencyStudy:
    """Lowest lateral and vertical frequencies of ``base`` (any preset, e.g. ``converged``) at
    each link count; its orders say whether the preset converges (the brief asks >= 1.8).

    Parameters
    ----------
    base : Params
        The model; only ``hose.links`` is changed.
    links : sequence of int
        Link counts (doubling, for the orders).

    Returns
    -------
    FrequencyStudy
        Frequencies [rad/s] per link count.
    """
    from .convergence import lowest_modes
    from ..analysis.linearize import linearize

    lat, ver = [], []
    for n in links:
        lm = linearize(base.replace(hose={"links": int(n)}))
        w_lat, w_ver = lowest_modes(lm)
        lat.append(w_lat)
        ver.append(w_ver)
    return FrequencyStudy(np.asarray(links), np.array(lat), np.array(ver))


@dataclass(frozen=True)
class LumpingStudy:
    """Convergence of one mass lumping against the link count; SI units, S_p frame."""

    lumping: str  #: "aft" or "split"
    links: np.ndarray  #: (k,) link counts
    drogue_position_m: np.ndarray  #: (k, 3) balance position of the drogue [m]
    continuum_m: np.ndarray  #: (3,) the continuum limit's drogue position [m]
    frequencies: FrequencyStudy | None  #: lowest lateral / vertical modes (None if not measured)
    rms_response_m: np.ndarray | None  #: (k, 2) RMS lateral, vertical drogue offset in turbulence
    turbulence_wall_s: np.ndarray | None  #: (k,) wall time of the 60 s turbulence run [s]

    @property
    def position_error_m(self) -> np.ndarray:
        """(k,) distance of the drogue from the continuum's [m]."""
        return np.linalg.norm(self.drogue_position_m - self.continuum_m, axis=1)

    @property
    def position_orders(self) -> np.ndarray:
        """(k - 1,) observed orders of the position error against the continuum."""
        return observed_orders(self.position_error_m)

    @property
    def extrapolated_m(self) -> np.ndarray:
        """Richardson limit of the two finest link counts at the lumping's nominal order
        (1 for ``aft``, 2 for ``split``) (3,) [m]."""
        order = 1.0 if self.lumping == "aft" else 2.0
        return richardson(self.drogue_position_m[-2], self.drogue_position_m[-1], order)

    @property
    def rms_orders(self) -> np.ndarray | None:
        return None if self.rms_response_m is None else difference_orders(self.rms_response_m)

    def to_dict(self) -> dict:
        out = {
            "lumping": self.lumping,
            "links": self.links.tolist(),
            "drogue_position_m": self.drogue_position_m.tolist(),
            "continuum_m": self.continuum_m.tolist(),
            "position_error_m": self.position_error_m.tolist(),
            "position_orders": self.position_orders.tolist(),
            "extrapolated_m": self.extrapolated_m.tolist(),
        }
        if self.frequencies is not None:
            out["lateral_rad_s"] = self.frequencies.lateral_rad_s.tolist()
            out["vertical_rad_s"] = self.frequencies.vertical_rad_s.tolist()
        if self.rms_response_m is not None:
            out["rms_response_m"] = self.rms_response_m.tolist()
            out["turbulence_wall_s"] = self.turbulence_wall_s.tolist()
        return out


def turbulence_response(params: Params, duration_s: float = TURBULENCE_DURATION_S) -> tuple[np.ndarray, float]:
    """RMS lateral and vertical drogue offset [m] (2,) from the balance position over a run of
    ``params`` with the paper's turbulence, and the run's wall time [s] (equilibrium excluded).

    Parameters
    ----------
    params : Params
        The model; its turbulence is replaced by :data:`TURBULENCE`.
    duration_s : float
        Length of the run [s].

    Returns
    -------
    rms : numpy.ndarray (2,)
        RMS lateral and vertical drogue offset [m].
    wall : float
        Wall time of the run [s].

    Raises
    ------
    RuntimeError
        If the run stops early.
    """
    from ..model.system import HoseModel
    from ..simulation import simulate

    p = params.replace(turbulence=TURBULENCE)
    model = HoseModel(p)
    eq = solve_equilibrium(p, model=model)
    t0 = time.perf_counter()
    res = simulate(p, duration_s, equilibrium=eq, model=model)
    wall = time.perf_counter() - t0
    if not res.completed:
        raise RuntimeError(f"turbulence run at {p.hose.links} links: {res.message}")
    off = res.drogue_offset_m[:, 1:]
    return np.sqrt(np.mean(off**2, axis=0)), wall


def lumping_convergence(lumping: str = "split", links=LINKS, base: Params = STUDY_BASE,
                        continuum: ContinuumShape | None = None, dynamics: bool = True) -> LumpingStudy:
    """The study above for one lumping. ``dynamics=False`` skips the frequencies and the
    turbulence runs (the balance positions alone take a few seconds).

    Parameters
    ----------
    lumping : {"aft", "split"}
        Mass lumping.
    links : sequence of int
        Link counts (doubling, for the orders).
    base : Params
        The model; lumping and links are changed.
    continuum : ContinuumShape, optional
        The continuous hose's balance shape (drogue position [m]); solved if not given.
    dynamics : bool
        Also measure the lowest frequencies [rad/s] and the RMS turbulence response [m].

    Returns
    -------
    LumpingStudy
    """
    base = base.replace(hose={"mass_lumping": lumping})
    cont = continuum if continuum is not None else solve_continuum(base)
    pos, rms, wall = [], [], []
    for n in links:
        p = base.replace(hose={"links": int(n)})
        pos.append(solve_equilibrium(p).drogue_position_m)
        if dynamics:
            r, w = turbulence_response(p)
            rms.append(r)
            wall.append(w)
    freqs = frequency_convergence(base, links) if dynamics else None
    return LumpingStudy(
        lumping=lumping,
        links=np.asarray(links),
        drogue_position_m=np.array(pos),
        continuum_m=cont.drogue_position_m.copy(),
        frequencies=freqs,
        rms_response_m=np.array(rms) if dynamics else None,
        turbulence_wall_s=np.array(wall) if dynamics else None,
    )


def fewest_links(lumping: str, tolerance_m: float, base: Params = STUDY_BASE,
                 continuum: ContinuumShape | None = None, max_links: int = 1000) -> int | None:
    """Fewest links whose steady drogue is within ``tolerance_m`` of the continuum (bisection on
    a monotone error; None if even ``max_links`` is not enough).

    Parameters
    ----------
    lumping : {"aft", "split"}
        Mass lumping.
    tolerance_m : float
        Largest distance of the drogue from the continuum's [m].
    base : Params
        The model; lumping and links are changed.
    continuum : ContinuumShape, optional
        The continuous hose's balance shape; solved if not given.
    max_links : int
        Upper end of the search.

    Returns
    -------
    int or None
    """
    base = base.replace(hose={"mass_lumping": lumping})
    cont = continuum if continuum is not None else solve_continuum(base)

    def err(n):
        eq = solve_equilibrium(base.replace(hose={"links": int(n)}))
        return float(np.linalg.norm(eq.drogue_position_m - cont.drogue_position_m))

    hi = 1
    while err(hi) > tolerance_m:
        if hi >= max_links:
            return None
        hi = min(2 * hi, max_links)
    lo = hi // 2
    if lo < 1:
        return hi
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if err(mid) > tolerance_m:
            lo = mid
        else:
            hi = mid
    return hi


def links_for_tolerance(study: LumpingStudy, tolerance_m: float) -> float:
    """Link count at which the error model ``C / n^p`` fitted to the two finest link counts of
    ``study`` reaches ``tolerance_m`` (an estimate where running it is impractical).

    Parameters
    ----------
    study : LumpingStudy
        Position errors [m] against link counts.
    tolerance_m : float
        Target error [m].

    Returns
    -------
    float
        Estimated link count (not rounded).
    """
    e = study.position_error_m
    n = study.links.astype(float)
    p = math.log(e[-2] / e[-1]) / math.log(n[-1] / n[-2])
    c = e[-1] * n[-1] ** p
    return (c / tolerance_m) ** (1.0 / p)


@dataclass(frozen=True)
class ScenarioStepStudy:
    """Step error of a turbulence scenario's gust reading, and how far its converged run is from
    the paper's reading (linear, hard window) converged; SI units."""

    steps_s: np.ndarray  #: (k,) RK4 steps [s]
    max_error_m: np.ndarray  #: (k,) max over the run of |drogue - drogue at reference_step_s| [m]
    reference_step_s: float  #: RK4 step of the reference run [s]
    reading_change_m: float  #: max |drogue(scenario reading) - drogue(paper's reading)|, both at the reference step [m]
    duration_s: float  #: length of the runs [s]

    def figures(self) -> dict:
        """The study's figure (:func:`hosedrogue.studies.accuracy_figures.plot_scenario_steps`).

        Returns
        -------
        dict
            ``{"steps": matplotlib.figure.Figure}``.
        """
        from .accuracy_figures import plot_scenario_steps

        return {"steps": plot_scenario_steps(self)}


def scenario_step_study(scenario="paper-turbulence", steps_s=(0.01, 0.02, 0.025),
                        reference_step_s: float = 0.000625) -> ScenarioStepStudy:
    """The numbers behind the shipped ``paper-turbulence`` step (docs/convergence.md): RK4 at
    ``steps_s`` with the scenario's gust reading against ``reference_step_s``, and the scenario's
    reading against the paper's (``interpolation = "linear"``, ``smoothing_s = 0``). Every step
    must divide 0.1 s (the common output interval).

    Parameters
    ----------
    scenario : str, Path or hosedrogue.scenarios.Scenario
        A fixed-length scenario: a shipped name, a TOML file or a Scenario.
    steps_s : sequence of float
        RK4 steps to test [s].
    reference_step_s : float
        Step of the reference run [s].

    Returns
    -------
    ScenarioStepStudy

    Raises
    ------
    RuntimeError
        If a run stops early.
    """
    from ..scenarios import Scenario, load_scenario
    from ..simulation import simulate

    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    p = sc.params
    eq = solve_equilibrium(p)
    out_dt = 0.1

    def path(params, h):
        pp = params.replace(numerics={"step_s": h, "output_every": int(round(out_dt / h))})
        res = simulate(pp, sc.duration_s, equilibrium=eq)
        if not res.completed:
            raise RuntimeError(f"{sc.name} at step {h} s: {res.message}")
        return res.drogue_position_m

    ref = path(p, reference_step_s)
    errs = np.array([np.max(np.abs(path(p, h) - ref)) for h in steps_s])
    paper = p.replace(turbulence={"interpolation": "linear", "smoothing_s": 0.0})
    change = float(np.max(np.abs(path(paper, reference_step_s) - ref)))
    return ScenarioStepStudy(np.asarray(steps_s, float), errs, reference_step_s, change, sc.duration_s)
