"""Nonlinear runs of the report and the statistics of the drogue offset in them.

The window statistics (:func:`peak_offsets_m`, :func:`rms_offsets_m`, :func:`peak_forces_n`)
are defined here only, so that a shared metrics module can replace them in one place.
"""

from __future__ import annotations

import numpy as np

from ..params import Params

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
    from ..runner import run_scenario
    from ..scenarios import load_scenario

    sc = load_scenario(name)
    if duration_s is not None or seed is not None:
        sc = sc.with_overrides(duration_s=duration_s, seed=seed)
    return sc, run_scenario(sc)


def turbulence_window_s(params: Params) -> tuple[float, float]:
    """When the turbulence is on.

    Parameters
    ----------
    params : Params
        The run's parameters.

    Returns
    -------
    tuple of float
        ``(start, end)`` [s].
    """
    tb = params.turbulence
    return (tb.start_s, tb.start_s + tb.duration_s)


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
    off = res.drogue_offset_m
    return float(np.max(np.abs(off[:, 1]))), float(np.max(np.abs(off[:, 2])))


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
    m = (res.t_s >= window_s[0]) & (res.t_s < window_s[1])
    off = res.drogue_offset_m[m]
    return float(np.sqrt(np.mean(off[:, 1] ** 2))), float(np.sqrt(np.mean(off[:, 2] ** 2)))


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
    return float(np.max(np.abs(res.control_n[:, 0]))), float(np.max(np.abs(res.control_n[:, 1])))
