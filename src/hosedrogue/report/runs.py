"""Nonlinear runs of the report and the statistics of the drogue offset in them.

The window statistics (:func:`peak_offsets_m`, :func:`rms_offsets_m`, :func:`peak_forces_n`)
read a run's arrays into the one definition in :mod:`hosedrogue.results.statistics`.
"""

from __future__ import annotations

from ..results import statistics
from ..spec.params import Params

__all__ = ["run_named_scenario", "turbulence_window_s", "peak_offsets_m", "rms_offsets_m", "peak_forces_n"]


def run_named_scenario(name: str, duration_s: float | None = None, seed: int | None = None):
    """Load a bundled scenario and run it.

    Parameters
    ----------
    name : str
        Scenario name (e.g. ``"paper-turbulence-pid"``).
    duration_s : float, optional
        Run length [s]; None keeps the scenario's own.
    seed : int, optional
        Turbulence seed; None keeps the scenario's own.

    Returns
    -------
    tuple
        ``(scenario, result)``: the scenario as run and its ``SimulationResult``.
    """
    from ..scenarios.runner import run as run_scenario
    from ..scenarios import load_scenario

    sc = load_scenario(name)
    if duration_s is not None or seed is not None:
        sc = sc.with_overrides(duration_s=duration_s, seed=seed)
    return sc, run_scenario(sc)


def turbulence_window_s(params: Params) -> tuple[float, float]:
    """When the turbulence is on (the window rule of :mod:`hosedrogue.results.statistics`).

    Parameters
    ----------
    params : Params
        The run's parameters.

    Returns
    -------
    tuple of float
        ``(start, end)`` [s].
    """
    return statistics.turbulence_window(params.turbulence)


def peak_offsets_m(res) -> tuple[float, float]:
    """Peak |dy|, |dz| of the drogue from its balance position over the whole run.

    Parameters
    ----------
    res : SimulationResult
        The run.

    Returns
    -------
    tuple of float
        Lateral and vertical peak [m].
    """
    return statistics.peaks(res.drogue_offset_m)


def rms_offsets_m(res, window_s) -> tuple[float, float]:
    """RMS dy, dz of the drogue from its balance position in a time window.

    Parameters
    ----------
    res : SimulationResult
        The run.
    window_s : tuple of float
        ``(start, end)`` [s], end excluded.

    Returns
    -------
    tuple of float
        Lateral and vertical RMS [m].
    """
    return statistics.rms_in_window(res.t_s, res.drogue_offset_m, window_s)


def peak_forces_n(res) -> tuple[float, float]:
    """Peak |u_hor|, |u_ver| of the control force over the whole run.

    Parameters
    ----------
    res : SimulationResult
        The run.

    Returns
    -------
    tuple of float
        Lateral and vertical peak [N].
    """
    return statistics.force_peaks(res.control_force_n)
