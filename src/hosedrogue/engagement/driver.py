"""The engagement simulation: a reel, a hose of varying length, a prescribed probe.

:func:`simulate_engagement` integrates the compiled RK4 loop of
:mod:`hosedrogue.model.engagement_kernels` segment by segment; a segment ends at a change of the
discretization (split or merge of the exit link, see :mod:`.chain`), at the probe tip crossing
the coupler plane (the capture test: ENGAGEMENT.md 2), at a failed state, or at the end.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..model import engagement_kernels as EK
from ..model import kernels as K
from ..params import ParameterError, Params
from .chain import (MERGE_RATIO, SPLIT_RATIO, SWITCH_YAW_DEG, Chain, chain_equilibrium, hose_mass_in_air,
                    initial_chain, merge, split, switch_charts)
from .spec import Probe, Reel

LAW_CODES = {"locked": EK.LAW_LOCKED, "constant-tension": EK.LAW_CONSTANT_TENSION, "response": EK.LAW_RESPONSE}
_STATUS = {K.NONFINITE: "the state became non-finite (numerical divergence)",
           K.YAW_LIMIT: "a link's yaw passed the limit where the angle coordinates become singular"}


@dataclass
class EngagementResult:
    """Time histories (S_p, SI units) and the outcome of one engagement run."""

    t_s: np.ndarray
    hose_length_m: np.ndarray
    reel_speed_m_s: np.ndarray  #: take-up speed r_d w, positive reeling in
    exit_tension_n: np.ndarray  #: T_0: hose tension at the exit along the hose
    drogue_tension_n: np.ndarray  #: tension in the last link (at the drogue)
    probe_force_n: np.ndarray  #: (N, 3) force of the probe on the drogue
    probe_position_m: np.ndarray  #: (N, 3)
    coupled: np.ndarray  #: (N,) bool
    slack_m: np.ndarray  #: hose length minus the straight exit-to-drogue distance
    drogue_position_m: np.ndarray  #: (N, 3)
    drogue_velocity_m_s: np.ndarray  #: (N, 3)
    tow_force_n: np.ndarray  #: (N, 3) force of the hose on the exit
    motor_torque_n_m: np.ndarray
    miss_distance_series_m: np.ndarray  #: radial probe-to-coupler distance in the coupler plane
    plane_distance_m: np.ndarray  #: probe tip aft of the coupler plane (positive before contact)
    closure_speed_series_m_s: np.ndarray  #: probe speed toward the coupler plane relative to the drogue
    links: np.ndarray  #: (N,) number of links
    hose_mass_kg: np.ndarray  #: hose mass in the air from the lumped masses
    joints_m: list  #: per output time, (n+1, 3) joint positions
    joint_velocities_m_s: list
    energy: dict  #: "kinetic", "elastic", "reel", "motor", "friction", "exit", "flux", "probe" (N,) [J]
    events: list  #: remesh and capture events (dicts)
    outcome: dict
    equilibrium_m: np.ndarray
    completed: bool
    message: str
    meta: dict = field(default_factory=dict)

    @property
    def drogue_offset_m(self) -> np.ndarray:
        return self.drogue_position_m - self.equilibrium_m

    def to_dataframe(self):
        import pandas as pd

        pos, off, vel, tow = self.drogue_position_m, self.drogue_offset_m, self.drogue_velocity_m_s, self.tow_force_n
        cols = {
            "t_s": self.t_s,
            "drogue_x_m": pos[:, 0], "drogue_y_m": pos[:, 1], "drogue_z_m": pos[:, 2],
            "drogue_dx_m": off[:, 0], "drogue_dy_m": off[:, 1], "drogue_dz_m": off[:, 2],
            "drogue_vx_m_s": vel[:, 0], "drogue_vy_m_s": vel[:, 1], "drogue_vz_m_s": vel[:, 2],
            "tow_force_x_n": tow[:, 0], "tow_force_y_n": tow[:, 1], "tow_force_z_n": tow[:, 2],
            "hose_length_m": self.hose_length_m,
            "reel_speed_m_s": self.reel_speed_m_s,
            "exit_tension_n": self.exit_tension_n,
            "drogue_tension_n": self.drogue_tension_n,
            "probe_load_n": np.linalg.norm(self.probe_force_n, axis=1),
            "probe_x_m": self.probe_position_m[:, 0], "probe_y_m": self.probe_position_m[:, 1],
            "probe_z_m": self.probe_position_m[:, 2],
            "miss_distance_m": self.miss_distance_series_m,
            "probe_plane_distance_m": self.plane_distance_m,
            "closure_speed_m_s": self.closure_speed_series_m_s,
            "slack_m": self.slack_m,
            "motor_torque_n_m": self.motor_torque_n_m,
            "links": self.links,
            "coupled": self.coupled.astype(int),
        }
        return pd.DataFrame(cols)

    def to_csv(self, path):
        from pathlib import Path

        path = Path(path)
        self.to_dataframe().to_csv(path, index=False, float_format="%.10g")
        return path


def engagement_parameters(params: Params, reel: Reel, probe: Probe | None, chain: Chain,
                          drogue_eq: np.ndarray) -> np.ndarray:
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
    return ep


def exit_tension_at_rest(params: Params, chain: Chain, z: np.ndarray, ep: np.ndarray, model) -> float:
    """T_0 [N] of state z with the reel held (L'' = 0): the steady trail tension at a balance position."""
    e = ep.copy()
    e[EK.EP_LAW] = EK.LAW_LOCKED
    e[EK.EP_PAY_DIST] = 0.0
    e[EK.EP_PROBE] = 0.0
    scal = _outputs(np.zeros(1), z[None, :], chain, model, e)[2]
    return float(scal[0, EK.O_T0])


def _outputs(ts, zs, chain: Chain, model, ep):
    n = chain.n
    N = ts.size
    joints = np.empty((N, n + 1, 3))
    jvel = np.empty((N, n + 1, 3))
    scal = np.empty((N, EK.O_SIZE))
    tow = np.empty((N, 3))
    tdrog = np.empty(N)
    EK.eng_outputs(np.ascontiguousarray(ts), np.ascontiguousarray(zs), n, chain.l.copy(), chain.M.copy(),
                   chain.J.copy(), model.ps, model.env, model.gust_values, ep, chain.chart, joints, jvel, scal, tow, tdrog)
    return joints, jvel, scal, tow, tdrog


def _energies(zs, chain: Chain, model, ep):
    out = np.empty((zs.shape[0], 3))
    for i, z in enumerate(zs):
        out[i] = EK.eng_energy(np.ascontiguousarray(z), chain.n, chain.l.copy(), chain.M.copy(),
                               chain.J.copy(), model.ps, ep, chain.chart)
    return out


def simulate_engagement(params: Params, reel: Reel, probe: Probe | None, duration_s: float,
                        energy: bool = False,
                        equilibrium=None, x0: np.ndarray | None = None, length_rate_m_s: float = 0.0,
                        gravity_m_s2: float | None = None) -> EngagementResult:
    """Simulate an engagement from the balance position at rest (steady air plus the
    ``params.turbulence`` gusts if enabled).

    Parameters
    ----------
    params : Params
        Hose, drogue, flight and numerics (RK4, ``numerics.step_s``, ``output_every``). The link
        masses are lumped as ``hose.mass_lumping`` says (docs/model.md §2; ``split`` converges at
        second order, the engagement scenarios set it).
    reel, probe : Reel, Probe or None
        The drum unit and the receiver's probe (None: no probe).
    duration_s : float
        Simulated time [s]; a miss ends the run earlier with the reason in ``outcome``.
    energy : bool
        Also evaluate the energy terms at every output time (for the energy balance).
    equilibrium : Equilibrium, optional
        Reuse a solved balance position of the initial mesh.
    x0 : array (4n,), optional
        Initial hose state [q, qd] instead of the balance position at rest (then, without a
        probe, no balance position is solved: the probe starts from it).
    length_rate_m_s : float
        Initial L' [m/s] (positive paying out).
    gravity_m_s2 : float, optional
        Overrides g (0 for the energy balance without gravity).
    """
    if not (isinstance(duration_s, (int, float)) and math.isfinite(duration_s) and duration_s > 0):
        raise ParameterError(f"duration_s = {duration_s!r}: must be a finite number > 0 s")
    num = params.numerics
    h = num.step_s
    every = num.output_every
    total_steps = int(round(duration_s / h))
    chain = initial_chain(params)
    from .chain import ChainModel

    need_eq = x0 is None or (probe is not None and probe.enabled)
    if equilibrium is None and need_eq:
        equilibrium, model = chain_equilibrium(params, chain)
    else:
        model = ChainModel(params, chain)
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
    ep = engagement_parameters(params, reel, probe, chain, drogue_eq)
    t_set = reel.tension_set_n
    if t_set < 0:
        t_set = exit_tension_at_rest(params, chain, z, ep, model)
        ep[EK.EP_TSET] = t_set
    max_yaw = math.radians(num.max_yaw_deg)

    segments = []  # (chain, ep copy, ts, zs)
    events: list[dict[str, Any]] = []
    outcome: dict[str, Any] = {"result": "no contact", "miss_distance_m": None, "closure_speed_m_s": None}
    if probe is None or not probe.enabled:
        outcome["result"] = "no probe"
    segments.append((chain, ep.copy(), np.array([0.0]), z[None, :].copy()))
    step = 0
    t = 0.0
    status = K.OK
    message = "completed"
    stop = False
    delta_total = 0.0
    while step < total_steps and not stop:
        remaining = total_steps - step
        nsave = remaining // every + 2
        ts = np.empty(nsave)
        zs = np.empty((nsave, z.size))
        zprev = np.empty(z.size)
        lw = chain.l.copy()
        Mw = chain.M.copy()
        Jw = chain.J.copy()
        code, done, saved = EK.eng_segment(
            z, t, step, h, remaining, every, chain.n, lw, Mw, Jw, model.ps, model.env, model.gust_values,
            ep, chain.chart, max_yaw, math.radians(SWITCH_YAW_DEG), SPLIT_RATIO * chain.l_nom, MERGE_RATIO * chain.l_nom, chain.n >= 2, zprev, ts, zs)
        step += done
        t = step * h
        if saved:
            segments.append((chain, ep.copy(), ts[:saved].copy(), zs[:saved].copy()))
        if code in (K.NONFINITE, K.YAW_LIMIT):
            status = code
            message = f"stopped at t = {t:.4f} s: {_STATUS[code]}"
            break
        if code == EK.CHART:
            before = _outputs(np.array([t]), z[None, :], chain, model, ep)
            e_before = _energies(z[None, :], chain, model, ep)[0]
            z, chain, moved = switch_charts(z, chain, math.radians(SWITCH_YAW_DEG))
            after = _outputs(np.array([t]), z[None, :], chain, model, ep)
            e_jump = float(np.sum(_energies(z[None, :], chain, model, ep)[0]) - np.sum(e_before))
            events.append({"kind": "chart", "t_s": t, "links": moved, "energy_jump_j": e_jump,
                           "position_jump_m": float(np.max(np.abs(after[0] - before[0]))),
                           "velocity_jump_m_s": float(np.max(np.abs(after[1] - before[1])))})
            continue
        if code in (EK.SPLIT, EK.MERGE):
            before = _outputs(np.array([t]), z[None, :], chain, model, ep)
            e_before = _energies(z[None, :], chain, model, ep)[0]
            n_before = chain.n
            if code == EK.SPLIT:
                z, chain = split(z, chain, params)
                delta = 0.0
            else:
                Ld_before = z[4 * n_before + EK.Z_LD]
                z, chain, delta = merge(z, chain, params)
                delta_total += delta
            after = _outputs(np.array([t]), z[None, :], chain, model, ep)
            e_after = _energies(z[None, :], chain, model, ep)[0]
            jb, ja = before[0][0], after[0][0]
            vb, va = before[1][0], after[1][0]
            if code == EK.SPLIT:  # the new joint 1 is inserted; old joints k -> k+1
                pos_jump = np.max(np.abs(ja[np.r_[0, 2:ja.shape[0]]] - jb))
                vel_jump = np.max(np.abs(va[np.r_[2:va.shape[0]]] - vb[1:]))
            else:  # old joint 1 is removed; old joints k >= 2 -> k-1
                pos_jump = np.max(np.abs(ja - jb[np.r_[0, 2:jb.shape[0]]]))
                vel_jump = np.max(np.abs(va[1:] - vb[2:]))
            events.append({
                "kind": "split" if code == EK.SPLIT else "merge", "t_s": t, "links_before": n_before,
                "links_after": chain.n, "position_jump_m": float(pos_jump), "velocity_jump_m_s": float(vel_jump),
                "length_lost_m": float(delta),
                "reel_speed_jump_m_s": 0.0 if code == EK.SPLIT else float(-(z[4 * chain.n + EK.Z_LD] - Ld_before)),
                "energy_jump_j": float(np.sum(e_after) - np.sum(e_before)),
            })
            continue
        if code == EK.PLANE:
            out = _outputs(np.array([t - h, t]), np.stack([zprev, z]), chain, model, ep)
            joints, jvel, scal = out[0], out[1], out[2]
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
            t_cap = t - h + frac * h
            outcome["miss_distance_m"] = miss
            outcome["closure_speed_m_s"] = vc
            outcome["contact_time_s"] = t_cap
            if miss > probe.capture_radius_m:
                outcome["result"] = (f"miss: radial miss {miss:.3f} m beyond the capture radius "
                                     f"{probe.capture_radius_m:g} m")
                stop = True
            elif vc < probe.min_closure_speed_m_s:
                outcome["result"] = (f"failed latch: closure speed {vc:.3f} m/s below the minimum "
                                     f"{probe.min_closure_speed_m_s:g} m/s")
                stop = True
            elif vc > probe.max_closure_speed_m_s:
                outcome["result"] = (f"failed latch: closure speed {vc:.3f} m/s above the maximum "
                                     f"{probe.max_closure_speed_m_s:g} m/s")
                stop = True
            else:
                outcome["result"] = "captured"
                ep[EK.EP_COUPLED] = 1.0
                ep[EK.EP_T_CAP] = t_cap
                ep[EK.EP_S_CAP] = ep[EK.EP_VC] * t_cap
            events.append({"kind": "contact", "t_s": t_cap, "miss_distance_m": miss, "closure_speed_m_s": vc,
                           "result": outcome["result"]})
            continue

    return _assemble(params, segments, events, outcome, model, drogue_eq, energy,
                     status == K.OK, message, delta_total, t_set, reel, probe)


def _assemble(params, segments, events, outcome, model, drogue_eq, energy, completed, message,
              delta_total, t_set, reel, probe) -> EngagementResult:
    cols = {k: [] for k in ("t", "L", "Ld", "T0", "Td", "fp", "pp", "cp", "slack", "rd", "vd", "tow", "tau",
                            "miss", "dplane", "vclose", "links", "mass", "E")}
    joints_all, jvel_all = [], []
    for chain, ep, ts, zs in segments:
        n = chain.n
        joints, jvel, scal, tow, tdrog = _outputs(ts, zs, chain, model, ep)
        cols["t"].append(ts)
        cols["L"].append(zs[:, 4 * n + EK.Z_L])
        cols["Ld"].append(zs[:, 4 * n + EK.Z_LD])
        cols["T0"].append(scal[:, EK.O_T0])
        cols["Td"].append(tdrog)
        cols["fp"].append(scal[:, [EK.O_FPX, EK.O_FPY, EK.O_FPZ]])
        pp = scal[:, [EK.O_PX, EK.O_PY, EK.O_PZ]]
        cols["pp"].append(pp)
        cols["cp"].append(np.full(ts.size, ep[EK.EP_COUPLED] != 0.0))
        cols["slack"].append(scal[:, EK.O_SLACK])
        cols["rd"].append(joints[:, -1, :])
        cols["vd"].append(jvel[:, -1, :])
        cols["tow"].append(tow)
        cols["tau"].append(scal[:, EK.O_TAU])
        e_last = joints[:, -1, :] - joints[:, -2, :]
        e_last /= np.linalg.norm(e_last, axis=1)[:, None]
        rel = pp - joints[:, -1, :]
        dpl = np.einsum("ij,ij->i", rel, e_last)
        cols["dplane"].append(dpl)
        cols["miss"].append(np.linalg.norm(rel - dpl[:, None] * e_last, axis=1))
        vp = scal[:, [EK.O_VPX, EK.O_VPY, EK.O_VPZ]]
        cols["vclose"].append(-np.einsum("ij,ij->i", vp - jvel[:, -1, :], e_last))
        cols["links"].append(np.full(ts.size, n))
        masses = []
        lw, Mw, Jw = chain.l.copy(), chain.M.copy(), chain.J.copy()
        for z in zs:
            EK.set_variable_link(z[4 * n + EK.Z_L], n, lw, Mw, Jw, ep)
            masses.append(hose_mass_in_air(Chain(lw, Mw, Jw, chain.l_nom, chain.chart), params))
        cols["mass"].append(np.array(masses))
        if energy:
            en = _energies(zs, chain, model, ep)
            cols["E"].append(np.column_stack([en, zs[:, 4 * n + EK.Z_WM:4 * n + EK.Z_WP + 1]]))
        joints_all.extend(list(joints))
        jvel_all.extend(list(jvel))
    cat = {k: np.concatenate(v) for k, v in cols.items() if v}
    en_dict = {}
    if energy:
        E = cat["E"]
        for i, name in enumerate(("kinetic", "elastic", "reel", "motor", "friction", "exit", "flux", "probe")):
            en_dict[name] = E[:, i]
    coupled = cat["cp"]
    fp = cat["fp"]
    drogue = cat["rd"]
    excursion = np.linalg.norm(drogue - drogue_eq, axis=1)
    outcome.update({
        "peak_probe_load_n": float(np.max(np.linalg.norm(fp, axis=1))),
        "peak_exit_tension_n": float(np.max(cat["T0"])),
        "min_exit_tension_n": float(np.min(cat["T0"])),
        "peak_drogue_tension_n": float(np.max(cat["Td"])),
        "peak_slack_m": float(np.max(cat["slack"])),
        "peak_drogue_excursion_m": float(np.max(excursion)),
        "hose_length_start_m": float(cat["L"][0]),
        "hose_length_end_m": float(cat["L"][-1]),
        "hose_length_min_m": float(np.min(cat["L"])),
        "length_taken_up_m": float(cat["L"][0] - np.min(cat["L"])),
        "length_lost_at_merges_m": float(delta_total),
        "tension_set_n": float(t_set),
        "remesh_events": sum(1 for e in events if e["kind"] in ("split", "merge")),
    })
    if reel.law == "locked":
        outcome["tension_set_n"] = None
    from .spec import plain

    meta = {"reel": plain(reel), "probe": plain(probe) if probe is not None else None,
            "lumping": params.hose.mass_lumping,
            "events": events}
    return EngagementResult(
        t_s=cat["t"], hose_length_m=cat["L"], reel_speed_m_s=-cat["Ld"], exit_tension_n=cat["T0"],
        drogue_tension_n=cat["Td"], probe_force_n=fp, probe_position_m=cat["pp"], coupled=coupled,
        slack_m=cat["slack"], drogue_position_m=drogue, drogue_velocity_m_s=cat["vd"], tow_force_n=cat["tow"],
        motor_torque_n_m=cat["tau"], miss_distance_series_m=cat["miss"], plane_distance_m=cat["dplane"],
        closure_speed_series_m_s=cat["vclose"],
        links=cat["links"], hose_mass_kg=cat["mass"], joints_m=joints_all, joint_velocities_m_s=jvel_all,
        energy=en_dict, events=events, outcome=outcome, equilibrium_m=np.asarray(drogue_eq, dtype=float).copy(),
        completed=completed, message=message, meta=meta)
