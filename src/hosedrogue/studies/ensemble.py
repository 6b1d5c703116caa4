"""A chaotic response as a distribution: a scenario run N times under stated perturbations, each
headline figure reported by its median, its 5-95 % range and bootstrap intervals
(docs/engagement.md, "Chaotic peaks as distributions"; ``hosedrogue simulate --ensemble N``).

Perturbations (:data:`PERTURBATIONS`):

* ``seed``: copy ``i`` has the turbulence seed ``run_seed(scenario's seed, i)``
  (:func:`hosedrogue.studies.seeds.run_seed`, the campaigns' rule); the scenario needs turbulence;
* ``probe-offset``: copy ``i`` starts its probe displaced in the S_p y-z plane by a point drawn
  uniformly in a disc of radius ``size_m`` [m] (numpy's PCG64 seeded with ``[scenario's seed,
  i]``: the same copies in every process); the scenario needs a probe.

With ``verify`` the same copies (the same perturbations) run again on twice the links at the
refined step (:func:`hosedrogue.studies.verify.refined_scenario`) and each figure's median, 5 %
and 95 % points are compared (:func:`hosedrogue.results.convergence.compare_figures`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..results.convergence import DEFAULT_TOLERANCE, compare_figures, headline_figures

__all__ = ["PERTURBATIONS", "QUANTILES", "CONFIDENCE", "BOOTSTRAP_RESAMPLES", "parse_perturbation",
           "perturbed", "distribution", "Ensemble", "run_ensemble"]

#: The perturbations an ensemble can apply.
PERTURBATIONS = ("seed", "probe-offset")
#: The quantiles reported besides the median [-]: the 5-95 % range.
QUANTILES = (0.05, 0.95)
#: Confidence level of the bootstrap intervals [-].
CONFIDENCE = 0.95
#: Bootstrap resamples [-]: scipy's default; the interval's ends move by well under a tenth of its
#: width between independent bootstraps of 32 samples.
BOOTSTRAP_RESAMPLES = 9999
#: Seed of the bootstrap's resampling (the same intervals in every process) [-].
BOOTSTRAP_SEED = 32
#: Largest ensemble [-].
MAX_COPIES = 100_000


def parse_perturbation(text: str) -> tuple[str, float]:
    """``"seed"`` or ``"probe-offset=SIZE_M"`` as (kind, size [m]; 0 for seed).

    Parameters
    ----------
    text : str
        The perturbation.

    Returns
    -------
    tuple of (str, float)

    Raises
    ------
    ParameterError
        Not one of those, or a size that is not a number in (0, 10] m.
    """
    kind, _, size = str(text).partition("=")
    if kind == "seed" and not size:
        return "seed", 0.0
    if kind == "probe-offset":
        try:
            s = float(size)
        except ValueError:
            s = math.nan
        if 0.0 < s <= 10.0:
            return "probe-offset", s
    raise ParameterError(f"perturb = {text!r}: must be 'seed' or 'probe-offset=SIZE_M' with SIZE_M in (0, 10] m "
                         "(e.g. probe-offset=1e-6)")


def perturbed(scenario, kind: str, size_m: float, index: int):
    """Copy ``index`` of the ensemble (the module's rules).

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The scenario.
    kind : str
        One of :data:`PERTURBATIONS`.
    size_m : float
        Radius of the probe's offset disc [m] (``probe-offset``).
    index : int
        The copy, >= 0.

    Returns
    -------
    hosedrogue.scenarios.Scenario
    """
    seed = scenario.params.turbulence.seed
    if kind == "seed":
        from .seeds import run_seed

        return scenario.with_overrides(seed=run_seed(seed, index))
    rng = np.random.Generator(np.random.PCG64([seed, index]))
    r, phi = size_m * math.sqrt(rng.random()), 2.0 * math.pi * rng.random()
    probe = scenario.engagement.probe
    probe = dataclasses.replace(probe, offset_y_m=probe.offset_y_m + r * math.cos(phi),
                                offset_z_m=probe.offset_z_m + r * math.sin(phi))
    return dataclasses.replace(scenario, engagement=dataclasses.replace(scenario.engagement, probe=probe))


def _check(scenario, kind: str, copies: int) -> None:
    if isinstance(copies, bool) or not isinstance(copies, (int, np.integer)) or not 2 <= copies <= MAX_COPIES:
        raise ParameterError(f"ensemble = {copies!r}: must be a whole number of runs in [2, {MAX_COPIES}]")
    if kind == "seed" and not scenario.params.turbulence.enabled:
        raise ParameterError(f"perturb = 'seed': scenario {scenario.name!r} has no turbulence ([turbulence] "
                             "enabled = false); perturb its probe instead (probe-offset=SIZE_M)")
    if kind == "probe-offset" and (scenario.engagement is None or not scenario.engagement.probe.enabled):
        raise ParameterError(f"perturb = 'probe-offset': scenario {scenario.name!r} has no probe; "
                             "perturb its turbulence seed instead (seed)")


def distribution(values) -> dict:
    """A figure's distribution over the copies: its median, 5 % and 95 % points (numpy's linear
    quantiles), and the bootstrap intervals (:data:`CONFIDENCE`, percentile method, :data:`BOOTSTRAP_RESAMPLES`
    resamples, scipy.stats.bootstrap; BCa's jackknife is degenerate for the median of a few samples) of the median and of the 95 % point.

    Parameters
    ----------
    values : sequence of float or None
        The figure of every copy (None: the copy has no such figure; left out and counted).

    Returns
    -------
    dict
        ``copies``, ``missing``, ``median``, ``p05``, ``p95``, ``min``, ``max``,
        ``median_interval`` and ``p95_interval`` ([low, high]; None with fewer than 3 values or
        none spread).
    """
    import scipy.stats

    v = np.array([x for x in values if x is not None], dtype=float)
    out = {"copies": int(v.size), "missing": len(values) - int(v.size)}
    if v.size == 0:
        return {**out, **dict.fromkeys(("median", "p05", "p95", "min", "max", "median_interval", "p95_interval"))}
    out.update(median=float(np.median(v)), p05=float(np.quantile(v, QUANTILES[0])),
               p95=float(np.quantile(v, QUANTILES[1])), min=float(v.min()), max=float(v.max()))
    for key, stat in (("median_interval", np.median), ("p95_interval", lambda x, axis: np.quantile(x, 0.95, axis=axis))):
        out[key] = None
        if v.size >= 3 and np.ptp(v) > 0.0:
            res = scipy.stats.bootstrap((v,), stat, confidence_level=CONFIDENCE, n_resamples=BOOTSTRAP_RESAMPLES,
                                        method="percentile", random_state=np.random.default_rng(BOOTSTRAP_SEED))
            out[key] = [float(res.confidence_interval.low), float(res.confidence_interval.high)]
    return out


@dataclass(frozen=True)
class Ensemble:
    """An ensemble's result: the figures of every copy and their distributions."""

    scenario: str  #: the scenario's name
    perturbation: str  #: "seed" or "probe-offset"
    size_m: float  #: the probe offset disc's radius [m] (0 for seed)
    links: int  #: links of the copies [-]
    step_s: float  #: their integration step [s]
    figures: list  #: per copy, :func:`~hosedrogue.results.convergence.headline_figures`
    completed: list  #: per copy, whether it reached its end
    distributions: dict  #: figure -> :func:`distribution`
    verification: dict | None = None  #: the quantiles against the refined ensemble's (None: not verified)

    def to_dict(self) -> dict:
        """The ensemble as a JSON-ready dict (strict JSON through :func:`hosedrogue.jsonio.dumps`)."""
        return dataclasses.asdict(self)


def _figures(scenario):
    """One copy's headline figures and whether it completed (a process of its own may run it)."""
    from ..scenarios.runner import run

    r = run(scenario)
    return headline_figures(r), r.completed


def _run_copies(scenarios: list, workers: int) -> list:
    if workers <= 1:
        return [_figures(sc) for sc in scenarios]
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    # spawn: a fresh interpreter per worker (no fork of numba's threads); map keeps the copies' order
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        return list(pool.map(_figures, scenarios))


def _ensemble(scenario, copies: int, kind: str, size_m: float, workers: int) -> Ensemble:
    done = _run_copies([perturbed(scenario, kind, size_m, i) for i in range(copies)], workers)
    figures = [f for f, _ in done]
    dist = {k: distribution([f[k] for f in figures]) for k in figures[0]}
    p = scenario.params
    return Ensemble(scenario=scenario.name, perturbation=kind, size_m=size_m, links=p.hose.links,
                    step_s=p.numerics.step_s, figures=figures, completed=[c for _, c in done], distributions=dist)


def _quantiles(ens: Ensemble, name: str) -> dict:
    return {f"{name}.{k}": ens.distributions[k][name] for k in ens.distributions}


def run_ensemble(scenario, copies: int, perturb: str = "probe-offset=1e-6", verify: bool = False,
                 tolerance: float = DEFAULT_TOLERANCE, workers: int = 1) -> Ensemble:
    """Run ``copies`` perturbed copies of ``scenario`` (the module's rules) and report each
    headline figure's distribution; with ``verify`` the same on the refined mesh, and each
    figure's median, 5 % and 95 % points compared with the tolerance.

    Parameters
    ----------
    scenario : hosedrogue.scenarios.Scenario
        The scenario.
    copies : int
        Runs [-], >= 2.
    perturb : str
        ``"seed"`` or ``"probe-offset=SIZE_M"`` (:func:`parse_perturbation`).
    verify : bool
        Also run the ensemble on twice the links at the refined step and compare the quantiles.
    tolerance : float
        Relative tolerance of the verification [-].
    workers : int
        Processes [-] (1: this one). The copies' figures do not depend on it.

    Returns
    -------
    Ensemble
    """
    from .verify import check_tolerance, refined_scenario

    kind, size = parse_perturbation(perturb)
    _check(scenario, kind, copies)
    tolerance = check_tolerance(tolerance)
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ParameterError(f"workers = {workers!r}: must be a whole number of processes >= 1")
    ens = _ensemble(scenario, copies, kind, size, workers)
    if not verify:
        return ens
    fine = _ensemble(refined_scenario(scenario), copies, kind, size, workers)
    figures = {}
    for q in ("median", "p05", "p95"):
        figures.update(compare_figures(_quantiles(ens, q), _quantiles(fine, q), tolerance))
    doc = {"status": "verified", "tolerance": tolerance, "refined": {"links": fine.links, "step_s": fine.step_s},
           "refined_distributions": fine.distributions, "converged": all(f["converged"] for f in figures.values()),
           "not_converged": [k for k, f in figures.items() if not f["converged"]], "figures": figures}
    return dataclasses.replace(ens, verification=doc)
