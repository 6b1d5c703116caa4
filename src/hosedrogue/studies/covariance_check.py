"""The covariance analysis's prediction of the drogue's RMS offset in turbulence
(:mod:`hosedrogue.controllers.covariance`) against the nonlinear model's: the mean RMS of many
turbulence seeds (:func:`hosedrogue.simulation.batch.simulate_batch`), with the sampling error
of that mean computed from the predicted autocovariance (docs/loop-analysis.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..controllers.covariance import disturbance_model, predict, with_standard_turbulence
from ..controllers.design import paper_pid
from ..simulation.batch import simulate_batch
from ..spec.config import resolve_configs
from ..spec.params import Params

__all__ = ["CASES", "RmsComparison", "case_params", "compare_rms"]

#: The cases of the check: the paper's (16 m, 4.4 kg/m hose at 150 m/s and 8000 m) and a wing
#: pod's (22.9 m, 3.6 kg/m hose at 128 m/s and 6100 m), each on the converged preset.
CASES = {
    "paper": {},
    "wing-pod": {"hose": {"length_m": 22.9, "mass_per_length_kg_m": 3.6},
                 "flight": {"airspeed_m_s": 128.0, "altitude_m": 6100.0}},
}


def case_params(case: str, level: str = "moderate") -> Params:
    """The converged preset with a case's overrides (:data:`CASES`) and a standard intensity.

    Parameters
    ----------
    case : str
        A key of :data:`CASES`.
    level : {"light", "moderate", "severe"}
        Turbulence intensity.

    Returns
    -------
    Params
    """
    base = resolve_configs(["converged"])
    over = CASES[case]
    return with_standard_turbulence(base.replace(**over) if over else base, level)


@dataclass(frozen=True)
class RmsComparison:
    """Predicted and simulated RMS offsets [m] (lateral, vertical) of one case and loop."""

    predicted_m: np.ndarray  #: (2,) the covariance analysis
    simulated_m: np.ndarray  #: (2,) mean over the seeds of each run's RMS
    standard_error_m: np.ndarray  #: (2,) the predicted standard deviation of that mean
    runs: int  #: seeds that completed
    duration_s: float  #: simulated time of each run [s]

    @property
    def difference(self) -> np.ndarray:
        """(simulated - predicted) / predicted [-]."""
        return (self.simulated_m - self.predicted_m) / self.predicted_m


def compare_rms(params: Params, seeds, duration_s: float, closed: bool = False, sample_time_s: float = 0.0,
                delay_s: float = 0.0) -> RmsComparison:
    """Predict and simulate the RMS offset of ``params`` open loop or with the paper's PID.

    Parameters
    ----------
    params : Params
        Model, flight condition and turbulence (enabled).
    seeds : iterable of int
        Turbulence seeds, one run each.
    duration_s : float
        Simulated time per run [s]; every run starts at the balance position at rest, so its
        first seconds (the loop's settling) count towards its RMS.
    closed : bool
        With the paper's PID (continuous, as the scenarios run it, unless sampled) instead of open loop.
    sample_time_s : float
        The PID's sample time [s] (0: continuous): its zero-order-hold discretization, run seed
        by seed by :func:`hosedrogue.simulation.simulate.simulate` (the batch runs continuous loops).
    delay_s : float
        The sensor's delay [s] (sampled only), a whole multiple of the sample time.

    Returns
    -------
    RmsComparison
    """
    ctrl = paper_pid() if closed else None
    pred = predict(params, ctrl, sample_time_s, delay_s, dm=disturbance_model(params))
    if sample_time_s > 0.0:
        rms = _sampled_runs(params, list(seeds), duration_s, ctrl, sample_time_s, delay_s)
    else:
        df = simulate_batch(params, list(seeds), duration_s, controller=ctrl)
        rms = df.loc[df["completed"], ["rms_dy_m", "rms_dz_m"]].to_numpy()
    return RmsComparison(pred.rms_m, rms.mean(axis=0), pred.rms_standard_error(duration_s, len(rms)), len(rms),
                         duration_s)


def _sampled_runs(params, seeds, duration_s, ctrl, sample_time_s, delay_s) -> np.ndarray:
    """(runs, 2) RMS lateral, vertical offset [m] of the completed runs of a sampled loop."""
    from ..analysis.equilibrium import solve_equilibrium
    from ..model.system import HoseModel
    from ..simulation.simulate import simulate
    from ..spec.sections import Sensor

    eq = solve_equilibrium(params, model=HoseModel(params))
    out = []
    for seed in seeds:
        p = params.replace(turbulence={"seed": seed})
        r = simulate(p, duration_s, control=ctrl, equilibrium=eq, sensor=Sensor(delay_s=delay_s),
                     sample_time_s=sample_time_s)
        if r.completed:
            st = r.statistics()
            out.append((st["rms_dy_m"], st["rms_dz_m"]))
    return np.array(out).reshape(-1, 2)
