"""The engagement's evaluations (numba): the accelerations, L'' and the outputs of a state of the
rigid chain (:func:`eng_evaluate`: two articulated-body solves, :mod:`hosedrogue.model.engagement`)
and of the elastic chain (:func:`eng_evaluate_elastic`: one, the reel eliminated into the exit
link's joint block in an implicit stage), an actuated drogue's surfaces in them, and dz/dt of
the whole state (the hose, the tail, the pilot's or receiver's, the controller's and the
actuator's states).
"""

from __future__ import annotations

import math

from numba import njit

from ...jit import JIT, JIT_INLINE, JIT_NO_ALLOC, JIT_NO_ALLOC_INLINE
from .. import drogue_actuator as DA
from ..chain_dynamics import (
    WS_A, WS_B, WS_C, WS_CS, WS_DINV, WS_DRAG, WS_E, WS_ENV, WS_F, WS_MOM, WS_QDD, WS_R, WS_RHS, WS_TAU, WS_TOW,
    WS_U, WS_V, chain_forward_dynamics, exit_tension,
)
from ..chain_loads import joint_forces, joint_forces_stretched, joint_kinematics, link_frames, rotational_terms
from ..elastic import (
    EWS_ANG_AUG, EWS_AUG, EWS_DINV, EWS_EPSD, EWS_LAMDD, EWS_RHS, EWS_T, EWS_TAUL, EWS_U, add_axial_rates,
    angle_stiff_terms, axial_tensions, elastic_exit_tension, elastic_forward_dynamics, hose_rates, stiff_terms,
)
from ..frame import frame_loads
from ..integrate import actuator_rates, applied_force_at, control_law, controller_rates
from ..layout import (
    EP_COUPLED, EP_CR, EP_CTRL, EP_JR, EP_LAW, EP_MU, EP_NPIL, EP_PIL, EP_RCV, EP_RD, EP_REEL_SLOT, EP_SPLIT,
    EP_TAU_MAX, LAW_COMMANDED, LAW_LOCKED, O_CY, O_CZ, O_EY, O_EZ, O_LDD, O_MY, O_MZ, O_PAXIAL, O_PEXIT, O_PFLUX,
    O_PFRIC, O_PMOTOR, O_PPROBE, O_Q, O_SERVO, O_UY, O_UZ, PS_G, PS_RHO, Z_L, Z_LD, Z_TAIL, Z_WAX, Z_WF, Z_WFLUX,
    Z_WM, Z_WP, Z_WX,
)
from .chain import apply_charts, exit_material_velocity, patch_kinematics, rotate_rows, set_variable_link
from .pilot import pilot_rates, receiver_rates
from .probe import air_with_bow_wave, probe_force, probe_tip
from .reel import commanded_reel, motor_torque, reel_outputs, schedule_acceleration


#: The kinds of loops a compiled derivative holds (:func:`loop_kind`): none beside the reel's, a
#: pilot or receiver flying the probe, or the drogue controller (with or without either). The
#: evaluations and outputs need only two variants, with the drogue controller or without it
#: (a pilot's or receiver's states enter the derivative only).
NO_LOOPS, STEERED, CONTROLLED = 0, 1, 2

def _evaluate(looped):
    """:func:`eng_evaluate` compiled with the drogue controller (``looped``) or without it
    (:func:`loop_kind` below :data:`CONTROLLED`: a constant, whose false branches numba prunes
    before typing)."""

    @njit(**JIT_NO_ALLOC)
    def eng_evaluate(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out):
        """Accelerations (ws[WS_QDD] holds qdd, out[O_LDD] holds L'') and the outputs of state z; chart
        (n,) selects each link's angle chart (:func:`~.chain.apply_charts`); ``loop`` the drogue controller's
        :class:`~hosedrogue.model.integrate.LoopArrays` (used if ``ep[EP_CTRL]``; its force acts at
        the drogue as in the fixed-length model until the probe couples, then it is off; not
        compiled into :data:`eng_evaluate_bare`)."""
        L = z[4 * n + Z_L]
        Ld = z[4 * n + Z_LD]
        set_variable_link(L, n, l, M, J, ep)
        q = z[: 2 * n]
        qd = z[2 * n: 4 * n]
        e, a, b, cs, r, v, c, F, Mom, tau = (ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS], ws[WS_R], ws[WS_V], ws[WS_C],
                                             ws[WS_F], ws[WS_MOM], ws[WS_TAU])
        link_frames(q, n, e, a, b, cs)
        charted = apply_charts(n, chart, e, a, b)  # whether any link is in the other chart
        joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, c)
        if charted:  # joint_kinematics writes l d2e/dt2 in the standard chart
            rotate_rows(n, chart, c, False)
        patch_kinematics(Ld, n, e, a, b, qd, v, c)
        # the probe, and its forebody's bow wave in the air the drag (and a steering drogue) sees
        px, py, pz, vpx, vpy, vpz = probe_tip(t, z, n, ep)
        air_with_bow_wave(t, env, gust, ep, px, py, pz, ws[WS_ENV])
        u0 = ws2[WS_DRAG][:2]  # the control force at the drogue (ws2[WS_DRAG] is free: the unit-L'' solve has no drag)
        u0[0] = 0.0
        u0[1] = 0.0
        m0 = m1 = c0 = c1 = 0.0
        actuated = False  # numba prunes a branch on the constant looped, not on a variable set from it
        if looped and ep[EP_CTRL] != 0.0:
            actuated = DA.is_actuated(loop.act)
        ddx = ddy = ddz = 0.0
        if looped and actuated:
            ddx, ddy, ddz = drogue_surfaces(t, z, n, r, v, ps, ws[WS_ENV], gust, ep, loop, u0, out)
            m0, m1, c0, c1 = out[O_MY], out[O_MZ], out[O_CY], out[O_CZ]
        elif looped and ep[EP_CTRL] != 0.0 and ep[EP_COUPLED] == 0.0:
            nx = 4 * n + Z_TAIL + int(ep[EP_NPIL])
            m0, m1, c0, c1 = applied_force_at(t, z, nx, r[n, 1], r[n, 2], loop.Cc, loop.Dc, loop.y_ref, loop.act,
                                              loop.noise, loop.noise_dt, u0)
        out[O_UY] = u0[0]
        out[O_UZ] = u0[1]
        out[O_MY] = m0
        out[O_MZ] = m1
        out[O_CY] = c0
        out[O_CZ] = c1
        joint_forces(t, u0, l, M, ps, ws[WS_ENV], gust, n, e, r, v, F, Mom, ws[WS_DRAG])
        if looped and actuated:
            DA.add_drogue_load(F, ws[WS_DRAG], n, ddx, ddy, ddz)
        # the tanker's motion (nothing in level flight); the exit's share of the hose mass, carried by
        # the tanker, feels its acceleration too (its weight is added with the tow force)
        frame_loads(ps[PS_G], 0.5 * ep[EP_MU] * l[0] if ep[EP_SPLIT] != 0.0 else 0.0, l, M, J, n, e, r, v,
                    ws[WS_ENV], F, Mom)
        fx = fy = fz = 0.0
        if ep[EP_COUPLED] != 0.0:
            fx, fy, fz = probe_force(ep, n, r, v, px, py, pz, vpx, vpy, vpz)
            F[n, 0] += fx
            F[n, 1] += fy
            F[n, 2] += fz
        if charted:  # moments into each link's chart axes
            rotate_rows(n, chart, Mom, True)
        rotational_terms(qd, J, n, cs, Mom, tau)
        qdd = ws[WS_QDD]
        chain_forward_dynamics(l, M, J, n, a, b, cs, c, F, tau, ws[WS_U], ws[WS_DINV], ws[WS_RHS], qdd, ws[WS_TOW])
        # response to a unit L'': d'Alembert force -M_k e_0 on joints 1..n, nothing else
        F2, c2, tau2, qdde = ws2[WS_F], ws2[WS_C], ws2[WS_TAU], ws2[WS_QDD]
        for i in range(3):
            F2[0, i] = 0.0
        for k in range(n):
            for i in range(3):
                F2[k + 1, i] = -M[k] * e[0, i]
                c2[k, i] = 0.0
            tau2[k, 0] = 0.0
            tau2[k, 1] = 0.0
        chain_forward_dynamics(l, M, J, n, a, b, cs, c2, F2, tau2, ws2[WS_U], ws2[WS_DINV], ws2[WS_RHS], qdde,
                               ws2[WS_TOW])
        # exit tension at L'' = 0 and the effective mass the hose adds to the reel
        T00 = exit_tension(l, ps, e, F, ws[WS_TOW], n)
        me = 0.0
        for i in range(3):
            me -= ws2[WS_TOW][i] * e[0, i]
        slack = L - math.sqrt(r[n, 0] ** 2 + r[n, 1] ** 2 + r[n, 2] ** 2)
        law = ep[EP_LAW]
        rd = ep[EP_RD]
        taum = 0.0
        if law == LAW_LOCKED:
            Ldd = schedule_acceleration(t, ep)
            pm = 0.0
            pf = 0.0
        else:
            if law == LAW_COMMANDED:
                taum, Ldd = commanded_reel(T00, me, Ld, z, n, ep)
            else:
                taum = motor_torque(Ld, slack, ep)
                mr = ep[EP_JR] / (rd * rd)
                Ldd = (T00 - taum / rd - ep[EP_CR] * Ld / (rd * rd)) / (mr + me)
            pm = -taum * Ld / rd  # tau_m omega, omega = -L'/r_d
            pf = ep[EP_CR] * Ld * Ld / (rd * rd)
        T0 = T00 - me * Ldd
        for i in range(2 * n):
            qdd[i] += Ldd * qdde[i]
        reel_outputs(Ld, n, l, ep, dM, v, cs, qd, T0, Ldd, taum, slack, px, py, pz, fx, fy, fz, vpx, vpy, vpz, pm, pf,
                     out)

    return eng_evaluate


#: :func:`_evaluate`'s rigid evaluation with and without the drogue controller (:func:`loop_kind`).
eng_evaluate, eng_evaluate_bare = _evaluate(True), _evaluate(False)


@njit(**JIT)
def drogue_surfaces(t, z, n, r, v, ps, env, gust, ep, loop, u, out):
    """An actuated drogue in the engagement (:func:`hosedrogue.model.drogue_actuator.drogue_actuator_law`,
    the fixed-length loop's law): the command until the probe couples (then zero: the surfaces
    go back to neutral and their force, from their deflections, keeps acting), the surfaces'
    force into u, q, the anti-windup error, the measured offsets, the command and the servo
    derivatives into ``out``. Returns the drag increment [N] on the drogue."""
    nx = 4 * n + Z_TAIL + int(ep[EP_NPIL])
    na = nx + loop.Ac.shape[0]
    on = ep[EP_COUPLED] == 0.0
    m0 = m1 = c0 = c1 = 0.0
    if on:
        m0, m1 = control_law(t, z, nx, r[n, 1], r[n, 2], loop.Cc, loop.Dc, loop.y_ref, loop.act, loop.noise,
                             loop.noise_dt, u)
        c0, c1 = u[0], u[1]
    q, e0, e1, ddx, ddy, ddz = DA.drogue_actuator_law(on, m0, m1, c0, c1, z, nx, na, r[n, 0], r[n, 1], r[n, 2],
                                                      v[n, 0], v[n, 1], v[n, 2], ps[PS_RHO], t, env, gust, loop.Cc,
                                                      loop.Dc, loop.act, u, out, O_SERVO)
    out[O_MY] = m0
    out[O_MZ] = m1
    out[O_CY] = c0
    out[O_CZ] = c1
    out[O_Q] = q
    out[O_EY] = e0
    out[O_EZ] = e1
    return ddx, ddy, ddz


@njit(**JIT_INLINE)
def eng_deriv(loops, t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, dz):
    """dz/dt of the engagement state z of rigid links for the loops ``loops`` (:func:`loop_kind`;
    ``hist``: the drogue history the pilot's delay reads). Inlined into its callers (the steps),
    where ``loops`` is a constant: numba prunes the other kinds' code before typing (a compiled
    function of its own would generate the machine code of the whole evaluation below it once
    more: docs/develop.md, "The compiled core", fifth round)."""
    if loops == CONTROLLED:
        eng_evaluate(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
    else:
        eng_evaluate_bare(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
    qdd = ws[WS_QDD]
    for i in range(2 * n):
        dz[i] = z[2 * n + i]
        dz[2 * n + i] = qdd[i]
    b = 4 * n
    tail_rates(z, b, out, dz)
    dz[b + Z_WAX] = 0.0
    loops_rates(loops, t, z, n, b, ep, loop, hist, out, dz)


@njit(**JIT_NO_ALLOC)
def tail_rates(z, b, out, dz):
    """dz/dt of L, L' and the work states (the tail starting at b) from the outputs ``out``."""
    dz[b + Z_L] = z[b + Z_LD]
    dz[b + Z_LD] = out[O_LDD]
    dz[b + Z_WM] = out[O_PMOTOR]
    dz[b + Z_WF] = out[O_PFRIC]
    dz[b + Z_WX] = out[O_PEXIT]
    dz[b + Z_WFLUX] = out[O_PFLUX]
    dz[b + Z_WP] = out[O_PPROBE]


@njit(**JIT_NO_ALLOC_INLINE)
def reel_slot_rate(b, ep, dz):
    """dz/dt of the held take-up speed command of a commanded reel (zero), the one state after
    the tail at b that a run without loops (:data:`NO_LOOPS`) has."""
    if ep[EP_REEL_SLOT] != 0.0:
        dz[b + Z_TAIL + int(ep[EP_REEL_SLOT]) - 1] = 0.0  # the held take-up speed command


@njit(**JIT)
def steer_rates(t, z, n, b, ep, hist, dz):
    """dz/dt of the pilot's or receiver's and the commanded reel's states (after the tail at b):
    the loops of a run without the drogue controller (:data:`STEERED`). A function of its own,
    as :func:`loop_rates` is: the steps inline their derivative at each stage."""
    if ep[EP_PIL] != 0.0:
        pilot_rates(t, z, n, ep, hist, dz)
    elif ep[EP_RCV] != 0.0:
        receiver_rates(t, z, n, ep, dz)
    reel_slot_rate(b, ep, dz)


@njit(**JIT)
def loop_rates(t, z, n, b, ep, loop, hist, out, dz):
    """dz/dt of the pilot's or receiver's, the commanded reel's (:func:`steer_rates`), the
    controller's and the actuator's states (after the tail at b)."""
    npil = int(ep[EP_NPIL])
    steer_rates(t, z, n, b, ep, hist, dz)
    if ep[EP_CTRL] != 0.0:
        nx = b + Z_TAIL + npil
        if DA.is_actuated(loop.act):
            nc = loop.Ac.shape[0]
            if ep[EP_COUPLED] == 0.0:
                controller_rates(out[O_MY], out[O_MZ], z, nx, loop.Ac, loop.Bc, dz)
                DA.windup_rates(out[O_EY], out[O_EZ], nx, nc, loop.act, dz)
            else:  # coupled: the controller's states are frozen, the surfaces return to neutral
                for i in range(nx, nx + nc):
                    dz[i] = 0.0
            for i in range(DA.servo_state_count(loop.act)):
                dz[nx + nc + i] = out[O_SERVO + i]
        elif ep[EP_COUPLED] == 0.0:
            actuator_rates(out[O_CY], out[O_CZ], z, nx + loop.Ac.shape[0], loop.act, dz)
            controller_rates(out[O_MY], out[O_MZ], z, nx, loop.Ac, loop.Bc, dz)
        else:  # coupled: the controller (and actuator) states are frozen
            for i in range(nx, z.shape[0]):
                dz[i] = 0.0


@njit(**JIT_NO_ALLOC_INLINE)
def loops_rates(loops, t, z, n, b, ep, loop, hist, out, dz):
    """dz/dt of the states after the tail at b for the loops ``loops`` (:func:`loop_kind`): every
    loop's (:func:`loop_rates`), a pilot's or receiver's (:func:`steer_rates`) or the one state of
    a run without loops (:func:`reel_slot_rate`); ``loops`` a constant of the caller it is inlined
    into."""
    if loops == CONTROLLED:
        loop_rates(t, z, n, b, ep, loop, hist, out, dz)
    elif loops == STEERED:
        steer_rates(t, z, n, b, ep, hist, dz)
    else:
        reel_slot_rate(b, ep, dz)


def _evaluate_elastic(looped):
    """:func:`eng_evaluate_elastic` compiled with the drogue controller (``looped``) or without it
    (:func:`loop_kind`)."""

    @njit(**JIT_NO_ALLOC)
    def eng_evaluate_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ews, dM, out, hg, guess):
        """:func:`eng_evaluate` of the elastic chain (docs/model.md §11): z = [q, qd, lam, lamd, tail,
        ...]. Joints 1..n are material points, so L moves no joint: the exit link's strain
        ``lam_0 / l_0 - 1`` (l_0 from L) carries the reel's pull, the hose's force on L is
        :func:`~hosedrogue.model.elastic.elastic_exit_tension` and the reel equation gives L''
        explicitly - one O(n) solve (:func:`~hosedrogue.model.elastic.elastic_forward_dynamics`; qdd in
        ws[WS_QDD], the length accelerations in ews[EWS_LAMDD], the tensions in ews[EWS_T]). ``hg`` and
        ``guess`` (the stage's slope guess, len(z)): an implicit stage's
        (:func:`~hosedrogue.model.elastic.stiff_terms`; hg = 0 for the true derivative, guess then
        unused). In a stage the exit link's spring-damper is implicit in its length and in L together:
        the reel's equation is eliminated into the exit link's joint block (its augmentation in series
        with the reel's mass), so a stiff hose on a free reel costs no extra solve."""
        nh = 6 * n
        L = z[nh + Z_L]
        Ld = z[nh + Z_LD]
        set_variable_link(L, n, l, M, J, ep)
        q = z[: 2 * n]
        qd = z[2 * n: 4 * n]
        lam = z[4 * n: 5 * n]
        lamd = z[5 * n: 6 * n]
        e, a, b, cs, r, v, c, F, Mom, tau = (ws[WS_E], ws[WS_A], ws[WS_B], ws[WS_CS], ws[WS_R], ws[WS_V], ws[WS_C],
                                             ws[WS_F], ws[WS_MOM], ws[WS_TAU])
        link_frames(q, n, e, a, b, cs)
        charted = apply_charts(n, chart, e, a, b)  # whether any link is in the other chart
        joint_kinematics(q, qd, lam, n, e, a, b, cs, r, v, c)
        if charted:  # joint_kinematics writes lam d2e/dt2 in the standard chart
            rotate_rows(n, chart, c, False)
        add_axial_rates(n, e, a, b, qd, lamd, v, c)
        exit_material_velocity(Ld, lam, l, e, v)
        u0 = ws[WS_RHS][0]  # the control force at the drogue (ws[WS_RHS] is the rigid recursion's scratch)
        u0[0] = 0.0
        u0[1] = 0.0
        m0 = m1 = c0 = c1 = 0.0
        if looped and ep[EP_CTRL] != 0.0 and ep[EP_COUPLED] == 0.0:
            nx = nh + Z_TAIL + int(ep[EP_NPIL])
            m0, m1, c0, c1 = applied_force_at(t, z, nx, r[n, 1], r[n, 2], loop.Cc, loop.Dc, loop.y_ref, loop.act,
                                              loop.noise, loop.noise_dt, u0)
        out[O_UY] = u0[0]
        out[O_UZ] = u0[1]
        out[O_MY] = m0
        out[O_MZ] = m1
        out[O_CY] = c0
        out[O_CZ] = c1
        px, py, pz, vpx, vpy, vpz = probe_tip(t, z, n, ep)
        air_with_bow_wave(t, env, gust, ep, px, py, pz, ws[WS_ENV])
        joint_forces_stretched(t, u0, l, lam, M, ps, ws[WS_ENV], gust, n, e, r, v, F, Mom, ws[WS_DRAG])
        # the tanker's motion (as the rigid chain's; the links' rates from their actual lengths)
        frame_loads(ps[PS_G], 0.5 * ep[EP_MU] * l[0] if ep[EP_SPLIT] != 0.0 else 0.0, lam, M, J, n, e, r, v,
                    ws[WS_ENV], F, Mom)
        fx = fy = fz = 0.0
        if ep[EP_COUPLED] != 0.0:
            fx, fy, fz = probe_force(ep, n, r, v, px, py, pz, vpx, vpy, vpz)
            F[n, 0] += fx
            F[n, 1] += fy
            F[n, 2] += fz
        if charted:  # moments into each link's chart axes
            rotate_rows(n, chart, Mom, True)
        rotational_terms(qd, J, n, cs, Mom, tau)
        T, epsd, aug, taul = ews[EWS_T], ews[EWS_EPSD], ews[EWS_AUG], ews[EWS_TAUL]
        p_axial = axial_tensions(n, l, lam, lamd, Ld, ps, T, epsd)
        stiff_terms(n, l, hg, ps, guess[5 * n: 6 * n], T, aug, taul)
        angle_stiff_terms(n, l, lam, hg, ps, cs, T, guess[2 * n: 4 * n], tau, ews[EWS_ANG_AUG])
        T0 = elastic_exit_tension(n, l, lam, ps, e, epsd)
        chord = math.sqrt(r[n, 0] ** 2 + r[n, 1] ** 2 + r[n, 2] ** 2)
        arc = 0.0
        for k in range(n):
            arc += lam[k]
        slack = arc - chord  # the stretched hose's length minus the straight exit-to-drogue distance
        law = ep[EP_LAW]
        rd = ep[EP_RD]
        taum = 0.0
        pm = 0.0
        pf = 0.0
        Ldd = 0.0
        rest = 0.0
        mr = 1.0
        prescribed = law == LAW_LOCKED
        if law == LAW_LOCKED:
            Ldd = schedule_acceleration(t, ep)
        else:
            mr = ep[EP_JR] / (rd * rd)
            if law == LAW_COMMANDED:
                # the drive gives the acceleration asked for unless at its torque limit (no hose mass is
                # dragged along: L moves no joint)
                taum, Ldd = commanded_reel(T0, 0.0, Ld, z, n, ep)
                prescribed = abs(taum) < ep[EP_TAU_MAX]
            else:
                taum = motor_torque(Ld, slack, ep)
            rest = -taum / rd - ep[EP_CR] * Ld / (rd * rd)  # the motor's and the friction's force on L
            pm = -taum * Ld / rd
            pf = ep[EP_CR] * Ld * Ld / (rd * rd)
        d0 = aug[0]
        aLg = guess[nh + Z_LD]
        s_r = 0.0
        if hg != 0.0:
            # the exit link's spring-damper couples its length to L: implicit in both (docs/model.md §11)
            if prescribed:
                taul[0] += d0 * (Ldd - aLg)
            else:
                s_r = d0 / (mr + d0)
                taul[0] = -T[0] + (1.0 - s_r) * d0 * guess[5 * n] + s_r * (T0 + rest - mr * aLg)
                aug[0] = (1.0 - s_r) * d0
        elastic_forward_dynamics(lam, M, J, n, a, b, e, cs, c, F, tau, taul, aug, ews[EWS_U], ews[EWS_DINV],
                                 ews[EWS_RHS], ws[WS_QDD], ews[EWS_LAMDD], ws[WS_TOW], ews[EWS_ANG_AUG])
        if not prescribed:
            if hg != 0.0:
                Ldd = (T0 + d0 * (ews[EWS_LAMDD][0] - guess[5 * n] + aLg) + rest) / (mr + d0)
            else:
                Ldd = (T0 + rest) / mr
        reel_outputs(Ld, n, l, ep, dM, v, cs, qd, T0, Ldd, taum, slack, px, py, pz, fx, fy, fz, vpx, vpy, vpz, pm, pf,
                     out)
        out[O_PAXIAL] = p_axial

    return eng_evaluate_elastic


#: :func:`_evaluate_elastic`'s evaluation with and without the drogue controller (:func:`loop_kind`).
eng_evaluate_elastic, eng_evaluate_elastic_bare = _evaluate_elastic(True), _evaluate_elastic(False)


@njit(**JIT_NO_ALLOC_INLINE)
def eng_deriv_elastic(loops, t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, hg, guess, dz):
    """:func:`eng_deriv` of the elastic chain (``hg``, ``guess`` (len(z)): see
    :func:`eng_evaluate_elastic`), inlined into the steps as the rigid one is: since the SDIRK's
    stages are one loop it is called at one place per step (in the fifth round, at more places,
    inlining made a cold elastic run slower; docs/develop.md, "The compiled core", seventh round)."""
    if loops == CONTROLLED:
        eng_evaluate_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ews, dM, out, hg, guess)
    else:
        eng_evaluate_elastic_bare(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ews, dM, out, hg, guess)
    hose_rates(z, n, ws, ews, dz)
    b = 6 * n
    tail_rates(z, b, out, dz)
    dz[b + Z_WAX] = out[O_PAXIAL]
    loops_rates(loops, t, z, n, b, ep, loop, hist, out, dz)


def loop_kind(ep) -> int:
    """The loops beside the reel's that the engagement of parameters ``ep`` runs, as its compiled
    derivatives, steps and outputs are specialized for them (numba prunes the other kinds'
    code before typing: a run compiles only what its loops need; docs/develop.md, "The compiled
    core"): :data:`CONTROLLED` with a drogue controller (``ep[EP_CTRL]``; a pilot or receiver
    may fly too), :data:`STEERED` with a pilot (``ep[EP_PIL]``) or receiver (``ep[EP_RCV]``)
    only, else :data:`NO_LOOPS`. The Python pickers call this at every call.

    Parameters
    ----------
    ep : numpy.ndarray
        The engagement's parameters (``hosedrogue.model.layout.EP_*``).

    Returns
    -------
    int
        :data:`NO_LOOPS`, :data:`STEERED` or :data:`CONTROLLED`.
    """
    if ep[EP_CTRL] != 0.0:
        return CONTROLLED
    return STEERED if ep[EP_PIL] != 0.0 or ep[EP_RCV] != 0.0 else NO_LOOPS
