"""The events that end a compiled segment of the engagement: a chart switch, a remesh (split or
merge of the exit link) and the probe tip reaching the coupler plane (the capture test,
docs/engagement.md "Capture"), and the failures that end the run. Each handler takes the run's
state between segments (the driver's ``_Run``: state, chain, parameters, time, events, outcome),
changes it and records the event with its jumps; :func:`segment_event` picks the handler of a
segment's code and :func:`failure_reason` words a failure, for both loops that run segments (the
driver's and the stepper's).
"""

from __future__ import annotations

import math

import numpy as np

from ..model import layout as LY
from ..model.engagement import chain as EC
from ..model.status import status_text
from ..spec.sections import Probe
from .chain import SWITCH_YAW_DEG, merge, split, switch_charts
from .result import segment_energies as _energies
from .result import segment_outputs as _outputs


def _at(run, model):
    """Joint positions and velocities (rows of :func:`.result.segment_outputs`' ``joints``, ``jvel``)
    and energies of the current state: a kinematic pass, not an evaluation."""
    joints, jvel, energies = _energies(run.z[None, :], run.chain, model, run.ep, kinematics=True)
    return (joints, jvel), energies[0]


def switch_event(run, model) -> None:
    """Move the links near the singular yaw to the other angle chart; record the (zero) jumps.

    Parameters
    ----------
    run : hosedrogue.engagement.driver._Run
        The run between segments (state, chain, parameters, time [s], events), changed in place.
    model : hosedrogue.model.system.HoseModel
        Parameter, environment and gust arrays.
    """
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
    if code == LY.SPLIT:  # the new joint 1 is inserted; old joints k -> k+1
        pos_jump = np.max(np.abs(ja[np.r_[0, 2:ja.shape[0]]] - jb))
        vel_jump = np.max(np.abs(va[np.r_[2:va.shape[0]]] - vb[1:]))
    else:  # old joint 1 is removed; old joints k >= 2 -> k-1
        pos_jump = np.max(np.abs(ja - jb[np.r_[0, 2:jb.shape[0]]]))
        vel_jump = np.max(np.abs(va[1:] - vb[2:]))
    return float(pos_jump), float(vel_jump)


def remesh_event(run, code: int, params, model) -> None:
    """Split or merge the exit link; record the event with its jumps.

    Parameters
    ----------
    run : hosedrogue.engagement.driver._Run
        The run between segments (state, chain, parameters, time [s], events), changed in place.
    code : int
        ``model.layout.SPLIT`` or ``MERGE``.
    params : Params
        For the masses [kg] and inertias [kg m^2] of the new mesh.
    model : hosedrogue.model.system.HoseModel
        Parameter, environment and gust arrays.
    """
    before, e_before = _at(run, model)
    n_before = run.chain.n
    Ld_before = run.z[EC.tail_start(n_before, run.ep) + LY.Z_LD]
    if code == LY.SPLIT:
        run.z, run.chain = split(run.z, run.chain, params)
        delta = 0.0
    else:
        run.z, run.chain, delta = merge(run.z, run.chain, params)
        run.delta_total += delta
    after, e_after = _at(run, model)
    pos_jump, vel_jump = _joint_jumps(code, before, after)
    run.events.append({
        "kind": "split" if code == LY.SPLIT else "merge", "t_s": run.t, "links_before": n_before,
        "links_after": run.chain.n, "position_jump_m": pos_jump, "velocity_jump_m_s": vel_jump,
        "length_lost_m": float(delta),
        "reel_speed_jump_m_s": 0.0 if code == LY.SPLIT else float(-(run.z[EC.tail_start(run.chain.n, run.ep) + LY.Z_LD] - Ld_before)),
        "energy_jump_j": float(np.sum(e_after) - np.sum(e_before)),
    })


def _plane_crossing(run, zprev: np.ndarray, h: float, model) -> tuple[float, float, float]:
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
        p = scal[i, [LY.O_PX, LY.O_PY, LY.O_PZ]]
        vp = scal[i, [LY.O_VPX, LY.O_VPY, LY.O_VPZ]]
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


def contact_event(run, zprev: np.ndarray, h: float, probe: Probe, model) -> bool:
    """The probe tip reached the coupler plane: test the capture, couple on success.

    Parameters
    ----------
    run : hosedrogue.engagement.driver._Run
        The run between segments (state, chain, parameters, time [s], events), changed in place.
    zprev : array
        The state one step before the crossing.
    h : float
        The RK4 step [s].
    probe : Probe
        The capture radius [m] and closure speed window [m/s].
    model : hosedrogue.model.system.HoseModel
        Parameter, environment and gust arrays.

    Returns
    -------
    bool
        True if the run ends here (a miss or a failed latch).
    """
    miss, vc, frac = _plane_crossing(run, zprev, h, model)
    t_cap = run.t - h + frac * h
    outcome = run.outcome
    outcome["miss_distance_m"] = miss
    outcome["closure_speed_m_s"] = vc
    outcome["contact_time_s"] = t_cap
    outcome["result"], captured = _capture_verdict(probe, miss, vc)
    if captured:
        run.ep[LY.EP_COUPLED] = 1.0
        run.ep[LY.EP_T_CAP] = t_cap
        run.ep[LY.EP_S_CAP] = run.ep[LY.EP_VC] * t_cap
    run.events.append({"kind": "contact", "t_s": t_cap, "miss_distance_m": miss, "closure_speed_m_s": vc,
                       "result": outcome["result"]})
    return not captured


#: the segment's codes that end a run early, incomplete (their reasons: :func:`failure_reason`)
FAILURES = (LY.NONFINITE, LY.YAW_LIMIT, LY.STAGE_LIMIT, LY.REEL_END)


def failure_reason(run, code: int) -> str:
    """Why an engagement run stopped with a failing segment code.

    Parameters
    ----------
    run : hosedrogue.engagement.driver._Run
        The run (its state, chain and engagement parameters).
    code : int
        One of :data:`FAILURES`.

    Returns
    -------
    str
        The status table's line (:data:`hosedrogue.model.status.STATUS_TEXT`), and for the reel at
        an end stop the free length and the reel's range.
    """
    reason = status_text(code)
    if code == LY.REEL_END:
        L = run.z[EC.tail_start(run.chain.n, run.ep) + LY.Z_L]
        reason += f": L = {L:.3f} m, range [{run.ep[LY.EP_L_MIN]:g}, {run.ep[LY.EP_L_MAX]:g}] m"
    return reason


def segment_event(run, code: int, params, model, zprev: np.ndarray, h: float, probe: Probe) -> bool:
    """Handle the event that ended a compiled segment (not a failure: :data:`FAILURES`).

    Parameters
    ----------
    run : hosedrogue.engagement.driver._Run
        The run between segments.
    code : int
        The segment's code: ``CHART`` (:func:`switch_event`), ``SPLIT`` or ``MERGE``
        (:func:`remesh_event`), ``PLANE`` (:func:`contact_event`); any other (``OK``: the segment
        reached its end) changes nothing.
    params : hosedrogue.spec.params.Params
        The run's parameters.
    model : hosedrogue.model.system.HoseModel
        The run's model.
    zprev : numpy.ndarray
        The state one step before the segment's last.
    h : float
        The step [s].
    probe : hosedrogue.spec.sections.Probe
        The probe (its capture rule).

    Returns
    -------
    bool
        True when the event ends the run, complete: a miss or a failed latch at the coupler plane.
    """
    if code == LY.CHART:
        switch_event(run, model)
    elif code in (LY.SPLIT, LY.MERGE):
        remesh_event(run, code, params, model)
    elif code == LY.PLANE:
        return contact_event(run, zprev, h, probe, model)
    return False
