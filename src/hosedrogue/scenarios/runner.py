"""Run a :class:`~hosedrogue.scenarios.Scenario` and write its files: the one place that chooses
the fixed-length or the varying-length (engagement) driver.

* :func:`run` - balance position, controller (designed once per process and design), initial
  state, simulation; returns a :class:`~hosedrogue.results.run.RunResult`;
* :func:`write` - ``timeseries.csv``, ``run.json``, ``hose.npz`` (the hose's shape over time),
  the figure and, with ``formats=("csv", "mat")``, ``timeseries.mat``, for either kind of result.
"""

from __future__ import annotations

import dataclasses
import json
import math
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Sequence

import numpy as np

from ..results import hose_file
from ..analysis.equilibrium import Equilibrium, solve_equilibrium
from ..errors import ParameterError
from ..jsonio import dumps, fallback
from ..model.system import HoseModel
from ..results.run import RunResult
from ..results.spectra import PREDICTION_KEY
from ..simulation import simulate
from ..simulation.budget import check_run
from . import Scenario
from .spectrum import spectrum_prediction

#: Output formats of :func:`write`: the CSV time series (always), and a MATLAB file.
FORMATS = ("csv", "mat")

#: Designed drogue controllers of this process, by design key (:func:`drogue_controller`).
_DESIGNS: dict = {}


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


def drogue_controller(scenario: Scenario, model: HoseModel | None = None, eq: Equilibrium | None = None):
    """The scenario's drogue controller (None for "none"), designed once per process.

    PID: the paper's gains (Eq. 33) unless ``lateral``/``vertical`` are given. LQR: the paper's
    LQR read on the balanced states of each 2nd-order channel (``design = "balanced"``, default)
    or the integral-action reading (``design = "integral"``), designed on the linearization of
    the fixed-length model of the scenario's parameters (the engagement's initial chain) about
    its balance position, with the paper's Q and R unless ``q_diag``/``r_diag`` are given
    (:func:`hosedrogue.controllers.design.design_controller`). The design is kept by its key
    (the parameters without the turbulence, which the design does not use; the controller's
    type and options), so a campaign designs it once per worker.

    Parameters
    ----------
    scenario : Scenario
        Its ``loop.controller`` and ``params``.
    model : HoseModel, optional
        The scenario's fixed-length model (built if missing; LQR only).
    eq : Equilibrium, optional
        Its balance position (solved if missing; LQR only).

    Returns
    -------
    LinearController or None
        Measured drogue offset [m] -> control force [N]; None for "none" and for the user's
        controller ("python": :func:`sampled_controllers`).
    """
    ctrl = scenario.loop.controller
    if ctrl.type in ("none", "python"):
        return None
    steady = {k: v for k, v in scenario.params.to_dict().items() if k != "turbulence"}
    key = json.dumps([steady, ctrl.to_dict()], sort_keys=True, default=repr)
    if key not in _DESIGNS:
        from ..controllers.design import design_controller

        _DESIGNS[key] = design_controller(ctrl.type, dict(ctrl.options), scenario.params, model, eq)
    return _DESIGNS[key]


def controller_record(scenario: Scenario) -> dict:
    """What ``run.json`` records of the scenario's drogue controller (``controller_design``): its
    type, where its numbers come from, and the gains (PID) or the regulator and observer gains
    (LQR) with the realization that ran (:func:`hosedrogue.controllers.design.controller_record`).

    Parameters
    ----------
    scenario : Scenario
        Its ``loop.controller``; the design is :func:`drogue_controller`'s (cached).

    Returns
    -------
    dict
        JSON-ready.
    """
    ctrl = scenario.loop.controller
    if ctrl.type not in ("pid", "lqr"):
        return {"type": ctrl.type}
    from ..controllers.design import controller_record as record  # python-control: only for a design

    return record(ctrl.type, dict(ctrl.options), drogue_controller(scenario))


def sampled_controllers(scenario: Scenario) -> dict:
    """The scenario's sampled-data controllers of the user (``[controller] type = "python"``,
    ``[reel] law = "python"``, ``[receiver]``), each's entry imported by its name (a one-line
    error before any run starts if one cannot be).

    Parameters
    ----------
    scenario : Scenario
        The case.

    Returns
    -------
    dict
        Role -> :class:`~hosedrogue.controllers.sampled.SampledController` (empty without).

    Raises
    ------
    ParameterError
        An entry missing, or that cannot be imported.
    """
    from ..controllers.sampled import SampledController

    out = {}
    ctrl = scenario.loop.controller
    if ctrl.type == "python":
        out["drogue"] = SampledController("drogue", ctrl.entry, ctrl.sample_time_s, dict(ctrl.options))
    e = scenario.engagement
    if e is not None:
        from ..engagement.simulate import sampled_controllers as engagement_controllers

        out.update(engagement_controllers(e.reel, e.receiver, None))
    for c in out.values():
        c.factory()
    return out


def run(scenario: Scenario) -> RunResult:
    """Run a scenario: the fixed-length hose, or the engagement if it has one.

    Solves the balance position, designs the controller (:func:`drogue_controller`), starts
    from :func:`initial_state` and simulates ``scenario.duration_s`` with the scenario's
    actuator and sensor (and the drogue's control surfaces, if any); the engagement adds the reel,
    probe, bow wave and pilot or receiver. The user's sampled-data controllers
    (:func:`sampled_controllers`) are imported and built before the run starts; a built-in
    controller with ``sample_time_s`` > 0 runs sampled.

    Parameters
    ----------
    scenario : Scenario
        The validated case.

    Returns
    -------
    RunResult
        :class:`~hosedrogue.results.run.SimulationResult` or
        :class:`~hosedrogue.results.run.EngagementResult`; ``meta`` records what was run (scenario,
        source, model, duration [s], initial state, controller, actuator, sensor, parameters).

    Raises
    ------
    EquilibriumError
        If no balance position is found.
    """
    if not isinstance(scenario, Scenario):
        raise ParameterError(f"scenario = {scenario!r}: must be a hosedrogue.scenarios.Scenario "
                             "(load_scenario(name) or Scenario(...))")
    # the commands' check: the step grid reaches the duration, the output fits in memory (before the work)
    check_run(scenario.params, scenario.duration_s, "scenario.duration_s")
    extra = {}
    if scenario.engagement is None:
        result = _run_fixed_length(scenario)
        extra[PREDICTION_KEY] = spectrum_prediction(scenario, drogue_controller(scenario))
    else:
        result = _run_engagement(scenario)
    return dataclasses.replace(result, meta={**result.meta, **_meta(scenario), **extra})


def _drogue(scenario: Scenario, controllers: dict, model=None, eq=None):
    """The drogue controller argument of the drivers: the user's, or the designed one."""
    return controllers.get("drogue") or drogue_controller(scenario, model, eq)


def _run_fixed_length(scenario: Scenario) -> RunResult:
    params = scenario.params
    controllers = sampled_controllers(scenario)
    model = HoseModel(params, duration_s=scenario.duration_s)
    eq = solve_equilibrium(params, model=model)
    ctrl = scenario.loop.controller
    return simulate(params, scenario.duration_s, x0=initial_state(scenario, eq),
                    control=_drogue(scenario, controllers, model, eq), equilibrium=eq,
                    actuator=scenario.loop.actuator, sensor=scenario.loop.sensor, model=model,
                    sample_time_s=ctrl.sample_time_s if ctrl.type in ("pid", "lqr") else 0.0,
                    drogue_actuator=scenario.loop.drogue_actuator)


def _run_engagement(scenario: Scenario) -> RunResult:
    from ..engagement import simulate_engagement

    return simulate_engagement(scenario.params, scenario.duration_s, **engagement_arguments(scenario))


def engagement_arguments(scenario: Scenario) -> dict:
    """The keyword arguments of :func:`~hosedrogue.engagement.simulate_engagement` that run the
    scenario's engagement: its sections, the drogue controller (designed, or the user's), the
    actuator and sensor, the displaced initial state, the built-in controller's sample time.

    Parameters
    ----------
    scenario : Scenario
        A scenario with an engagement.

    Returns
    -------
    dict
        ``reel``, ``probe``, ``bow_wave``, ``pilot``, ``receiver``, ``control``, ``actuator``,
        ``sensor``, ``x0``, ``sample_time_s``, ``drogue_actuator``.

    Raises
    ------
    ParameterError
        A user's controller that cannot be imported or built.
    """
    e = scenario.engagement
    controllers = sampled_controllers(scenario)
    x0 = None
    if scenario.initial == "displaced":
        x0 = initial_state(scenario, solve_equilibrium(scenario.params))
    ctrl = scenario.loop.controller
    return {"reel": e.reel, "probe": e.probe, "bow_wave": e.bow_wave, "pilot": e.pilot, "receiver": e.receiver,
            "control": _drogue(scenario, controllers), "actuator": scenario.loop.actuator,
            "sensor": scenario.loop.sensor, "x0": x0,
            "sample_time_s": ctrl.sample_time_s if ctrl.type in ("pid", "lqr") else 0.0,
            "drogue_actuator": scenario.loop.drogue_actuator}


def run_meta(scenario: Scenario) -> dict:
    """What a run records of its scenario in ``run.json`` (what :func:`run` puts in ``meta``).

    Parameters
    ----------
    scenario : Scenario
        The case run.

    Returns
    -------
    dict
        Scenario name, source, model, duration [s], initial state, controller and its options,
        actuator, sensor, the engagement's pilot, bow wave and receiver, the sampled-data
        controllers, the parameters.
    """
    return _meta(scenario)


def _meta(scenario: Scenario) -> dict:
    """What a run records of its scenario (run.json)."""
    meta = {"scenario": scenario.name, "source": scenario.source, "model": scenario.model,
            "duration_s": scenario.duration_s, "initial": scenario.initial,
            "controller": scenario.loop.controller.type, "controller_options": dict(scenario.loop.controller.options),
            "controller_design": controller_record(scenario),
            "actuator": scenario.loop.actuator.to_dict(), "sensor": scenario.loop.sensor.to_dict()}
    if scenario.loop.drogue_actuator is not None:
        meta["drogue_actuator"] = scenario.loop.drogue_actuator.to_dict()
    if scenario.engagement is not None:
        e = scenario.engagement
        meta["pilot"] = None if e.pilot is None else e.pilot.to_dict()
        meta["bow_wave"] = None if e.bow_wave is None else e.bow_wave.to_dict()
        if e.receiver is not None:
            meta["receiver"] = e.receiver.to_dict()
    sampled = _sampled_meta(scenario)
    if sampled:
        meta["sampled_controllers"] = sampled
    meta["params"] = scenario.params.to_dict()
    return meta


def _sampled_meta(scenario: Scenario) -> dict:
    """The sampled-data controllers a run had (run.json ``sampled_controllers``): role -> entry,
    sample time [s], options; the built-in drogue controller's sample time if it had one."""
    ctrl, out = scenario.loop.controller, {}
    if ctrl.type == "python":
        out["drogue"] = {k: v for k, v in ctrl.to_dict().items() if k != "type"}
    elif ctrl.sampled:
        out["drogue"] = {"entry": f"built-in {ctrl.type}", "sample_time_s": ctrl.sample_time_s}
    e = scenario.engagement
    if e is not None and e.reel.law == "python":
        out["reel"] = {k: e.reel.to_dict()[k] for k in ("entry", "sample_time_s", "options")}
    if e is not None and e.receiver is not None:
        out["receiver"] = {k: e.receiver.to_dict()[k] for k in ("entry", "sample_time_s", "options")}
    return out


def _write_hose(path: Path, t_s: np.ndarray, shapes: tuple) -> tuple[Path, str]:
    """Write a run's ``hose.npz`` and return it with its arrays' digest (:func:`write`'s thread)."""
    return hose_file.write_hose_npz(path, t_s, *shapes), hose_file.hose_digest(t_s, *shapes)


def write(result: RunResult, out_dir: str | Path, formats: Sequence[str] = ("csv",), plot: bool = True) -> list[Path]:
    """Write a run's files to ``out_dir``: ``timeseries.csv``, ``run.json``, ``hose.npz`` (the
    joint positions at every output time, :mod:`hosedrogue.results.hose_file`; what ``hosedrogue view``
    draws), its figure (``displacement.png`` or ``engagement.png``) and, with
    ``"mat"``, ``timeseries.mat``. ``run.json`` holds the SHA-256 of the time series and of the hose's
    arrays (``data_sha256``, :func:`hosedrogue.results.hose_file.run_digests`), by which ``view``
    knows the files belong together.

    Parameters
    ----------
    result : RunResult
        The run (either hose model).
    out_dir : str or pathlib.Path
        Directory to write into; created (with parents) if missing.
    formats : sequence of {"csv", "mat"}
        Time-series formats; the CSV is always written.
    plot : bool, optional
        Also write the figure (skipped for a result with fewer than two samples).

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    bad = [f for f in formats if f not in FORMATS]
    if bad:
        raise ParameterError(f"formats = {list(formats)!r}: each must be one of {', '.join(map(repr, FORMATS))}")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    shapes = result.hose_shapes()
    # hose.npz and the digests of the run's data (by which the viewer knows run.json belongs to
    # these files) on a thread beside the CSV: writing a file and hashing release Python's lock,
    # formatting the CSV holds it, so on two cores they take no time of their own (0.2 of the 3 s
    # that 5000 s of the paper's case add, docs/benchmarks.md)
    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="hosedrogue-write") as pool:
        hose = pool.submit(_write_hose, out_dir / hose_file.FILE, result.t_s, shapes)
        csv = result.to_csv(out_dir / "timeseries.csv")
        csv_sha = pool.submit(hose_file.file_digest, csv)
        doc = result.run_document()
        npz, hose_sha = hose.result()
        doc[hose_file.DIGEST_KEY] = hose_file.digest_record(csv_sha.result(), hose_sha)
    (out_dir / "run.json").write_text(dumps(doc, indent=2, default=fallback) + "\n")
    paths = [csv, out_dir / "run.json", npz]
    if plot and result.t_s.size > 1:
        from ..plotting.figures import save_figure

        paths.append(save_figure(result.plot(), out_dir / result.FIGURE))
    if "mat" in formats:
        paths.append(result.to_mat(out_dir / "timeseries.mat"))
    return paths

