"""The result of an engagement run, and its assembly from the integrated segments.

:func:`~hosedrogue.engagement.driver.simulate_engagement` integrates segment by segment (one
discretization each); :func:`assemble_result` evaluates the compiled output and energy kernels
of :mod:`hosedrogue.model.engagement` on every segment's saved states, concatenates
them and adds the run's peaks to its outcome (what is reported per engagement:
docs/engagement.md, "What a run reports").
"""

from __future__ import annotations

import numpy as np

from ..results.statistics import turbulence_window
from ..model import drogue_actuator as DA, layout as LY
from ..results.surfaces import surface_fields
from ..model.engagement import chain as EC, outputs as EO
from ..spec.params import Params
from ..results.run import EngagementResult
from .chain import Chain

#: Names of the energy terms, in the order of the columns of the energy kernel and the work states.
ENERGY_TERMS = ("kinetic", "elastic", "reel", "motor", "friction", "exit", "flux", "probe", "axial")


def segment_outputs(ts: np.ndarray, zs: np.ndarray, chain: Chain, model, ep: np.ndarray, loop=None,
                    loads: np.ndarray | None = None, controlled: bool | None = None):
    """The compiled outputs of states ``zs`` of one discretization.

    Parameters
    ----------
    ts : array (N,)
        Times [s].
    zs : array (N, 4n + Z_TAIL)
        States: hose [rad, rad/s], L [m], L' [m/s] and the work states [J].
    chain : Chain
        The discretization the states belong to.
    model : hosedrogue.model.system.HoseModel
        Parameter, environment and gust arrays.
    ep : array (EP_SIZE,)
        Engagement parameters (:func:`hosedrogue.engagement.parameters.engagement_parameters`).
    loop : LoopArrays, optional
        The drogue controller's arrays (:func:`hosedrogue.engagement.loop.engagement_loop`); needed
        when ``ep[EP_CTRL]`` is set, else an empty loop is used.
    loads : array (N, 4), optional
        Elastic links: receives each state's loads as the time loop's per-step record has them
        (exit and drogue-end tension [N], probe load [N], slack [m]; ``model.engagement.outputs.state_loads``).
    controlled : bool, optional
        The compiled variant, with the drogue controller or without
        (``model.engagement.outputs.eng_outputs``; default: whether ``ep`` has it).

    Returns
    -------
    joints, jvel : array (N, n+1, 3)
        Joint positions [m] and velocities [m/s].
    scal : array (N, O_SIZE)
        Scalar outputs (``model.layout.O_*``: tensions [N], probe [m, m/s, N], slack [m],
        torque [N m]).
    tow : array (N, 3)
        Force of the hose on the exit [N].
    tdrog : array (N,)
        Tension in the last link [N].
    drag : array (N, 3)
        Aerodynamic force on the drogue [N].
    links_t : array (N, n)
        Elastic links: every link's tension [N], exit link first (NaN for rigid links).
    """
    n = chain.n
    N = ts.size
    joints = np.empty((N, n + 1, 3))
    jvel = np.empty((N, n + 1, 3))
    scal = np.empty((N, LY.O_SIZE))
    tow = np.empty((N, 3))
    tdrog = np.empty(N)
    drag = np.empty((N, 3))
    # the elastic kernel writes every link's tension of every row; rigid links leave theirs NaN
    links_t = np.empty((N, n)) if ep[LY.EP_ELASTIC] != 0.0 else np.full((N, n), np.nan)
    if loop is None:
        from .loop import no_loop

        loop = no_loop()
    if loads is None:
        loads = np.empty((N, 4))
    EO.eng_outputs(np.ascontiguousarray(ts), np.ascontiguousarray(zs), n, chain.l.copy(), chain.M.copy(),
                   chain.J.copy(), model.ps, model.env, model.gust_values, ep, chain.chart, loop, joints, jvel, scal, tow, tdrog,
                   drag, links_t, loads, controlled)
    return joints, jvel, scal, tow, tdrog, drag, links_t


def segment_energies(zs: np.ndarray, chain: Chain, model, ep: np.ndarray, kinematics: bool = False):
    """Kinetic, elastic and reel energy [J] of states ``zs`` of one discretization, and with
    ``kinematics`` their joint positions and velocities (:func:`segment_outputs`' ``joints`` and
    ``jvel``, the same numbers, without the rest of an evaluation).

    Parameters
    ----------
    zs : array (N, 4n + Z_TAIL)
        States (see :func:`segment_outputs`).
    chain : Chain
        The discretization the states belong to.
    model : hosedrogue.model.system.HoseModel
        Parameter array ``ps``.
    ep : array (EP_SIZE,)
        Engagement parameters.
    kinematics : bool
        Also return the states' joint positions and velocities (what a remesh event compares).

    Returns
    -------
    array (N, 3)
        Kinetic, elastic (gravity and probe spring) and reel energy [J]; with ``kinematics`` a
        tuple (joints, jvel, energies), joints and jvel (N, n+1, 3) [m, m/s].
    """
    out = np.empty((zs.shape[0], 3))
    joints = np.empty((zs.shape[0], chain.n + 1, 3))
    jvel = np.empty_like(joints)
    for i, z in enumerate(zs):
        out[i] = EO.eng_energy(np.ascontiguousarray(z), chain.n, chain.l.copy(), chain.M.copy(),
                               chain.J.copy(), model.ps, ep, chain.chart, joints[i], jvel[i])
    return (joints, jvel, out) if kinematics else out


def coupler_geometry(joints, jvel, scal):
    """The probe tip relative to the coupler plane (its normal: the last link's direction).

    Parameters
    ----------
    joints, jvel : array (N, n+1, 3)
        Joint positions [m] and velocities [m/s] (:func:`segment_outputs`).
    scal : array (N, O_SIZE)
        The scalar outputs (probe tip position and velocity [m, m/s]).

    Returns
    -------
    distance : array (N,)
        Probe tip minus drogue along the normal [m]: positive while the tip is aft of the plane
        (the last link points aft).
    miss : array (N,)
        Radial distance of the tip from the drogue's axis [m].
    closure : array (N,)
        Closure speed of the tip toward the plane [m/s].
    """
    e_last = joints[:, -1, :] - joints[:, -2, :]
    e_last /= np.linalg.norm(e_last, axis=1)[:, None]
    rel = scal[:, [LY.O_PX, LY.O_PY, LY.O_PZ]] - joints[:, -1, :]
    dpl = np.einsum("ij,ij->i", rel, e_last)
    miss = np.linalg.norm(rel - dpl[:, None] * e_last, axis=1)
    vp = scal[:, [LY.O_VPX, LY.O_VPY, LY.O_VPZ]]
    return dpl, miss, -np.einsum("ij,ij->i", vp - jvel[:, -1, :], e_last)


def _hose_masses(zs, chain: Chain, ep, params: Params) -> np.ndarray:
    """Hose mass in the air [kg] at every state, from the lumped masses at its length.

    Only the exit link's length and joint mass depend on the paid-out length, so the lumped masses
    of every state are one array with that column set as :func:`..model.engagement.chain.set_variable_link`
    sets it (its sum of the fixed links in the same order) and summed row by row as
    :func:`.chain.hose_mass_in_air` sums one state: the same numbers, bit for bit, at a
    hundredth of the cost of a call per state.
    """
    n = chain.n
    lengths = zs[:, EC.tail_start(n, ep) + LY.Z_L]
    if lengths.size == 0:
        return np.zeros(0)
    fixed = 0.0
    for k in range(1, n):
        fixed += chain.l[k]
    exit_l = lengths - fixed
    mu, drogue = ep[LY.EP_MU], ep[LY.EP_MD] if n == 1 else 0.0
    if ep[LY.EP_SPLIT] != 0.0:
        exit_m = 0.5 * mu * exit_l + drogue if n == 1 else 0.5 * mu * (exit_l + chain.l[1])
    else:
        exit_m = mu * exit_l + drogue
    masses = np.repeat(chain.M[None, :], lengths.size, axis=0)
    masses[:, 0] = exit_m
    m = masses.sum(axis=1) - params.drogue.mass_kg
    if params.hose.mass_lumping == "split":
        m += 0.5 * params.hose.mass_per_length_kg_m * exit_l
    return m


def _segment_columns(params: Params, segment, model, energy: bool, loop) -> tuple[dict, np.ndarray, np.ndarray]:
    """One segment's columns (keys of :func:`assemble_result`), joint positions and velocities."""
    chain, ep, ts, zs = segment
    n = chain.n
    loads = np.empty((ts.size, 4))
    joints, jvel, scal, tow, tdrog, drag, links_t = segment_outputs(ts, zs, chain, model, ep, loop, loads)
    dpl, miss, vclose = coupler_geometry(joints, jvel, scal)
    b = EC.tail_start(n, ep)
    cols = {"t": ts, "L": zs[:, b + LY.Z_L], "Ld": zs[:, b + LY.Z_LD], "T0": scal[:, LY.O_T0],
            "Td": tdrog, "fp": scal[:, [LY.O_FPX, LY.O_FPY, LY.O_FPZ]], "pp": scal[:, [LY.O_PX, LY.O_PY, LY.O_PZ]],
            "cp": np.full(ts.size, ep[LY.EP_COUPLED] != 0.0), "slack": scal[:, LY.O_SLACK],
            "rd": joints[:, -1, :], "vd": jvel[:, -1, :], "tow": tow, "tau": scal[:, LY.O_TAU],
            "miss": miss, "dplane": dpl, "vclose": vclose, "links": np.full(ts.size, n),
            "mass": _hose_masses(zs, chain, ep, params), "u": scal[:, [LY.O_UY, LY.O_UZ]], "drag": drag,
            "links_t": list(links_t), "hose_states": [(zs[:, :4 * n], np.asarray(chain.chart, dtype=float))],
            "loads": loads}
    if loop is not None and ep[LY.EP_CTRL] != 0.0 and DA.is_actuated(loop.act):
        ns = int(loop.act[DA.DA_NS])
        na = b + LY.Z_TAIL + int(ep[LY.EP_NPIL]) + loop.Ac.shape[0]
        cols["defl"] = zs[:, na:na + ns]
        cols["rate"] = scal[:, LY.O_SERVO:LY.O_SERVO + ns]
        cols["q"] = scal[:, LY.O_Q]
    if energy:
        en = segment_energies(zs, chain, model, ep)
        cols["E"] = np.column_stack([en, zs[:, b + LY.Z_WM:b + LY.Z_WAX + 1]])
    return cols, joints, jvel


def _peaks(cat: dict, drogue_eq, events: list, delta_total: float, t_set: float) -> dict:
    """The run's peaks and hose lengths (outcome keys, units in their names)."""
    excursion = np.linalg.norm(cat["rd"] - drogue_eq, axis=1)
    return {
        "peak_probe_load_n": float(np.max(np.linalg.norm(cat["fp"], axis=1))),
        "peak_exit_tension_n": float(np.max(cat["T0"])),
        "min_exit_tension_n": float(np.min(cat["T0"])),
        "peak_drogue_tension_n": float(np.max(cat["Td"])),
        "peak_tension_rise_n": float(np.max(cat["T0"]) - cat["T0"][0]),
        "peak_slack_m": float(np.max(cat["slack"])),
        "peak_drogue_excursion_m": float(np.max(excursion)),
        "hose_length_start_m": float(cat["L"][0]),
        "hose_length_end_m": float(cat["L"][-1]),
        "hose_length_min_m": float(np.min(cat["L"])),
        "length_taken_up_m": float(cat["L"][0] - np.min(cat["L"])),
        "length_lost_at_merges_m": float(delta_total),
        "tension_set_n": float(t_set),
        "remesh_events": sum(1 for e in events if e["kind"] in ("split", "merge")),
        "peak_control_force_n": float(np.max(np.linalg.norm(cat["u"], axis=1))),
    }


def _step_peaks(record: np.ndarray) -> dict:
    """The peaks of the per-step load record (t [s], exit tension [N], drogue-end tension [N],
    probe load [N], slack [m]), which replace those of the saved outputs: a whip's tension pulse
    lasts a few milliseconds, shorter than the output interval; none when the run stopped before its
    first step."""
    record = record[np.all(np.isfinite(record), axis=1)]  # a diverged run's last state aside
    if not record.size:  # stopped before its first step (a controller failing at t = 0): the outputs' peaks stay
        return {}
    return {"peak_probe_load_n": float(np.max(record[:, 3])),
            "peak_exit_tension_n": float(np.max(record[:, 1])),
            "peak_tension_rise_n": float(np.max(record[:, 1]) - record[0, 1]),
            "min_exit_tension_n": float(np.min(record[:, 1])),
            "peak_drogue_tension_n": float(np.max(record[:, 2])),
            "peak_slack_m": float(np.max(record[:, 4]))}


def assemble_result(params: Params, segments: list, events: list, outcome: dict, model, drogue_eq: np.ndarray,
                    energy: bool, completed: bool, message: str, delta_total: float, t_set: float,
                    reel, probe, loop=None, step_loads: np.ndarray | None = None,
                    drogue_actuator=None, loads_from_outputs: bool = False) -> EngagementResult:
    """Evaluate the outputs of every segment and build the run's result.

    Parameters
    ----------
    params : Params
        The run's parameters (hose mass per length [kg/m] and lumping for ``hose_mass_kg``).
    segments : list of (Chain, array, array, array)
        Per segment: its discretization, engagement parameters, output times [s] and states.
    events : list of dict
        Remesh, chart and contact events.
    outcome : dict
        Result and contact figures so far; updated in place with the peaks.
    model : hosedrogue.model.system.HoseModel
        Parameter, environment and gust arrays of the run.
    drogue_eq : array (3,)
        Drogue position at the start [m] (the reference of the excursion).
    energy : bool
        Also evaluate the energy terms [J].
    completed : bool
        Whether the run reached its end without a failed state.
    message : str
        "completed" or why it stopped.
    delta_total : float
        Hose length lost at merges [m].
    t_set : float
        Tension set point of the reel [N] (resolved if the reel's was negative).
    reel : Reel
        The drum unit.
    probe : Probe or None
        The receiver's probe.
    loop : LoopArrays, optional
        The drogue controller's arrays (see :func:`segment_outputs`).
    step_loads : array (steps + 1, 4), optional
        Elastic links: exit and drogue-end tension [N], probe load [N] and slack [m] after every
        integration step (``model.engagement.outputs.state_loads``); the run's peaks are taken from it.
        With ``loads_from_outputs`` its rows at the saved steps are written here, in place, from
        the saved states' outputs.
    drogue_actuator : hosedrogue.spec.sections.DrogueActuator, optional
        The drogue's control surfaces (their deflections, rates and q become result fields).
    loads_from_outputs : bool
        The time loop left the saved steps' rows of ``step_loads`` to the saved states' outputs
        (the driver's segments: ``model.engagement.steps.eng_steps``, ``saved_loads``).

    Returns
    -------
    EngagementResult
    """
    cols: dict = {}
    joints_all, jvel_all = [], []
    for segment in segments:
        seg, joints, jvel = _segment_columns(params, segment, model, energy, loop)
        for k, v in seg.items():
            cols.setdefault(k, []).append(v)
        joints_all.extend(list(joints))
        jvel_all.extend(list(jvel))
    link_tensions = [t for seg in cols.pop("links_t") for t in seg] if params.hose.elastic else None
    cols.pop("links_t", None)
    hose_states = [s for seg in cols.pop("hose_states") for s in seg]  # matrices built when asked for
    saved_loads = cols.pop("loads")
    cat = {k: np.concatenate(v) for k, v in cols.items()}
    surfaces = {} if "defl" not in cat else surface_fields(cat["defl"], cat["rate"], cat["q"], drogue_actuator)
    en_dict = {name: cat["E"][:, i] for i, name in enumerate(ENERGY_TERMS)} if energy else {}
    outcome.update(_peaks(cat, drogue_eq, events, delta_total, t_set))
    record = None
    if step_loads is not None:
        if loads_from_outputs:  # the saved steps' rows, the same numbers as the time loop's
            step_loads[np.rint(cat["t"] / params.numerics.step_s).astype(np.int64)] = np.concatenate(saved_loads)
        record = np.column_stack([np.arange(step_loads.shape[0]) * params.numerics.step_s, step_loads])
        outcome.update(_step_peaks(record))
    if reel.law == "locked":
        outcome["tension_set_n"] = None
    meta = {"reel": reel.to_dict(), "probe": probe.to_dict() if probe is not None else None,
            "lumping": params.hose.mass_lumping,
            "events": events}
    return EngagementResult(
        t_s=cat["t"], hose_length_m=cat["L"], reel_speed_m_s=-cat["Ld"], exit_tension_n=cat["T0"],
        drogue_tension_n=cat["Td"], probe_force_n=cat["fp"], probe_position_m=cat["pp"], coupled=cat["cp"],
        slack_m=cat["slack"], drogue_position_m=cat["rd"], drogue_velocity_m_s=cat["vd"], tow_force_n=cat["tow"],
        drogue_drag_n=cat["drag"],
        motor_torque_n_m=cat["tau"], control_force_n=cat["u"], miss_distance_series_m=cat["miss"], plane_distance_m=cat["dplane"],
        closure_speed_series_m_s=cat["vclose"],
        links=cat["links"], hose_mass_kg=cat["mass"], joints_m=joints_all, joint_velocities_m_s=jvel_all,
        energy=en_dict, events=events, outcome=outcome, step_loads=record, link_tensions_n=link_tensions,
        hose_states=hose_states, equilibrium_m=np.asarray(drogue_eq, dtype=float).copy(),
        completed=completed, message=message, meta=meta, statistics_window_s=turbulence_window(params.turbulence),
        **surfaces)
