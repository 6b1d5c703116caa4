"""The engagement simulation: a reel, a hose of varying length, a prescribed probe.

:func:`simulate_engagement` integrates the compiled RK4 loop of
:mod:`hosedrogue.model.engagement_kernels` segment by segment; a segment ends at a change of the
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

from ..environment.bow_wave import BowWaveField
from ..model import engagement_kernels as EK
from ..model import kernels as K
from ..params import Actuator, ParameterError, Params, Sensor
from .chain import (MERGE_RATIO, SPLIT_RATIO, SWITCH_YAW_DEG, Chain, chain_equilibrium, chain_model, initial_chain,
                    merge, split, switch_charts)
from .result import EngagementResult, assemble_result
from .result import segment_energies as _energies
from .result import segment_outputs as _outputs
from .loop import drogue_history, engagement_loop, extra_states, set_pilot
from ..sections import BowWave, Engagement, Loop, Pilot, Probe, Reel

LAW_CODES = {"locked": EK.LAW_LOCKED, "constant-tension": EK.LAW_CONSTANT_TENSION, "response": EK.LAW_RESPONSE}
_STATUS = {K.NONFINITE: "the state became non-finite (numerical divergence)",
           K.YAW_LIMIT: "a link's yaw passed the limit where the angle coordinates become singular",
           EK.REEL_END: "the free hose length left the reel's range between its end stops (fully reeled in or "
                        "fully paid out)"}


def engagement_parameters(params: Params, reel: Reel, probe: Probe | None, chain: Chain,
                          drogue_eq: np.ndarray, bow_wave: BowWave | None = None) -> np.ndarray:
    """The engagement parameter array of the compiled kernels (``engagement_kernels.EP_*``).

    Parameters
    ----------
    params : Params
        Hose mass per length [kg/m], lumping and link inertia [kg m^2], drogue mass [kg] and
        inertia [kg m^2].
    reel : Reel
        The drum unit (law, radius [m], inertia [kg m^2], friction [N m s], tension set point [N],
        torque [N m] and speed [m/s] limits, gains, payout schedule [s, m, m/s, m/s^2]).
    probe : Probe or None
        The receiver's probe (standoff and offsets [m], closure speed [m/s], push [m], stop
        time [s], contact stiffness [N/m] and damping [N s/m]); None or disabled: parked far aft.
    chain : Chain
        The initial discretization (its nominal link length [m]).
    drogue_eq : array (3,)
        Drogue position at the start [m] in S_p, from which the probe starts.
    bow_wave : BowWave, optional
        The receiver's forebody (radius [m], probe offset from the nose [m], shape, nose
        length [m]); None or disabled: no bow wave.

    Returns
    -------
    array (EP_SIZE,)
        Not coupled yet (``EP_COUPLED`` 0, capture time ``EP_T_CAP`` infinite).
    """
    ep = np.zeros(EK.EP_SIZE)
    hose = params.hose
    ep[EK.EP_MU] = hose.mass_per_length_kg_m
    ep[EK.EP_MD] = params.drogue.mass_kg
    ep[EK.EP_SPLIT] = 1.0 if hose.mass_lumping == "split" else 0.0
    ep[EK.EP_JLINK] = -1.0 if hose.link_inertia == "rod" else hose.link_inertia_kg_m2
    ep[EK.EP_JD] = params.drogue.inertia_kg_m2
    ep[EK.EP_L0] = chain.l_nom
    ep[EK.EP_LAW] = LAW_CODES[reel.law]
    ep[EK.EP_RD] = reel.drum_radius_m
    ep[EK.EP_JR] = reel.inertia_kg_m2
    ep[EK.EP_CR] = reel.friction_n_m_s
    ep[EK.EP_TSET] = reel.tension_set_n
    ep[EK.EP_TAU_MAX] = reel.max_torque_n_m
    ep[EK.EP_V_IN_MAX] = reel.max_takeup_speed_m_s
    ep[EK.EP_V_OUT_MAX] = reel.max_payout_speed_m_s
    ep[EK.EP_K_GOV] = reel.governor_gain_n_s_m
    ep[EK.EP_KS] = reel.takeup_gain_1_s
    ep[EK.EP_DB] = reel.slack_dead_band_m
    ep[EK.EP_KV] = reel.speed_gain_n_s_m
    ep[EK.EP_PAY_T0] = reel.payout_start_s
    ep[EK.EP_PAY_DIST] = reel.payout_m
    ep[EK.EP_PAY_V] = reel.payout_speed_m_s
    ep[EK.EP_PAY_A] = reel.payout_acceleration_m_s2
    ep[EK.EP_L_MIN] = reel.min_length_m
    ep[EK.EP_L_MAX] = reel.max_length_m
    if probe is not None and probe.enabled:
        ep[EK.EP_PROBE] = 1.0
        ep[EK.EP_P0X] = drogue_eq[0] - probe.standoff_m
        ep[EK.EP_P0Y] = drogue_eq[1] + probe.offset_y_m
        ep[EK.EP_P0Z] = drogue_eq[2] + probe.offset_z_m
        ep[EK.EP_VC] = probe.closure_speed_m_s
        ep[EK.EP_PUSH] = probe.push_m
        ep[EK.EP_T_STOP] = probe.stop_time_s
        ep[EK.EP_KP] = probe.stiffness_n_m
        ep[EK.EP_CP] = probe.damping_n_s_m
    else:
        ep[EK.EP_VC] = 0.0
        ep[EK.EP_P0X] = drogue_eq[0] - 1e3  # parked far aft, never used
    ep[EK.EP_T_CAP] = math.inf
    set_bow_wave(ep, params, bow_wave)
    return ep


def set_bow_wave(ep: np.ndarray, params: Params, bow_wave: BowWave | None) -> None:
    """Write the bow-wave entries of ``ep`` (``EP_BW*``): shape code, source minus probe tip [m],
    flux [m^3/s], line length [m]. The source sits still relative to the probe tip; its flux is
    that of the forebody in the tanker's airspeed (the closure speed, ~1 m/s of 150 m/s, aside).

    Parameters
    ----------
    ep : array (EP_SIZE,)
        Engagement parameters, changed in place.
    params : Params
        Its ``flight.airspeed_m_s`` [m/s] is the free stream of the forebody.
    bow_wave : BowWave or None
        None or disabled: ``EP_BW`` = off.
    """
    if bow_wave is None or not bow_wave.enabled:
        ep[EK.EP_BW] = EK.BW_OFF
        return
    bw = BowWaveField.of(bow_wave, params.flight.airspeed_m_s)
    ep[EK.EP_BW] = EK.BW_RANKINE if bow_wave.shape == "rankine" else EK.BW_LINE
    ep[[EK.EP_BW_DX, EK.EP_BW_DY, EK.EP_BW_DZ]] = bw.source_position_m(np.zeros(3))
    ep[EK.EP_BW_Q] = bw.flux_m3_s
    ep[EK.EP_BW_LEN] = bow_wave.nose_length_m


def exit_tension_at_rest(params: Params, chain: Chain, z: np.ndarray, ep: np.ndarray, model) -> float:
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

    Returns
    -------
    float
        Exit tension T_0 [N].
    """
    e = ep.copy()
    e[EK.EP_LAW] = EK.LAW_LOCKED
    e[EK.EP_PAY_DIST] = 0.0
    e[EK.EP_PROBE] = 0.0
    e[EK.EP_BW] = EK.BW_OFF
    e[EK.EP_CTRL] = 0.0  # no control force: the drogue at its balance position needs none
    steady = SimpleNamespace(ps=model.ps, env=model.steady_env, gust_values=model.gust_values)  # no gusts
    scal = _outputs(np.zeros(1), z[None, :], chain, steady, e)[2]
    return float(scal[0, EK.O_T0])


def simulate_engagement(params: Params, duration_s: float, *, reel: Reel | None = None, probe: Probe | None = None,
                        bow_wave: BowWave | None = None, pilot: Pilot | None = None, control=None,
                        actuator: Actuator = Actuator(), sensor: Sensor = Sensor(), x0: np.ndarray | None = None,
                        equilibrium=None, seed: int | None = None, length_rate_m_s: float = 0.0,
                        energy: bool = False, gravity_m_s2: float | None = None,
                        drogue_actuator=None) -> EngagementResult:
    """Simulate an engagement from the balance position at rest (steady air plus the
    ``params.turbulence`` gusts if enabled).

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and numerics (RK4, ``numerics.step_s``, ``output_every``). The link
        masses are lumped as ``hose.mass_lumping`` says (docs/model.md §2; ``split`` converges at
        second order, the engagement scenarios set it).
    duration_s : float
        Simulated time [s]; a miss ends the run earlier with the reason in ``outcome``.
    reel : Reel, optional
        The drum unit (default ``Reel()``: constant tension at the steady trail tension).
    probe : Probe, optional
        The receiver's probe (None: no probe).
    bow_wave : BowWave, optional
        The receiver's forebody moving with the probe tip (radius [m], probe offset [m], shape);
        its perturbation velocity is added to the air at every hose drag point and at the drogue.
    pilot : Pilot, optional
        Flies the probe's lateral and vertical position toward the delayed drogue
        (docs/engagement.md, "Pilot model"); needs a probe.
    control : LinearController, optional
        Drogue controller: measured drogue offset [m] from its balance position at the start ->
        force [N] at the drogue, until capture (docs/engagement.md, "Drogue controller during
        the approach").
    actuator : Actuator
        Force [N] and rate [N/s] limits of the control force (the fixed-length loop's semantics).
    sensor : Sensor
        Noise [m] on the measured drogue offset, sample time [s].
    x0 : array (4n,), optional
        Initial hose state [q, qd] instead of the balance position at rest (then, without a
        probe, no balance position is solved: the probe starts from it).
    equilibrium : Equilibrium, optional
        Reuse a solved balance position of the initial mesh.
    seed : int, optional
        Overrides ``params.turbulence.seed`` (and seeds the sensor noise).
    length_rate_m_s : float
        Initial L' [m/s] (positive paying out).
    energy : bool
        Also evaluate the energy terms at every output time (for the energy balance).
    gravity_m_s2 : float, optional
        Overrides g [m/s^2] (0 for the energy balance without gravity).
    drogue_actuator : hosedrogue.sections.DrogueActuator, optional
        The drogue steers itself with these control surfaces (the fixed-length loop's model,
        docs/model.md, "Actuated drogue"); once coupled their command is zero (they return to
        neutral). ``actuator`` must then have no limits.

    Returns
    -------
    EngagementResult
        Time histories, events and outcome (``completed`` False and ``message`` saying why if a
        state failed).

    Raises
    ------
    ParameterError
        ``duration_s`` not a finite number > 0 or shorter than one step, ``x0`` of the wrong
        shape or not finite, a pilot or bow wave without a probe, a free length outside the
        reel's end stops.
    """
    _check_duration(duration_s)
    params.numerics.steps(duration_s)
    if seed is not None:
        params = params.replace(turbulence={"seed": int(seed)})
    reel = Reel() if reel is None else reel
    Engagement(reel=reel, probe=probe, bow_wave=bow_wave, pilot=pilot)  # the sections' rules (a pilot needs a probe)
    chain, model, drogue_eq, z = _initial_state(params, probe, equilibrium, x0, length_rate_m_s, gravity_m_s2,
                                                duration_s)
    ep = engagement_parameters(params, reel, probe, chain, drogue_eq, bow_wave)
    L0 = z[4 * chain.n + EK.Z_L]
    if not reel.min_length_m <= L0 <= reel.max_length_m:
        raise ParameterError(f"hose.length_m = {L0!r}: the free length must lie between the reel's end stops "
                             f"reel.min_length_m = {reel.min_length_m!r} and reel.max_length_m = {reel.max_length_m!r} m")
    set_pilot(ep, pilot, params.numerics.step_s)
    if drogue_actuator is not None:
        Loop(actuator=actuator, drogue_actuator=drogue_actuator)  # the loop's rule: the surfaces set the limits
        drogue_actuator.check_step(params.numerics.step_s)
    z = np.concatenate([z, extra_states(ep, control, actuator, pilot, drogue_actuator)])
    loop = engagement_loop(control, drogue_eq[1:], actuator, sensor, duration_s, params.turbulence.seed,
                           drogue_actuator)
    t_set = reel.tension_set_n
    if t_set < 0:
        t_set = exit_tension_at_rest(params, chain, z, ep, model)
        ep[EK.EP_TSET] = t_set
    outcome: dict[str, Any] = {"result": "no contact", "miss_distance_m": None, "closure_speed_m_s": None}
    if probe is None or not probe.enabled:
        outcome["result"] = "no probe"
    run = _Run(z=z, chain=chain, ep=ep, outcome=outcome, loop=loop,
               hist=drogue_history(ep, int(round(duration_s / params.numerics.step_s))),
               segments=[(chain, ep.copy(), np.array([0.0]), z[None, :].copy())])
    status, message = _integrate(run, params, probe, model, duration_s)
    return assemble_result(params, run.segments, run.events, run.outcome, model, drogue_eq, energy,
                           status == K.OK, message, run.delta_total, t_set, reel, probe, loop=loop,
                           drogue_actuator=drogue_actuator)


def _check_duration(duration_s) -> None:
    if not (isinstance(duration_s, (int, float)) and math.isfinite(duration_s) and duration_s > 0):
        raise ParameterError(f"duration_s = {duration_s!r}: must be a finite number > 0 s")


def _initial_state(params: Params, probe, equilibrium, x0, length_rate_m_s: float, gravity_m_s2, duration_s):
    """The initial chain, its model (with the gust record of the run), the drogue's reference
    position [m] and the full state z."""
    chain = initial_chain(params)
    need_eq = x0 is None or (probe is not None and probe.enabled)
    if equilibrium is None and need_eq:
        equilibrium, model = chain_equilibrium(params, chain, duration_s)
    else:
        model = chain_model(params, chain, duration_s)
    if gravity_m_s2 is not None:
        model.ps[K.PS_G] = float(gravity_m_s2)
    n = chain.n
    L0 = float(np.sum(chain.l))
    hose0 = equilibrium.state if x0 is None else np.asarray(x0, dtype=np.float64)
    if hose0.shape != (4 * n,) or not np.all(np.isfinite(hose0)):
        raise ParameterError(f"x0: must be a finite array of shape ({4 * n},)")
    if equilibrium is None:
        drogue_eq = model.joint_positions(hose0[: 2 * n])[-1]
    else:
        drogue_eq = equilibrium.drogue_position_m.copy()
    z = np.concatenate([hose0, [L0, float(length_rate_m_s)], np.zeros(EK.Z_TAIL - 2)])
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
        if code in (K.NONFINITE, K.YAW_LIMIT):
            return code, f"stopped at t = {run.t:.4f} s: {_STATUS[code]}"
        if code == EK.REEL_END:
            L = run.z[4 * run.chain.n + EK.Z_L]
            return code, (f"stopped at t = {run.t:.4f} s: {_STATUS[code]}: L = {L:.3f} m, range "
                          f"[{run.ep[EK.EP_L_MIN]:g}, {run.ep[EK.EP_L_MAX]:g}] m")
        if code == EK.CHART:
            _switch_charts(run, model)
        elif code in (EK.SPLIT, EK.MERGE):
            _remesh(run, code, params, model)
        elif code == EK.PLANE and _contact(run, zprev, h, probe, model):
            break
    return K.OK, "completed"


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
    code, done, saved = EK.eng_segment(
        z, run.t, run.step, h, remaining, every, chain.n, lw, Mw, Jw, model.ps, model.env, model.gust_values,
        run.ep, chain.chart, run.loop, run.hist, max_yaw, math.radians(SWITCH_YAW_DEG), SPLIT_RATIO * chain.l_nom,
        MERGE_RATIO * chain.l_nom, chain.n >= 2, zprev, ts, zs)
    run.step += done
    run.t = run.step * h
    if saved:
        run.segments.append((chain, run.ep.copy(), ts[:saved].copy(), zs[:saved].copy()))
    return code, zprev


def _at(run: _Run, model):
    """Outputs and energies of the current state (see :func:`.result.segment_outputs`)."""
    z1 = run.z[None, :]
    return _outputs(np.array([run.t]), z1, run.chain, model, run.ep, run.loop), _energies(z1, run.chain, model, run.ep)[0]


def _switch_charts(run: _Run, model) -> None:
    """Move the links near the singular yaw to the other angle chart; record the (zero) jumps."""
    before, e_before = _at(run, model)
    run.z, run.chain, moved = switch_charts(run.z, run.chain, math.radians(SWITCH_YAW_DEG))
    after, e_after = _at(run, model)
    run.events.append({"kind": "chart", "t_s": run.t, "links": moved,
                       "energy_jump_j": float(np.sum(e_after) - np.sum(e_before)),
                       "position_jump_m": float(np.max(np.abs(after[0] - before[0]))),
                       "velocity_jump_m_s": float(np.max(np.abs(after[1] - before[1])))})


def _joint_jumps(code: int, before, after) -> tuple[float, float]:
    """Largest jump of a joint's position [m] and velocity [m/s] across a split or merge."""
    jb, ja = before[0][0], after[0][0]
    vb, va = before[1][0], after[1][0]
    if code == EK.SPLIT:  # the new joint 1 is inserted; old joints k -> k+1
        pos_jump = np.max(np.abs(ja[np.r_[0, 2:ja.shape[0]]] - jb))
        vel_jump = np.max(np.abs(va[np.r_[2:va.shape[0]]] - vb[1:]))
    else:  # old joint 1 is removed; old joints k >= 2 -> k-1
        pos_jump = np.max(np.abs(ja - jb[np.r_[0, 2:jb.shape[0]]]))
        vel_jump = np.max(np.abs(va[1:] - vb[2:]))
    return float(pos_jump), float(vel_jump)


def _remesh(run: _Run, code: int, params: Params, model) -> None:
    """Split or merge the exit link; record the event with its jumps."""
    before, e_before = _at(run, model)
    n_before = run.chain.n
    Ld_before = run.z[4 * n_before + EK.Z_LD]
    if code == EK.SPLIT:
        run.z, run.chain = split(run.z, run.chain, params)
        delta = 0.0
    else:
        run.z, run.chain, delta = merge(run.z, run.chain, params)
        run.delta_total += delta
    after, e_after = _at(run, model)
    pos_jump, vel_jump = _joint_jumps(code, before, after)
    run.events.append({
        "kind": "split" if code == EK.SPLIT else "merge", "t_s": run.t, "links_before": n_before,
        "links_after": run.chain.n, "position_jump_m": pos_jump, "velocity_jump_m_s": vel_jump,
        "length_lost_m": float(delta),
        "reel_speed_jump_m_s": 0.0 if code == EK.SPLIT else float(-(run.z[4 * run.chain.n + EK.Z_LD] - Ld_before)),
        "energy_jump_j": float(np.sum(e_after) - np.sum(e_before)),
    })


def _plane_crossing(run: _Run, zprev: np.ndarray, h: float, model) -> tuple[float, float, float]:
    """Radial miss [m] and closure speed [m/s] where the probe tip crossed the coupler plane
    (linear between the last two steps), and the step fraction of the crossing."""
    joints, jvel, scal = _outputs(np.array([run.t - h, run.t]), np.stack([zprev, run.z]), run.chain, model,
                                  run.ep, run.loop)[:3]
    d = np.empty(2)
    radial = np.empty((2, 3))
    vclose = np.empty(2)
    for i in range(2):
        e_last = joints[i][-1] - joints[i][-2]
        e_last /= np.linalg.norm(e_last)
        p = scal[i, [EK.O_PX, EK.O_PY, EK.O_PZ]]
        vp = scal[i, [EK.O_VPX, EK.O_VPY, EK.O_VPZ]]
        rel = p - joints[i][-1]
        d[i] = rel @ e_last
        radial[i] = rel - d[i] * e_last
        vclose[i] = -(vp - jvel[i][-1]) @ e_last
    frac = d[0] / (d[0] - d[1])
    miss = float(np.linalg.norm(radial[0] + frac * (radial[1] - radial[0])))
    vc = float(vclose[0] + frac * (vclose[1] - vclose[0]))
    return miss, vc, frac


def _capture_verdict(probe: Probe, miss: float, vc: float) -> tuple[str, bool]:
    """The capture test (docs/engagement.md, "Capture"): the result and whether it is a capture."""
    if miss > probe.capture_radius_m:
        return (f"miss: radial miss {miss:.3f} m beyond the capture radius "
                f"{probe.capture_radius_m:g} m"), False
    if vc < probe.min_closure_speed_m_s:
        return (f"failed latch: closure speed {vc:.3f} m/s below the minimum "
                f"{probe.min_closure_speed_m_s:g} m/s"), False
    if vc > probe.max_closure_speed_m_s:
        return (f"failed latch: closure speed {vc:.3f} m/s above the maximum "
                f"{probe.max_closure_speed_m_s:g} m/s"), False
    return "captured", True


def _contact(run: _Run, zprev: np.ndarray, h: float, probe: Probe, model) -> bool:
    """The probe tip reached the coupler plane: test the capture, couple on success. Returns
    True if the run ends here (a miss or a failed latch)."""
    miss, vc, frac = _plane_crossing(run, zprev, h, model)
    t_cap = run.t - h + frac * h
    outcome = run.outcome
    outcome["miss_distance_m"] = miss
    outcome["closure_speed_m_s"] = vc
    outcome["contact_time_s"] = t_cap
    outcome["result"], captured = _capture_verdict(probe, miss, vc)
    if captured:
        run.ep[EK.EP_COUPLED] = 1.0
        run.ep[EK.EP_T_CAP] = t_cap
        run.ep[EK.EP_S_CAP] = run.ep[EK.EP_VC] * t_cap
    run.events.append({"kind": "contact", "t_s": t_cap, "miss_distance_m": miss, "closure_speed_m_s": vc,
                       "result": outcome["result"]})
    return not captured
