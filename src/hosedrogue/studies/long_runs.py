"""The "long runs" study (docs/long-runs.md).

The paper's model (midpoint drag, no structural damping) has zigzag modes of the link chain with
damping ratios ~4e-5; turbulence feeds them until a link's yaw reaches the coordinate limit. This
module measures that and shows the remedy:

* time to blow-up of the paper's model against the standard turbulence intensities (light,
  moderate, severe at the flight altitude), a few seeds each, capped at an hour;
* the least damped mode (damping ratio, natural frequency) of the linearization for each model
  option: the paper's, + Gauss drag, + structural damping, rod inertia, the ``converged`` preset;
* an hour-long run of the ``converged`` model in severe turbulence (the shipped scenario
  ``long-turbulence-severe``).

:func:`long_runs_study` returns a :class:`LongRunStudy`; :mod:`hosedrogue.studies.long_runs_figures`
draws it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np
import pandas as pd

from ..analysis.linearize import linearize
from ..simulation import simulate_batch
from ..spec.config import load_preset, preset_data
from ..spec.params import PAPER, ParameterError, Params
from ..results.run import SimulationResult

#: Standard intensities in the order of the study.
INTENSITIES = ("light", "moderate", "severe")
#: Turbulence seeds of the blow-up study (the paper's record's seed first).
SEEDS = (2018, 2019, 2020)
#: Runs are capped at an hour [s].
CAP_S = 3600.0
#: Turbulence is switched on at this time [s] and stays on to the end (the paper's start).
TURBULENCE_START_S = 10.0
#: The hour-long run of the stable model.
HOUR_SCENARIO = "long-turbulence-severe"


def model_options(base: Params = PAPER) -> dict[str, Params]:
    """The model options compared: the paper's, each change alone, and the ``converged`` preset.

    Parameters
    ----------
    base : Params
        The paper's model (flight, hose, drogue) the options change.

    Returns
    -------
    dict of str to Params
        Option name -> parameters.
    """
    damping = preset_data("converged")["hose"]["bending_damping_n_m2_s"]
    return {
        "paper": base,
        "+gauss2 drag": base.replace(hose={"drag_quadrature": "gauss2"}),
        "+structural damping": base.replace(hose={"bending_damping_n_m2_s": damping}),
        "rod inertia": base.replace(hose={"link_inertia": "rod"}),
        "converged": load_preset("converged", base=base),
    }


def least_damped_mode(params: Params) -> tuple[float, float]:
    """(damping ratio, natural frequency [rad/s]) of the least damped oscillatory mode of the
    linearization about the balance position (steady air, wake as configured).

    Parameters
    ----------
    params : Params
        The model.

    Returns
    -------
    zeta : float
        Damping ratio [-].
    omega : float
        Natural frequency [rad/s].
    """
    poles = linearize(params).poles
    poles = poles[poles.imag > 0.0]
    zeta = -poles.real / np.abs(poles)
    i = int(np.argmin(zeta))
    return float(zeta[i]), float(np.abs(poles[i]))


def mode_table(options: Mapping[str, Params]) -> pd.DataFrame:
    """Least damped mode per model option: columns option, damping_ratio, natural_frequency_rad_s.

    Parameters
    ----------
    options : mapping of str to Params
        Option name -> model (:func:`model_options`).

    Returns
    -------
    pandas.DataFrame
        One row per option; damping ratio [-], natural frequency [rad/s].
    """
    rows = []
    for name, params in options.items():
        zeta, omega = least_damped_mode(params)
        rows.append({"option": name, "damping_ratio": zeta, "natural_frequency_rad_s": omega})
    return pd.DataFrame(rows)


def turbulence_to_the_end(params: Params, intensity: str, duration_s: float) -> Params:
    """``params`` with standard turbulence of ``intensity`` on from 10 s to the end of the run.

    Parameters
    ----------
    params : Params
        The model.
    intensity : {"light", "moderate", "severe"}
        Standard turbulence intensity at the flight altitude.
    duration_s : float
        Length of the run [s]; the turbulence lasts ``duration_s - 10`` s (at least 0).

    Returns
    -------
    Params
    """
    return params.replace(turbulence={"enabled": True, "intensity": intensity, "start_s": TURBULENCE_START_S,
                                      "duration_s": max(duration_s - TURBULENCE_START_S, 0.0)})


def blowup_table(params: Params = PAPER, intensities: Sequence[str] = INTENSITIES,
                 seeds: Sequence[int] = SEEDS, cap_s: float = CAP_S) -> pd.DataFrame:
    """Time to blow-up (yaw limit or non-finite state) of open-loop runs in turbulence.

    Columns: intensity, sigma_m_s, seed, completed, t_end_s (``cap_s`` when the run completed).
    All seeds of one intensity run in one compiled call (:func:`hosedrogue.simulation.batch.simulate_batch`).

    Parameters
    ----------
    params : Params
        The model (open loop).
    intensities : sequence of str
        Standard intensities ("light", "moderate", "severe").
    seeds : sequence of int
        Turbulence seeds, each run at every intensity.
    cap_s : float
        Length of each run [s], > 10 s (the turbulence start).

    Returns
    -------
    pandas.DataFrame
        One row per run: sigma_m_s [m/s], t_end_s [s].
    """
    if not (isinstance(cap_s, (int, float)) and np.isfinite(cap_s) and cap_s > TURBULENCE_START_S):
        raise ParameterError(f"cap_s = {cap_s!r}: must be a finite number > {TURBULENCE_START_S:g} s")
    frames = []
    for level in intensities:
        p = turbulence_to_the_end(params, level, cap_s)
        df = simulate_batch(p, seeds, cap_s)
        frames.append(pd.DataFrame({
            "intensity": level,
            "sigma_m_s": p.turbulence.sigma_m_s[0],
            "seed": df["seed"],
            "completed": df["completed"],
            "t_end_s": df["t_end_s"],
        }))
    return pd.concat(frames, ignore_index=True)


def hour_run(duration_s: float | None = None) -> SimulationResult:
    """The shipped scenario ``long-turbulence-severe`` (converged model, an hour of severe
    turbulence); ``duration_s`` shortens it (turbulence still to the end).

    Parameters
    ----------
    duration_s : float, optional
        Simulated length [s]; default the scenario's hour.

    Returns
    -------
    SimulationResult
    """
    from ..scenarios.runner import run as run_scenario
    from ..scenarios import load_scenario

    sc = load_scenario(HOUR_SCENARIO)
    if duration_s is not None:
        sc = sc.with_overrides(duration_s=duration_s)
    return run_scenario(sc)


@dataclass(frozen=True)
class LongRunStudy:
    """Data of the long-runs study (SI units)."""

    #: Paper model, open loop: intensity, sigma_m_s, seed, completed, t_end_s.
    blowup: pd.DataFrame
    #: Least damped mode per model option: option, damping_ratio, natural_frequency_rad_s.
    modes: pd.DataFrame
    #: The converged model's run in severe turbulence.
    hour: SimulationResult
    #: Cap of the blow-up runs [s].
    cap_s: float

    def figures(self) -> dict:
        """The study's figure (:func:`hosedrogue.studies.long_runs_figures.plot_long_runs`).

        Returns
        -------
        dict
            ``{"long_runs": matplotlib.figure.Figure}``.
        """
        from .long_runs_figures import plot_long_runs

        return {"long_runs": plot_long_runs(self)}

    @property
    def damping_gain(self) -> float:
        """Least damping ratio of the converged model over the paper's."""
        z = self.modes.set_index("option")["damping_ratio"]
        return float(z["converged"] / z["paper"])


def long_runs_study(intensities: Sequence[str] = INTENSITIES, seeds: Sequence[int] = SEEDS,
                    cap_s: float = CAP_S, hour_duration_s: float | None = None,
                    base: Params = PAPER) -> LongRunStudy:
    """Run the whole study (about 2-4 minutes of computing at the defaults).

    Parameters
    ----------
    intensities : sequence of str
        Standard intensities of the blow-up runs.
    seeds : sequence of int
        Turbulence seeds of the blow-up runs.
    cap_s : float
        Length of the blow-up runs [s].
    hour_duration_s : float, optional
        Length of the stable model's run [s]; default an hour.
    base : Params
        The paper's model.

    Returns
    -------
    LongRunStudy
    """
    return LongRunStudy(
        blowup=blowup_table(base, intensities, seeds, cap_s),
        modes=mode_table(model_options(base)),
        hour=hour_run(hour_duration_s),
        cap_s=float(cap_s),
    )
