"""The engagement simulation: a reel, a hose of varying length, a prescribed probe.

:func:`simulate_engagement` integrates the compiled RK4 loop of
:mod:`hosedrogue.model.engagement` segment by segment; a segment ends at a change of the
discretization (split or merge of the exit link, see :mod:`.chain`), at the probe tip crossing
the coupler plane (the capture test: docs/engagement.md, "Capture"), at a failed state, or at
the end. The result's class and its assembly from the segments are in :mod:`.result`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Any

import numpy as np

from ..model import layout as LY
from ..model.engagement import chain as EC, outputs as EO, steps as ES
from ..model.engagement.evaluation import CONTROLLED, loop_kind
from ..spec.params import Actuator, ParameterError, Params, Sensor
from ..simulation.budget import check_duration, check_integrator, check_run
from .balance import initial_equilibrium
from .chain import MERGE_RATIO, SPLIT_RATIO, SWITCH_YAW_DEG, Chain, chain_model, initial_chain
from .events import FAILURES, failure_reason, segment_event
from ..results.run import stop_message
from .result import EngagementResult, assemble_result
from .result import segment_outputs as _outputs
from .loop import drogue_history, engagement_loop, extra_states, has_drogue_controller, no_loop, set_pilot
from .parameters import engagement_parameters
from ..spec.sections import BowWave, Engagement, Pilot, Probe, Receiver, Reel


def exit_tension_at_rest(params: Params, chain: Chain, z: np.ndarray, ep: np.ndarray, model,
                         measured: bool = False) -> float:
    """T_0 [N] of state z with the reel held (L'' = 0): the steady trail tension at a balance position.

    Parameters
    ----------
    params : Params
        The run's parameters (unused; kept for the call's symmetry with the other helpers).
    chain : Chain
        The discretization of ``z``.
    z : array (4n + Z_TAIL,)
        State: hose angles [rad] and rates [rad/s], L [m], L' [m/s], work states [J].
    ep : array (EP_SIZE,)
        Engagement parameters (:func:`engagement_parameters`); copied, the reel locked, the
        probe and the bow wave off, in steady air (the gusts at t = 0 aside, so that the set
        point does not depend on the turbulence seed).
    model : hosedrogue.model.system.HoseModel
        Parameter, environment and gust arrays.
    measured : bool
        Evaluate by the raw measurement's kernel (``model.engagement.outputs.measured_exit_tension``,
        what the sampled-data stepper compiles) instead of the output kernel: the same number.

    Returns
    -------
    float
        Exit tension T_0 [N].
    """
    e = ep.copy()
    e[LY.EP_LAW] = LY.LAW_LOCKED
    e[LY.EP_PAY_DIST] = 0.0
    e[LY.EP_PROBE] = 0.0
    e[LY.EP_BW] = LY.BW_OFF
    e[LY.EP_CTRL] = 0.0  # no control force: the drogue at its balance position needs none
    steady = SimpleNamespace(ps=model.ps, env=model.steady_env, gust_values=model.gust_values)  # no gusts
    # the variant compiled for the run's loops (model.engagement.outputs.eng_outputs): one, not two
    controlled = loop_kind(ep) == CONTROLLED
    if measured:  # the raw measurement's kernel, which a sampled-data stepper compiles anyway: the same T_0
        return EO.measured_exit_tension(z, chain.n, chain.l, chain.M, chain.J, steady.ps, steady.env,
                                        steady.gust_values, e, chain.chart, no_loop(), controlled)
    scal = _outputs(np.zeros(1), z[None, :], chain, steady, e, controlled=controlled)[2]
    return float(scal[0, LY.O_T0])


def simulate_engagement(params: Params, duration_s: float, *, reel: Reel | None = None, probe: Probe | None = None,
                        bow_wave: BowWave | None = None, pilot: Pilot | None = None, control=None,
                        actuator: Actuator = Actuator(), sensor: Sensor = Sensor(), x0: np.ndarray | None = None,
                        equilibrium=None, seed: int | None = None, length_rate_m_s: float = 0.0,
                        energy: bool = False, gravity_m_s2: float | None = None,
                        drogue_actuator=None) -> EngagementResult:
    """An engagement with every controller compiled in the loop (the built-in reel laws, the
    prescribed probe or the pilot, a continuous built-in drogue controller);
    :func:`hosedrogue.engagement.simulate_engagement` takes the same arguments and adds the
    sampled-data controllers (docs/controllers.md). The parameters are that function's.

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and numerics.
    duration_s : float
        Simulated time [s].
    reel, probe, bow_wave, pilot : sections, optional
        The drum unit, the probe, the forebody's bow wave, the pilot.
    control : LinearController, optional
        The continuous drogue controller.
    actuator : Actuator
        Force [N] and rate [N/s] limits.
    sensor : Sensor
        Noise [m] on the measured drogue offset.
    x0 : array (4n,), optional
        Initial hose state [rad, rad/s].
    equilibrium : Equilibrium, optional
        A solved balance position of the initial mesh.
    seed : int, optional
        Turbulence seed.
    length_rate_m_s : float
        Initial L' [m/s].
    energy : bool
        Also evaluate the energy terms [J].
    gravity_m_s2 : float, optional
        Overrides g [m/s^2].
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue's control surfaces.

    Returns
    -------
    EngagementResult
    """
    start = prepare(params, duration_s, reel=reel, probe=probe, bow_wave=bow_wave, pilot=pilot, control=control,
                    actuator=actuator, sensor=sensor, x0=x0, equilibrium=equilibrium, seed=seed,
                    length_rate_m_s=length_rate_m_s, gravity_m_s2=gravity_m_s2, drogue_actuator=drogue_actuator)
    run = start.new_run()
    status, message = _integrate(run, start.params, probe, start.model, duration_s)
    return assemble_result(start.params, run.segments, run.events, run.outcome, start.model, start.drogue_eq, energy,
                           status == LY.OK, message, run.delta_total, start.t_set, start.reel, probe, loop=start.loop,
                           step_loads=step_record(start.params, run),
                           drogue_actuator=start.drogue_actuator, loads_from_outputs=True)


@dataclass
class Start:
    """An engagement's initial state and arrays (:func:`prepare`): what a run starts from."""

    params: Params  #: the run's parameters (with the seed)
    chain: Chain  #: the initial discretization
    model: Any  #: :class:`~hosedrogue.model.system.HoseModel` of the initial chain (gusts of the run)
    drogue_eq: np.ndarray  #: drogue position at the start [m]
    z: np.ndarray  #: initial state
    ep: np.ndarray  #: engagement parameters
    loop: Any  #: the drogue controller's LoopArrays
    t_set: float  #: the reel's tension set point [N]
    reel: Reel  #: the drum unit
    probe: Probe | None  #: the probe
    total_steps: int  #: RK4 steps of the run
    drogue_actuator: Any = None  #: the drogue's control surfaces (None: the ideal force)

    def new_run(self) -> "_Run":
        """A :class:`_Run` at the start (copies of the state and parameters).

        Returns
        -------
        _Run
        """
        outcome: dict[str, Any] = {"result": "no contact", "miss_distance_m": None, "closure_speed_m_s": None}
        if self.probe is None or not self.probe.enabled:
            outcome["result"] = "no probe"
        ep = self.ep.copy()
        return _Run(z=self.z.copy(), chain=self.chain, ep=ep, outcome=outcome, loop=self.loop,
                    hist=drogue_history(ep, self.total_steps),
                    loads=np.full((self.total_steps + 1 if self.params.hose.elastic else 1, 4), math.nan),
                    segments=[(self.chain, ep.copy(), np.array([0.0]), self.z[None, :].copy())])


def prepare(params: Params, duration_s: float, *, reel: Reel | None = None, probe: Probe | None = None,
            bow_wave: BowWave | None = None, pilot: Pilot | None = None, receiver: Receiver | None = None,
            control=None, actuator: Actuator = Actuator(), sensor: Sensor = Sensor(),
            x0: np.ndarray | None = None, equilibrium=None, seed: int | None = None, length_rate_m_s: float = 0.0,
            gravity_m_s2: float | None = None, drogue_actuator=None, measured_rest: bool = False) -> Start:
    """An engagement's start: the balance position, the model with the run's gusts, the
    parameters and the initial state (see :func:`simulate_engagement` for the parameters).

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and numerics.
    duration_s : float
        Simulated time [s].
    reel, probe, bow_wave, pilot, receiver : sections, optional
        As for :func:`simulate_engagement` (a receiver's entry is not needed here).
    control : LinearController, optional
        The drogue controller compiled in the loop (the "hold" controller of a commanded force).
    actuator : Actuator
        Force [N] and rate [N/s] limits.
    sensor : Sensor
        The continuous controller's noise [m].
    x0 : array (4n,), optional
        Initial hose state [rad, rad/s].
    equilibrium : Equilibrium, optional
        A solved balance position of the initial mesh.
    seed : int, optional
        Turbulence seed.
    length_rate_m_s : float
        Initial L' [m/s].
    gravity_m_s2 : float, optional
        Overrides g [m/s^2].
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue steers itself with these control surfaces (the fixed-length loop's model,
        docs/model.md §10); once coupled their command is zero (they return to neutral).
        ``actuator`` must then have no limits.
    measured_rest : bool
        The reel's set point at rest (:func:`exit_tension_at_rest`) by the raw measurement's
        kernel, which a sampled-data stepper compiles anyway, instead of the output kernel (the
        same number; a process then compiles one of the two).

    Returns
    -------
    Start
    """
    check_duration(duration_s)
    params.numerics.steps(duration_s)
    check_run(params, duration_s)  # its step and output grids reach duration_s; its output fits in memory
    check_integrator(params, "engagement")
    if seed is not None:
        params = params.replace(turbulence={"seed": int(seed)})
    reel = Reel() if reel is None else reel
    # the sections' rules (a pilot or a receiver needs a probe)
    Engagement(reel=reel, probe=probe, bow_wave=bow_wave, pilot=pilot, receiver=receiver)
    chain, model, drogue_eq, z = _initial_state(params, probe, equilibrium, x0, length_rate_m_s, gravity_m_s2,
                                                duration_s, has_drogue_controller(control, drogue_actuator))
    ep = engagement_parameters(params, reel, probe, chain, drogue_eq, bow_wave)
    L0 = z[EC.tail_start(chain.n, ep) + LY.Z_L]
    if not reel.min_length_m <= L0 <= reel.max_length_m:
        raise ParameterError(f"hose.length_m = {L0!r}: the free length must lie between the reel's end stops "
                             f"reel.min_length_m = {reel.min_length_m!r} and reel.max_length_m = {reel.max_length_m!r} m")
    set_pilot(ep, pilot, params.numerics.step_s)
    if drogue_actuator is not None:
        drogue_actuator.check_hose(params.hose.axial_stiffness_n)  # the surfaces' kernels: rigid links
        drogue_actuator.check_loop(actuator == Actuator(), None)  # the surfaces make the force, its limits
        drogue_actuator.check_step(params.numerics.step_s)
    z = np.concatenate([z, extra_states(ep, control, actuator, pilot, receiver, reel, drogue_actuator)])
    loop = engagement_loop(control, drogue_eq[1:], actuator, sensor, duration_s, params.turbulence.seed,
                           drogue_actuator)
    t_set = reel.tension_set_n
    if t_set < 0:
        t_set = exit_tension_at_rest(params, chain, z, ep, model, measured_rest)
        ep[LY.EP_TSET] = t_set
    return Start(params, chain, model, drogue_eq, z, ep, loop, t_set, reel, probe,
                 int(round(duration_s / params.numerics.step_s)), drogue_actuator)


def step_record(params: Params, run) -> np.ndarray | None:
    """The elastic links' per-step loads of a run up to its last step, or None for rigid links.

    Parameters
    ----------
    params : Params
        The run's parameters (``hose.elastic``).
    run : _Run
        The run (its ``loads`` and ``step``).

    Returns
    -------
    array (steps + 1, 4) or None
    """
    return run.loads[: run.step + 1] if params.hose.elastic else None


def _initial_state(params: Params, probe, equilibrium, x0, length_rate_m_s: float, gravity_m_s2, duration_s,
                   controlled: bool):
    """The initial chain, its model (with the gust record of the run), the drogue's reference
    position [m] and the full state z (``controlled``: the run has a drogue controller, whose
    evaluation variant the balance position is then solved by)."""
    chain = initial_chain(params)
    need_eq = x0 is None or (probe is not None and probe.enabled)
    if equilibrium is None and need_eq:
        equilibrium = initial_equilibrium(params, controlled)  # solved once per model and flight condition
    model = chain_model(params, chain, duration_s)
    if gravity_m_s2 is not None:
        model.ps[LY.PS_G] = float(gravity_m_s2)
    n = chain.n
    L0 = float(np.sum(chain.l))
    hose0 = equilibrium.state if x0 is None else np.asarray(x0, dtype=np.float64)
    nh = model.state_size  # 4n, or 6n for elastic links [q, qd, lam, lamd]
    if hose0.shape != (nh,) or not np.all(np.isfinite(hose0)):
        raise ParameterError(f"x0: must be a finite array of shape ({nh},)")
    if equilibrium is None:
        drogue_eq = model.joint_positions(hose0[: 2 * n], hose0[4 * n: 5 * n] if model.elastic else None)[-1]
    else:
        drogue_eq = equilibrium.drogue_position_m.copy()
    z = np.concatenate([hose0, [L0, float(length_rate_m_s)], np.zeros(LY.Z_TAIL - 2)])
    return chain, model, drogue_eq, z


@dataclass
class _Run:
    """The state of a run between segments: current state, discretization and parameters,
    the saved segments ``(chain, ep copy, ts, zs)``, the events and the outcome so far."""

    z: np.ndarray
    chain: Chain
    ep: np.ndarray
    outcome: dict
    segments: list
    loop: Any  #: the controller's LoopArrays (empty without a controller)
    hist: np.ndarray  #: the drogue history the pilot's delay reads (loop.drogue_history)
    #: elastic links: the loads after every step (exit and drogue-end tension [N], probe load [N],
    #: slack [m]; model.engagement.outputs.state_loads), NaN until written; a (1, 4) placeholder otherwise
    loads: np.ndarray = field(default_factory=lambda: np.full((1, 4), math.nan))
    events: list = field(default_factory=list)
    step: int = 0
    t: float = 0.0
    delta_total: float = 0.0


def _integrate(run: _Run, params: Params, probe, model, duration_s: float) -> tuple[int, str]:
    """Integrate segment by segment to the end, a failed state or a failed capture; handle the
    event that ends each segment. Returns the status code and the run's message."""
    num = params.numerics
    h = num.step_s
    every = num.output_every
    total_steps = int(round(duration_s / h))
    max_yaw = math.radians(num.max_yaw_deg)
    while run.step < total_steps:
        code, zprev = _segment(run, model, h, every, total_steps - run.step, max_yaw)
        kept = float(run.segments[-1][2][-1]) if run.segments else 0.0  # the last state kept
        if code in FAILURES:
            return code, stop_message(kept, failure_reason(run, code), run.t)
        if segment_event(run, code, params, model, zprev, h, probe):
            break
    return LY.OK, "completed"


def _segment(run: _Run, model, h: float, every: int, remaining: int, max_yaw: float):
    """Run the compiled loop on the current discretization until an event or the end; save the
    outputs. Returns the kernel's code and the state one step before the last."""
    chain, z = run.chain, run.z
    nsave = remaining // every + 2
    ts = np.empty(nsave)
    zs = np.empty((nsave, z.size))
    zprev = np.empty(z.size)
    lw = chain.l.copy()
    Mw = chain.M.copy()
    Jw = chain.J.copy()
    code, done, saved = ES.eng_segment(
        z, run.t, run.step, h, remaining, every, chain.n, lw, Mw, Jw, model.ps, model.env, model.gust_values,
        run.ep, chain.chart, run.loop, run.hist, max_yaw, math.radians(SWITCH_YAW_DEG), SPLIT_RATIO * chain.l_nom,
        MERGE_RATIO * chain.l_nom, chain.n >= 2, zprev, ts, zs, run.loads)
    run.step += done
    run.t = run.step * h
    if saved:
        run.segments.append((chain, run.ep.copy(), ts[:saved].copy(), zs[:saved].copy()))
    return code, zprev
