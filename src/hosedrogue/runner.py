"""Run a :class:`~hosedrogue.scenarios.Scenario`: initial state, controller, simulation, files."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from . import __version__
from .analysis.equilibrium import Equilibrium, solve_equilibrium
from .model.system import HoseModel
from .results import SimulationResult
from .scenarios import Scenario
from .simulation import Actuator, Sensor, simulate


def initial_state(scenario: Scenario, eq: Equilibrium) -> np.ndarray:
    """The scenario's initial state [q, qd]: the balance position, optionally displaced."""
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
    """
    if scenario.controller == "none":
        return None
    from .analysis.linearize import linearize
    from .controllers.design import lqr_controller_for
    from .controllers.pid import PAPER_PID, PIDGains, pid_controller

    opts = scenario.controller_options
    if scenario.controller == "pid":
        gains = {ch: PIDGains(*opts[ch]) if ch in opts else PAPER_PID[ch] for ch in ("lateral", "vertical")}
        return pid_controller(gains["lateral"], gains["vertical"])
    Q = np.diag(opts["q_diag"]) if "q_diag" in opts else None
    R = np.diag(opts["r_diag"]) if "r_diag" in opts else None
    return lqr_controller_for(linearize(scenario.params, eq, model), opts.get("design", "balanced"), Q, R)


def run_scenario(scenario: Scenario) -> SimulationResult:
    """Simulate a scenario; the result's ``meta`` records what was run."""
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
    """Write ``timeseries.csv``, ``run.json`` and (optionally) ``displacement.png`` to out_dir."""
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = [result.to_csv(out_dir / "timeseries.csv")]
    meta = {
        "package": "hosedrogue",
        "version": __version__,
        "completed": result.completed,
        "message": result.message,
        "t_end_s": float(result.t_s[-1]) if result.t_s.size else 0.0,
        "equilibrium_drogue_position_m": result.equilibrium_m.tolist(),
        **result.meta,
    }
    (out_dir / "run.json").write_text(json.dumps(meta, indent=2) + "\n")
    paths.append(out_dir / "run.json")
    if plot and result.t_s.size > 1:
        from .plotting.figures import plot_displacement, save_figure

        paths.append(save_figure(plot_displacement(result), out_dir / "displacement.png"))
    return paths
