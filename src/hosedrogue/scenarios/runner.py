"""Run a :class:`~hosedrogue.scenarios.Scenario`: initial state, controller, simulation, files."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ..analysis.equilibrium import Equilibrium, solve_equilibrium
from ..model.system import HoseModel
from ..params import Actuator, Sensor
from ..results import SimulationResult, run_header
from ..simulation import simulate
from . import Scenario


def initial_state(scenario: Scenario, eq: Equilibrium) -> np.ndarray:
    """The scenario's initial state [q, qd]: the balance position, optionally displaced.

    Parameters
    ----------
    scenario : Scenario
        Its ``initial`` ("equilibrium" or "displaced") and, for "displaced", the offsets
        ``initial_pitch_offset_deg`` and ``initial_yaw_offset_deg`` [deg] added to every link.
    eq : Equilibrium
        The balance position of the scenario's model.

    Returns
    -------
    numpy.ndarray
        State (4n,): link pitch and yaw angles q [rad], interleaved per link, then their rates
        qd [rad/s], all zero (released from rest).
    """
    x0 = eq.state.copy()
    if scenario.initial == "displaced":
        n = eq.q.size // 2
        x0[0 : 2 * n : 2] += math.radians(scenario.initial_pitch_offset_deg)
        x0[1 : 2 * n : 2] += math.radians(scenario.initial_yaw_offset_deg)
    return x0


def build_controller(scenario: Scenario, model: HoseModel, eq: Equilibrium):
    """The scenario's controller as a LinearController (None for "none").

    PID: the paper's gains (Eq. 33) unless ``lateral``/``vertical`` are given. LQR: the paper's
    LQR read on the balanced states of each 2nd-order channel (``design = "balanced"``, default)
    or the integral-action reading (``design = "integral"``), designed on this flight condition's
    linearization, with the paper's Q and R unless ``q_diag``/``r_diag`` are given.

    Parameters
    ----------
    scenario : Scenario
        Its ``controller`` ("none", "pid" or "lqr") and ``controller_options``: PID
        ``lateral``/``vertical`` = [K_P [N/m], K_I [N/(m s)], K_D [N s/m], N [rad/s]]; LQR
        ``design``, ``q_diag`` and ``r_diag`` [1/N^2] (see :class:`~hosedrogue.scenarios.Scenario`).
    model : HoseModel
        The scenario's model, linearized for an LQR design (unused for PID).
    eq : Equilibrium
        The balance position the LQR's linearization is taken about (unused for PID).

    Returns
    -------
    LinearController or None
        Measured drogue offset [m] -> control force [N]; None for ``controller = "none"``.
    """
    from ..controllers.design import design_controller

    return design_controller(scenario.controller, scenario.controller_options, scenario.params, model, eq)


def run_scenario(scenario: Scenario) -> SimulationResult:
    """Simulate a scenario; the result's ``meta`` records what was run.

    Solves the balance position, builds the controller (:func:`build_controller`), starts from
    :func:`initial_state` and simulates ``scenario.duration_s`` with the scenario's actuator and
    sensor.

    Parameters
    ----------
    scenario : Scenario
        The validated case: parameters, duration [s], initial state, controller, actuator and
        sensor settings.

    Returns
    -------
    SimulationResult
        The time series; ``meta`` adds ``scenario``, ``source``, ``controller``, ``duration_s``
        [s] and ``initial``.

    Raises
    ------
    EquilibriumError
        If no balance position is found.
    """
    params = scenario.params
    model = HoseModel(params)
    eq = solve_equilibrium(params, model=model)
    controller = build_controller(scenario, model, eq)
    result = simulate(
        params,
        scenario.duration_s,
        x0=initial_state(scenario, eq),
        control=controller,
        equilibrium=eq,
        actuator=Actuator(**scenario.actuator),
        sensor=Sensor(**scenario.sensor),
        model=model,
    )
    result.meta.update(
        {
            "scenario": scenario.name,
            "source": scenario.source,
            "controller": scenario.controller,
            "duration_s": scenario.duration_s,
            "initial": scenario.initial,
        }
    )
    return result


def write_run(result: SimulationResult, out_dir: Path, plot: bool = True) -> list[Path]:
    """Write ``timeseries.csv``, ``run.json`` and (optionally) ``displacement.png`` to out_dir.

    Parameters
    ----------
    result : SimulationResult
        The run to write; ``run.json`` holds its ``meta`` with the package version, whether it
        completed, its message, its end time ``t_end_s`` [s] and the balance position of the
        drogue ``equilibrium_drogue_position_m`` [m].
    out_dir : pathlib.Path
        Directory to write into; created (with parents) if missing.
    plot : bool, optional
        Also plot the drogue displacement to ``displacement.png`` (default True; skipped for a
        result with fewer than two samples).

    Returns
    -------
    list of pathlib.Path
        The files written, in the order above.
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = [result.to_csv(out_dir / "timeseries.csv")]
    meta = {**run_header(result), **result.meta}
    (out_dir / "run.json").write_text(json.dumps(meta, indent=2) + "\n")
    paths.append(out_dir / "run.json")
    if plot and result.t_s.size > 1:
        from ..plotting.figures import plot_displacement, save_figure

        paths.append(save_figure(plot_displacement(result), out_dir / "displacement.png"))
    return paths
