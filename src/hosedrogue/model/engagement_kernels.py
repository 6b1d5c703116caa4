"""Compiled core of the engagement (numba): a hose of varying free length on a reel, and the probe.

The chain is the one of :mod:`hosedrogue.model.kernels` with one change: link 0 (the exit link,
from the hose exit to joint 1) has the variable length ``l_0 = L - sum_{k>=1} l_k``, L the free
hose length, a generalized coordinate of its own (docs/model.md, "Hose of varying length").
Joints 1..n are material points of the hose. Every joint's velocity gains ``L' e_0`` and every
joint's acceleration ``L'' e_0 + 2 L' de_0/dt``. The existing kernels are reused unchanged:

* :func:`~hosedrogue.model.kernels.joint_kinematics` gives positions, velocities and the
  velocity-product accelerations of the fixed-length chain; :func:`patch_kinematics` adds the
  ``L' e_0`` velocity (also to joint 0: the hose material leaves the exit at ``L' e_0``, which the
  exit link's drag sees) and the Coriolis-like ``2 L' de_0/dt`` term;
* the term ``L'' e_0`` is the same for every joint 1..n, so it acts on the chain like an
  acceleration of its root. The dynamics are linear in it: one articulated-body solve
  (:func:`~hosedrogue.model.kernels.chain_forward_dynamics`) with the real loads gives qdd and the
  hose's pull ``P_0`` at L'' = 0; a second with only the d'Alembert forces ``-M_k e_0`` gives the
  response per unit L''. The exit tension ``T_0 = P . e_0`` is the generalized force of the hose
  on L; the reel equation closes the system for L''. Still O(n).

State ``z = [q (2n), qd (2n), L, L', W_motor, W_friction, W_exit, W_flux, W_probe]``: the five
last entries integrate powers for the energy balance (work of the motor on the drum, heat of the
drum's friction, work of the exit on the hose, kinetic energy carried by hose joining or leaving
the moving masses, work of the probe on the drogue; the tail's slots ``Z_*``, and the ``EP_*`` of
``ep``, the engagement scalars, are declared in :mod:`hosedrogue.model.layout`); ``ws`` is
:func:`~hosedrogue.model.kernels.make_workspace` of n links and ``ws2`` a second one for the
unit-L'' solve.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .kernels import (
    PS_RHO,
    ENV_BW,
    ENV_BW_LEN,
    ENV_BW_Q,
    ENV_BW_X,
    ENV_BW_Y,
    ENV_BW_Z,
    PS_G,
    fill_env,
    exit_tension,
    JIT,
    OK,
    chain_energy,
    chain_forward_dynamics,
    joint_forces,
    joint_forces_stretched,
    joint_kinematics,
    link_frames,
    make_workspace_jit,
    rotational_terms,
)
from .elastic import (add_axial_rates, axial_tensions, elastic_exit_tension, elastic_forward_dynamics,
                      make_elastic_workspace_jit, stiff_terms, strain_energy, angle_stiff_terms)
from .implicit import (SDIRK2_GAMMA, SDIRK_MAX_CORRECTIONS, SDIRK_MAX_SUBSTEPS, SDIRK_TOLERANCE_M_S, after_stage1,
                       correction_size, stage_point)
from .integrate import (actuator_rates, applied_force_at, control_law, controller_rates, rk4_combine, rk4_stage,
                        step_status)
from . import drogue_actuator as DA
from .frame import frame_loads
from .sampled import (C_ORIGIN, C_SAMPLE, C_SAVED, C_STATUS, C_STEP, C_TARGET, R_COUPLED, R_Q, R_DROGUE, R_DROGUE_V, R_L, R_PROBE, R_PROBE_V,
                      R_REEL_V, R_T0, deliver)
from .layout import (  # the ep, state tail, pilot, receiver and out tables, their codes and the status codes,
    # declared and documented there
    BW_LINE, BW_OFF, BW_RANKINE, CHART, EP_BW, EP_BW_DX, EP_BW_DY, EP_BW_DZ, EP_BW_LEN, EP_BW_Q, EP_COUPLED, EP_CP,
    EP_CR, EP_CTRL, EP_DB, EP_ELASTIC, EP_FEED, EP_FEED_A, EP_FEED_J, EP_FEED_P, EP_FEED_T0, EP_FEED_V, EP_H,
    EP_ITER, EP_JD, EP_JLINK, EP_JR, EP_KP, EP_KS, EP_KV, EP_K_GOV, EP_L0, EP_LAW, EP_L_MAX, EP_L_MIN, EP_MD, EP_MU,
    EP_NPIL, EP_P0X, EP_P0Y, EP_P0Z, EP_PAY_A, EP_PAY_DIST, EP_PAY_T0, EP_PAY_V, EP_PIL, EP_PIL_AMAX, EP_PIL_DELAY,
    EP_PIL_LAG, EP_PIL_TV, EP_PIL_VMAX, EP_PROBE, EP_PUSH, EP_RCV, EP_RCV_AMAX, EP_RCV_TV, EP_RCV_VMAX, EP_RD,
    EP_REEL_SLOT, EP_REEL_TV, EP_SCHEME, EP_SIZE, EP_SPLIT, EP_S_CAP, EP_TAU_MAX, EP_TSET, EP_T_CAP, EP_T_STOP,
    EP_VC, EP_V_IN_MAX, EP_V_OUT_MAX, LAW_COMMANDED, LAW_CONSTANT_TENSION, LAW_LOCKED, LAW_RESPONSE, MERGE,
    NONFINITE, O_CY, O_CZ, O_EY, O_EZ, O_FPX, O_FPY, O_FPZ, O_LDD, O_MY, O_MZ, O_PAXIAL, O_PEXIT, O_PFLUX, O_PFRIC,
    O_PMOTOR, O_PPROBE, O_PX, O_PY, O_PZ, O_Q, O_SERVO, O_SIZE, O_SLACK, O_T0, O_TAU, O_UY, O_UZ, O_VPX, O_VPY,
    O_VPZ, PIL_STATES, PIL_VY, PIL_VZ, PIL_Y, PIL_Z, PLANE, RCV_CX, RCV_STATES, RCV_VX, RCV_X, REEL_END, SCHEME_RK4,
    SCHEME_SDIRK2, SPLIT, STAGE_LIMIT, YAW_LIMIT, Z_L, Z_LD, Z_TAIL, Z_WAX, Z_WF, Z_WFLUX, Z_WM, Z_WP, Z_WX,
)


@njit(**JIT)
def tail_start(n, ep):
    """Index of the state's tail (L, L', the work states, ...): after the 4n hose entries
    ``[q, qd]``, or the 6n ``[q, qd, lam, lamd]`` of elastic links."""
    return 6 * n if ep[EP_ELASTIC] != 0.0 else 4 * n


@njit(**JIT)
def apply_charts(n, chart, e, a, b):
    """Links in the alternative chart have e = R e_std(theta), R the rotation by +90 deg about x
    ((x, y, z) -> (x, -z, y)): its singular directions are +-z instead of +-y, so a link whose yaw
    nears +-90 deg in one chart is far from singular in the other (docs/engagement.md)."""
    for k in range(n):
        if chart[k] != 0.0:
            for arr in (e, a, b):
                y = arr[k, 1]
                arr[k, 1] = -arr[k, 2]
                arr[k, 2] = y


@njit(**JIT)
def rotate_rows(n, chart, c, inverse):
    """Rotate rows of c (n,3) of the alternative-chart links by R (or R^T if inverse)."""
    for k in range(n):
        if chart[k] != 0.0:
            y = c[k, 1]
            if inverse:
                c[k, 1] = c[k, 2]
                c[k, 2] = -y
            else:
                c[k, 1] = -c[k, 2]
                c[k, 2] = y


@njit(**JIT)
def set_variable_link(L, n, l, M, J, ep):
    """Length of the exit link from L, and the masses and inertia that depend on it.

    ``split`` lumping: half of each link's mass at each end joint (the exit's half is carried by
    the tanker); ``aft``: each link's mass at its aft joint. Joint k+1's mass is M[k]; the drogue's
    mass is in M[n-1]. ``ep[EP_JLINK] < 0`` selects the rod inertia m l^2 / 12 for link 0 (the
    other links' J are set once); else every link has the fixed ``ep[EP_JLINK]``.
    """
    fixed = 0.0
    for k in range(1, n):
        fixed += l[k]
    l[0] = L - fixed
    mu = ep[EP_MU]
    if ep[EP_SPLIT] != 0.0:
        if n == 1:
            M[0] = 0.5 * mu * l[0] + ep[EP_MD]
        else:
            M[0] = 0.5 * mu * (l[0] + l[1])
    else:
        M[0] = mu * l[0] + (ep[EP_MD] if n == 1 else 0.0)
    if ep[EP_JLINK] < 0.0:
        J[0] = mu * l[0] ** 3 / 12.0 + (ep[EP_JD] if n == 1 else 0.0)


@njit(**JIT)
def mass_rates(Ld, n, l, ep, dM):
    """dM (2,): rate of change [kg/s] of joint 1's mass and, for ``split``, of the exit's share."""
    mu = ep[EP_MU]
    if ep[EP_SPLIT] != 0.0:
        dM[0] = 0.5 * mu * Ld
        dM[1] = 0.5 * mu * Ld
    else:
        dM[0] = mu * Ld
        dM[1] = 0.0


@njit(**JIT)
def patch_kinematics(Ld, n, e, a, b, qd, v, c):
    """Add the variable exit link's terms: L' e_0 to every joint's velocity (joint 0: the hose
    material at the exit) and 2 L' de_0/dt to link 0's velocity-product acceleration."""
    ex, ey, ez = e[0, 0], e[0, 1], e[0, 2]
    for k in range(n + 1):
        v[k, 0] += Ld * ex
        v[k, 1] += Ld * ey
        v[k, 2] += Ld * ez
    d1 = qd[0]
    d2 = qd[1]
    for i in range(3):
        c[0, i] += 2.0 * Ld * (a[0, i] * d1 + b[0, i] * d2)


@njit(**JIT)
def probe_state(t, ep):
    """Prescribed probe-tip position and velocity [m, m/s] in S_p at time t.

    From ``P0`` forward (+x) at the closure speed; after capture at ``t_cap`` (probe travel
    ``s_cap``) it goes on to ``s_cap + push`` and stops with a half-cosine speed ramp of
    ``t_stop`` seconds (no step in the probe's speed, so no impulse in the damper).
    """
    vc = ep[EP_VC]
    s = vc * t
    v = vc
    if ep[EP_COUPLED] != 0.0:
        t_stop = ep[EP_T_STOP]
        # cruise until the ramp starts; the ramp covers vc t_stop / 2
        cruise = ep[EP_PUSH] - 0.5 * vc * t_stop
        if cruise < 0.0:
            cruise = 0.0
        t1 = ep[EP_T_CAP] + cruise / vc
        if t > t1:
            tau = t - t1
            s1 = ep[EP_S_CAP] + cruise
            if tau >= t_stop:
                s = s1 + 0.5 * vc * t_stop
                v = 0.0
            else:
                w = math.pi / t_stop
                s = s1 + 0.5 * vc * (tau + math.sin(w * tau) / w)
                v = 0.5 * vc * (1.0 + math.cos(w * tau))
    return ep[EP_P0X] + s, ep[EP_P0Y], ep[EP_P0Z], v, 0.0, 0.0


@njit(**JIT)
def fed_axis(s, ep, i):
    """Position, velocity and acceleration [m, m/s, m/s^2] along axis i of the fed path (``EP_FEED``)
    s seconds after ``EP_FEED_T0``."""
    v0, a0, j = ep[EP_FEED_V + i], ep[EP_FEED_A + i], ep[EP_FEED_J + i]
    return (ep[EP_FEED_P + i] + s * (v0 + s * (0.5 * a0 + s * (j / 6.0))), v0 + s * (a0 + 0.5 * s * j),
            a0 + s * j)


@njit(**JIT)
def fed_tip(t, ep):
    """Position, velocity and acceleration [m, m/s, m/s^2] (tuples of 3) at time t of a probe path
    fed from outside (``EP_FEED``): the cubic from ``EP_FEED_T0`` with ``EP_FEED_P``,
    ``EP_FEED_V``, ``EP_FEED_A`` and ``EP_FEED_J``."""
    s = t - ep[EP_FEED_T0]
    px, vx, ax = fed_axis(s, ep, 0)
    py, vy, ay = fed_axis(s, ep, 1)
    pz, vz, az = fed_axis(s, ep, 2)
    return (px, py, pz), (vx, vy, vz), (ax, ay, az)


@njit(**JIT)
def probe_force(ep, n, r, v, px, py, pz, vpx, vpy, vpz):
    """The coupling's force on the drogue (joint n of r, v) [N] from the probe tip at (px, py, pz)
    moving at (vpx, vpy, vpz): the spring ``EP_KP`` [N/m] and damper ``EP_CP`` [N s/m] between them."""
    kp = ep[EP_KP]
    cp = ep[EP_CP]
    return (kp * (px - r[n, 0]) + cp * (vpx - v[n, 0]), kp * (py - r[n, 1]) + cp * (vpy - v[n, 1]),
            kp * (pz - r[n, 2]) + cp * (vpz - v[n, 2]))


@njit(**JIT)
def probe_tip(t, z, n, ep):
    """Probe-tip position and velocity [m, m/s] at time t and state z: :func:`probe_state`, whose
    lateral and vertical motion the pilot's states replace when a pilot flies the probe; the
    receiver's states when the receiver flies it; a fed path (:func:`fed_tip`) as a function of
    time, as the prescribed path, not through the states: an integrator's stages then see the tip
    where the path is at their times (the states' stage values of a curved path are off by
    O(h^2): the SDIRK's first stage puts it at p + hg v + (hg)^2 a, the path is at
    p + hg v + (hg)^2 a / 2)."""
    if ep[EP_RCV] != 0.0:
        if ep[EP_FEED] != 0.0:
            p, v, _ = fed_tip(t, ep)
            return p[0], p[1], p[2], v[0], v[1], v[2]
        b = tail_start(n, ep) + Z_TAIL
        return (z[b + RCV_X], z[b + RCV_X + 1], z[b + RCV_X + 2], z[b + RCV_VX], z[b + RCV_VX + 1],
                z[b + RCV_VX + 2])
    px, py, pz, vpx, vpy, vpz = probe_state(t, ep)
    if ep[EP_PIL] != 0.0:
        b = tail_start(n, ep) + Z_TAIL
        py = z[b + PIL_Y]
        pz = z[b + PIL_Z]
        vpy = z[b + PIL_VY]
        vpz = z[b + PIL_VZ]
    return px, py, pz, vpx, vpy, vpz


@njit(**JIT)
def delayed_drogue(tq, hist, h):
    """Drogue lateral and vertical position [m] at time tq >= 0 from the history ``hist`` (rows:
    global RK4 steps; y, z, y', z' [m, m/s]) by cubic Hermite interpolation between the steps
    (O(h^4), below the RK4 error); a row not yet written (NaN) is never used."""
    x = tq / h
    k = int(math.floor(x))
    last = hist.shape[0] - 1
    if k < 0:
        k = 0
    if k >= last:
        return hist[last, 0], hist[last, 1]
    s = x - k
    if s < 1e-9 or not math.isfinite(hist[k + 1, 0]):
        return hist[k, 0], hist[k, 1]
    s2 = s * s
    s3 = s2 * s
    h00 = 2.0 * s3 - 3.0 * s2 + 1.0
    h10 = s3 - 2.0 * s2 + s
    h01 = -2.0 * s3 + 3.0 * s2
    h11 = s3 - s2
    y = h00 * hist[k, 0] + h10 * h * hist[k, 2] + h01 * hist[k + 1, 0] + h11 * h * hist[k + 1, 2]
    zz = h00 * hist[k, 1] + h10 * h * hist[k, 3] + h01 * hist[k + 1, 1] + h11 * h * hist[k + 1, 3]
    return y, zz


@njit(**JIT)
def pilot_rates(t, z, n, ep, hist, dz):
    """dz/dt of the pilot's states (docs/engagement.md, "Pilot model"): per axis the aim is the
    drogue's position one reaction time ago (before t = 0 the start point: the pilot starts to
    chase the drogue at t = 0), the commanded speed ``(aim - p) / lag`` clipped to the speed
    bound, and the acceleration ``(v_cmd - v) / tau_v`` clipped to the acceleration bound. Once
    coupled the pilot holds station (v_cmd = 0): the drogue is on the probe."""
    b = tail_start(n, ep) + Z_TAIL
    tq = t - ep[EP_PIL_DELAY]
    if tq < 0.0:
        ay = ep[EP_P0Y]
        az = ep[EP_P0Z]
    else:
        ay, az = delayed_drogue(tq, hist, ep[EP_H])
    vmax = ep[EP_PIL_VMAX]
    amax = ep[EP_PIL_AMAX]
    for i in range(2):
        aim = ay if i == 0 else az
        p = z[b + PIL_Y + i]
        v = z[b + PIL_VY + i]
        vcmd = 0.0
        if ep[EP_COUPLED] == 0.0:
            vcmd = min(max((aim - p) / ep[EP_PIL_LAG], -vmax), vmax)
        dz[b + PIL_Y + i] = v
        dz[b + PIL_VY + i] = min(max((vcmd - v) / ep[EP_PIL_TV], -amax), amax)


@njit(**JIT)
def receiver_rates(t, z, n, ep, dz):
    """dz/dt of the receiver's states (docs/controllers.md): per axis the held velocity command,
    clipped to the speed bound, is followed through the first-order lag tau_v with the
    acceleration clipped to its bound (the pilot model's response, :func:`pilot_rates`); the
    command itself is held (zero rate). A fed path (``EP_FEED``): the tip's velocity and
    acceleration at time t on it (:func:`fed_tip`; the states follow it, the tip is the path)."""
    b = tail_start(n, ep) + Z_TAIL
    if ep[EP_FEED] != 0.0:
        _, v, a = fed_tip(t, ep)
        for i in range(3):
            dz[b + RCV_X + i] = v[i]
            dz[b + RCV_VX + i] = a[i]
            dz[b + RCV_CX + i] = 0.0
        return
    tv = ep[EP_RCV_TV]
    for i in range(3):
        vmax = ep[EP_RCV_VMAX + i]
        amax = ep[EP_RCV_AMAX + i]
        v = z[b + RCV_VX + i]
        vcmd = min(max(z[b + RCV_CX + i], -vmax), vmax)
        dz[b + RCV_X + i] = v
        dz[b + RCV_VX + i] = min(max((vcmd - v) / tv, -amax), amax)
        dz[b + RCV_CX + i] = 0.0


@njit(**JIT)
def commanded_reel(T00, me, Ld, z, n, ep):
    """Motor torque [N m] and L'' [m/s^2] of the commanded reel (LAW_COMMANDED): the held take-up
    speed command, clipped to the speed limits, is followed through a first-order lag of
    ``EP_REEL_TV``: the drive sets the torque the reel equation needs for that acceleration
    (given the hose's pull T00 at L'' = 0 and its effective mass me), clipped to the torque
    limit; with the torque at its limit L'' follows from the reel equation."""
    rd = ep[EP_RD]
    vcmd = z[tail_start(n, ep) + Z_TAIL + int(ep[EP_REEL_SLOT]) - 1]  # take-up speed, positive reeling in
    vcmd = min(max(vcmd, -ep[EP_V_OUT_MAX]), ep[EP_V_IN_MAX])
    mr = ep[EP_JR] / (rd * rd)
    fric = ep[EP_CR] * Ld / (rd * rd)
    target = (-vcmd - Ld) / ep[EP_REEL_TV]
    tau = rd * (T00 - fric - (mr + me) * target)
    tmax = ep[EP_TAU_MAX]
    if tau > tmax:
        tau = tmax
    elif tau < -tmax:
        tau = -tmax
    else:
        return tau, target  # within the torque limit the drive gives the acceleration asked for
    return tau, (T00 - tau / rd - fric) / (mr + me)


@njit(**JIT)
def chain_kinematics(z, n, l, M, J, ep, chart, ws):
    """Set the exit link's length from L and write the frames (ws[0:4]), joint positions (ws[4]),
    velocities (ws[5]) and velocity-product accelerations (ws[6]) of state z, the reel's L' terms
    included (the accelerations in the standard chart: no ``rotate_rows``). Elastic links: with
    their actual lengths and stretching rates, the exit's hose material at ``L' lam_0 / l_0``."""
    nh = tail_start(n, ep)
    set_variable_link(z[nh + Z_L], n, l, M, J, ep)
    q = z[: 2 * n]
    qd = z[2 * n: 4 * n]
    e, a, b, cs, r, v, c = ws[0], ws[1], ws[2], ws[3], ws[4], ws[5], ws[6]
    link_frames(q, n, e, a, b, cs)
    apply_charts(n, chart, e, a, b)
    if ep[EP_ELASTIC] != 0.0:
        lam = z[4 * n: 5 * n]
        joint_kinematics(q, qd, lam, n, e, a, b, cs, r, v, c)
        add_axial_rates(n, e, a, b, qd, z[5 * n: 6 * n], v, c)
        exit_material_velocity(z[nh + Z_LD], lam, l, e, v)
        return
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, c)
    patch_kinematics(z[4 * n + Z_LD], n, e, a, b, qd, v, c)


@njit(**JIT)
def exit_material_velocity(Ld, lam, l, e, v):
    """Elastic links: the hose material at the exit (joint 0's row of v) moves along the exit
    link at ``L' lam_0 / l_0`` (material paid out at L' is stretched as the exit link is)."""
    s0 = Ld * lam[0] / l[0]
    v[0, 0] = s0 * e[0, 0]
    v[0, 1] = s0 * e[0, 1]
    v[0, 2] = s0 * e[0, 2]


@njit(**JIT)
def drogue_motion(z, n, l, M, J, ep, chart, ws):
    """Drogue (joint n) y, z [m] and y', z' [m/s] of state z (kinematics only, into ws)."""
    chain_kinematics(z, n, l, M, J, ep, chart, ws)
    r, v = ws[4], ws[5]
    return r[n, 1], r[n, 2], v[n, 1], v[n, 2]


@njit(**JIT)
def schedule_acceleration(t, ep):
    """L'' [m/s^2] of the locked reel's length schedule: pays out ``pay_dist`` (negative: takes up)
    from ``pay_t0`` at up to ``pay_v``, speeding up and slowing down along half-sine acceleration
    pulses of peak ``pay_a``. The acceleration is continuous, so RK4 keeps its accuracy across
    the schedule (a step in L'' inside a step would cost O(h) in the paid-out length)."""
    d = ep[EP_PAY_DIST]
    if d == 0.0:
        return 0.0
    sgn = 1.0 if d > 0.0 else -1.0
    d = abs(d)
    vmax = ep[EP_PAY_V]
    acc = ep[EP_PAY_A]
    if math.pi * vmax * vmax / (2.0 * acc) > d:  # no cruise: a lower top speed
        vmax = math.sqrt(2.0 * acc * d / math.pi)
    ta = math.pi * vmax / (2.0 * acc)  # each ramp covers vmax ta / 2
    tc = (d - vmax * ta) / vmax
    tau = t - ep[EP_PAY_T0]
    if tau <= 0.0:
        return 0.0
    if tau < ta:
        return sgn * acc * math.sin(math.pi * tau / ta)
    if tau < ta + tc:
        return 0.0
    if tau < 2.0 * ta + tc:
        return -sgn * acc * math.sin(math.pi * (tau - ta - tc) / ta)
    return 0.0


@njit(**JIT)
def motor_torque(Ld, slack, ep):
    """Motor torque [N m] (positive reels in) of the ``constant-tension`` and ``response`` laws,
    with the speed governor and the torque limit."""
    rd = ep[EP_RD]
    vr = -Ld  # take-up speed, positive reeling in
    tau = rd * ep[EP_TSET]
    if ep[EP_LAW] == LAW_RESPONSE:
        over = slack - ep[EP_DB]
        vcmd = ep[EP_KS] * over if over > 0.0 else 0.0
        if vcmd > ep[EP_V_IN_MAX]:
            vcmd = ep[EP_V_IN_MAX]
        tau += rd * ep[EP_KV] * (vcmd - vr)
    if vr > ep[EP_V_IN_MAX]:
        tau -= rd * ep[EP_K_GOV] * (vr - ep[EP_V_IN_MAX])
    elif vr < -ep[EP_V_OUT_MAX]:
        tau += rd * ep[EP_K_GOV] * (-ep[EP_V_OUT_MAX] - vr)
    tmax = ep[EP_TAU_MAX]
    if tau > tmax:
        tau = tmax
    elif tau < -tmax:
        tau = -tmax
    return tau


@njit(**JIT)
def air_with_bow_wave(t, env, gust, ep, px, py, pz, scratch):
    """This evaluation's air (``env`` into ``scratch``, with the gust at time t when uniform:
    :func:`~hosedrogue.model.kernels.env_at`) and the bow wave of the forebody whose probe tip is
    at (px, py, pz) [m]: its source sits ``ep[EP_BW_D*]`` from the tip. The drag kernel then adds
    its velocity to the air at every drag point and at the drogue."""
    fill_env(t, env, gust, scratch)
    scratch[ENV_BW] = ep[EP_BW]
    if ep[EP_BW] != BW_OFF:
        scratch[ENV_BW_X] = px + ep[EP_BW_DX]
        scratch[ENV_BW_Y] = py + ep[EP_BW_DY]
        scratch[ENV_BW_Z] = pz + ep[EP_BW_DZ]
        scratch[ENV_BW_Q] = ep[EP_BW_Q]
        scratch[ENV_BW_LEN] = ep[EP_BW_LEN]


@njit(**JIT)
def reel_outputs(Ld, n, l, ep, dM, v, cs, qd, T0, Ldd, taum, slack, px, py, pz, fx, fy, fz, vpx, vpy, vpz, pm, pf,
                 out):
    """The evaluation's outputs of the reel, the probe and the powers into ``out`` (the ``O_*``
    slots), both chains: the exit tension T0 [N], L'' [m/s^2], the motor torque [N m], the slack
    [m], the probe tip, its force and velocity, the motor's and the friction's power and the
    exit's, and the power of the kinetic energy carried by hose joining (L' > 0) or leaving the
    moving masses (dM into ``dM``, :func:`mass_rates`) [W]."""
    mass_rates(Ld, n, l, ep, dM)
    v1 = v[1, 0] ** 2 + v[1, 1] ** 2 + v[1, 2] ** 2
    pflux = 0.5 * dM[0] * v1
    if ep[EP_JLINK] < 0.0:
        c20 = cs[0, 2]
        pflux += 0.5 * 0.25 * ep[EP_MU] * l[0] * l[0] * Ld * (c20 * c20 * qd[0] * qd[0] + qd[1] * qd[1])
    out[O_T0] = T0
    out[O_LDD] = Ldd
    out[O_TAU] = taum
    out[O_SLACK] = slack
    out[O_PX] = px
    out[O_PY] = py
    out[O_PZ] = pz
    out[O_FPX] = fx
    out[O_FPY] = fy
    out[O_FPZ] = fz
    out[O_VPX] = vpx
    out[O_VPY] = vpy
    out[O_VPZ] = vpz
    out[O_PMOTOR] = pm
    out[O_PFRIC] = pf
    out[O_PEXIT] = -Ld * T0
    out[O_PFLUX] = pflux
    out[O_PPROBE] = fx * v[n, 0] + fy * v[n, 1] + fz * v[n, 2]


@njit(**JIT)
def eng_evaluate(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out):
    """Accelerations (ws[15] holds qdd, out[O_LDD] holds L'') and the outputs of state z; chart
    (n,) selects each link's angle chart (:func:`apply_charts`); ``loop`` the drogue controller's
    :class:`~hosedrogue.model.integrate.LoopArrays` (used if ``ep[EP_CTRL]``; its force acts at
    the drogue as in the fixed-length model until the probe couples, then it is off)."""
    L = z[4 * n + Z_L]
    Ld = z[4 * n + Z_LD]
    set_variable_link(L, n, l, M, J, ep)
    q = z[: 2 * n]
    qd = z[2 * n: 4 * n]
    e, a, b, cs, r, v, c, F, Mom, tau = ws[0], ws[1], ws[2], ws[3], ws[4], ws[5], ws[6], ws[7], ws[8], ws[9]
    link_frames(q, n, e, a, b, cs)
    apply_charts(n, chart, e, a, b)
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, c)
    rotate_rows(n, chart, c, False)  # joint_kinematics writes l d2e/dt2 in the standard chart
    patch_kinematics(Ld, n, e, a, b, qd, v, c)
    # the probe, and its forebody's bow wave in the air the drag (and a steering drogue) sees
    px, py, pz, vpx, vpy, vpz = probe_tip(t, z, n, ep)
    air_with_bow_wave(t, env, gust, ep, px, py, pz, ws[16])
    u0 = ws2[13][:2]  # the control force at the drogue (ws2[13] is free: the unit-L'' solve has no drag)
    u0[0] = 0.0
    u0[1] = 0.0
    m0 = m1 = c0 = c1 = 0.0
    actuated = ep[EP_CTRL] != 0.0 and DA.is_actuated(loop.act)
    ddx = ddy = ddz = 0.0
    if actuated:
        ddx, ddy, ddz = drogue_surfaces(t, z, n, r, v, ps, ws[16], gust, ep, loop, u0, out)
        m0, m1, c0, c1 = out[O_MY], out[O_MZ], out[O_CY], out[O_CZ]
    elif ep[EP_CTRL] != 0.0 and ep[EP_COUPLED] == 0.0:
        nx = 4 * n + Z_TAIL + int(ep[EP_NPIL])
        m0, m1, c0, c1 = applied_force_at(t, z, nx, r[n, 1], r[n, 2], loop.Cc, loop.Dc, loop.y_ref, loop.act,
                                          loop.noise, loop.noise_dt, u0)
    out[O_UY] = u0[0]
    out[O_UZ] = u0[1]
    out[O_MY] = m0
    out[O_MZ] = m1
    out[O_CY] = c0
    out[O_CZ] = c1
    joint_forces(t, u0, l, M, ps, ws[16], gust, n, e, r, v, F, Mom, ws[13])
    if actuated:
        DA.add_drogue_load(F, ws[13], n, ddx, ddy, ddz)
    # the tanker's motion (nothing in level flight); the exit's share of the hose mass, carried by
    # the tanker, feels its acceleration too (its weight is added with the tow force)
    frame_loads(ps[PS_G], 0.5 * ep[EP_MU] * l[0] if ep[EP_SPLIT] != 0.0 else 0.0, l, M, J, n, e, r, v, ws[16], F, Mom)
    fx = fy = fz = 0.0
    if ep[EP_COUPLED] != 0.0:
        fx, fy, fz = probe_force(ep, n, r, v, px, py, pz, vpx, vpy, vpz)
        F[n, 0] += fx
        F[n, 1] += fy
        F[n, 2] += fz
    rotate_rows(n, chart, Mom, True)  # moments into each link's chart axes
    rotational_terms(qd, J, n, cs, Mom, tau)
    qdd = ws[15]
    chain_forward_dynamics(l, M, J, n, a, b, cs, c, F, tau, ws[10], ws[11], ws[12], qdd, ws[14])
    # response to a unit L'': d'Alembert force -M_k e_0 on joints 1..n, nothing else
    F2, c2, tau2, qdde = ws2[7], ws2[6], ws2[9], ws2[15]
    for i in range(3):
        F2[0, i] = 0.0
    for k in range(n):
        for i in range(3):
            F2[k + 1, i] = -M[k] * e[0, i]
            c2[k, i] = 0.0
        tau2[k, 0] = 0.0
        tau2[k, 1] = 0.0
    chain_forward_dynamics(l, M, J, n, a, b, cs, c2, F2, tau2, ws2[10], ws2[11], ws2[12], qdde, ws2[14])
    # exit tension at L'' = 0 and the effective mass the hose adds to the reel
    T00 = exit_tension(l, ps, e, F, ws[14], n)
    me = 0.0
    for i in range(3):
        me -= ws2[14][i] * e[0, i]
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


@njit(**JIT)
def eng_deriv(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, dz):
    """dz/dt of the engagement state z (``hist``: the drogue history the pilot's delay reads)."""
    eng_evaluate(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
    qdd = ws[15]
    for i in range(2 * n):
        dz[i] = z[2 * n + i]
        dz[2 * n + i] = qdd[i]
    b = 4 * n
    tail_rates(z, b, out, dz)
    dz[b + Z_WAX] = 0.0
    loop_rates(t, z, n, b, ep, loop, hist, out, dz)


@njit(**JIT)
def tail_rates(z, b, out, dz):
    """dz/dt of L, L' and the work states (the tail starting at b) from the outputs ``out``."""
    dz[b + Z_L] = z[b + Z_LD]
    dz[b + Z_LD] = out[O_LDD]
    dz[b + Z_WM] = out[O_PMOTOR]
    dz[b + Z_WF] = out[O_PFRIC]
    dz[b + Z_WX] = out[O_PEXIT]
    dz[b + Z_WFLUX] = out[O_PFLUX]
    dz[b + Z_WP] = out[O_PPROBE]


@njit(**JIT)
def loop_rates(t, z, n, b, ep, loop, hist, out, dz):
    """dz/dt of the pilot's or receiver's, the commanded reel's, the controller's and the
    actuator's states (after the tail at b)."""
    npil = int(ep[EP_NPIL])
    if ep[EP_PIL] != 0.0:
        pilot_rates(t, z, n, ep, hist, dz)
    elif ep[EP_RCV] != 0.0:
        receiver_rates(t, z, n, ep, dz)
    if ep[EP_REEL_SLOT] != 0.0:
        dz[b + Z_TAIL + int(ep[EP_REEL_SLOT]) - 1] = 0.0  # the held take-up speed command
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


@njit(**JIT)
def eng_evaluate_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ews, dM, out, hg, guess):
    """:func:`eng_evaluate` of the elastic chain (docs/model.md §11): z = [q, qd, lam, lamd, tail,
    ...]. Joints 1..n are material points, so L moves no joint: the exit link's strain
    ``lam_0 / l_0 - 1`` (l_0 from L) carries the reel's pull, the hose's force on L is
    :func:`~hosedrogue.model.elastic.elastic_exit_tension` and the reel equation gives L''
    explicitly - one O(n) solve (:func:`~hosedrogue.model.elastic.elastic_forward_dynamics`; qdd in
    ws[15], the length accelerations in ews[7], the tensions in ews[3]). ``hg`` and ``guess`` (the
    stage's slope guess, len(z)): an implicit stage's (:func:`~hosedrogue.model.elastic.stiff_terms`;
    hg = 0 for the true derivative, guess then unused). In a stage the exit link's spring-damper
    is implicit in its length and in L together: the reel's equation is eliminated into the exit
    link's joint block (its augmentation in series with the reel's mass), so a stiff hose on a free
    reel costs no extra solve."""
    nh = 6 * n
    L = z[nh + Z_L]
    Ld = z[nh + Z_LD]
    set_variable_link(L, n, l, M, J, ep)
    q = z[: 2 * n]
    qd = z[2 * n: 4 * n]
    lam = z[4 * n: 5 * n]
    lamd = z[5 * n: 6 * n]
    e, a, b, cs, r, v, c, F, Mom, tau = ws[0], ws[1], ws[2], ws[3], ws[4], ws[5], ws[6], ws[7], ws[8], ws[9]
    link_frames(q, n, e, a, b, cs)
    apply_charts(n, chart, e, a, b)
    joint_kinematics(q, qd, lam, n, e, a, b, cs, r, v, c)
    rotate_rows(n, chart, c, False)  # joint_kinematics writes lam d2e/dt2 in the standard chart
    add_axial_rates(n, e, a, b, qd, lamd, v, c)
    exit_material_velocity(Ld, lam, l, e, v)
    u0 = ws[12][0]  # the control force at the drogue (ws[12] is the rigid recursion's scratch)
    u0[0] = 0.0
    u0[1] = 0.0
    m0 = m1 = c0 = c1 = 0.0
    if ep[EP_CTRL] != 0.0 and ep[EP_COUPLED] == 0.0:
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
    air_with_bow_wave(t, env, gust, ep, px, py, pz, ws[16])
    joint_forces_stretched(t, u0, l, lam, M, ps, ws[16], gust, n, e, r, v, F, Mom, ws[13])
    # the tanker's motion (as the rigid chain's; the links' rates from their actual lengths)
    frame_loads(ps[PS_G], 0.5 * ep[EP_MU] * l[0] if ep[EP_SPLIT] != 0.0 else 0.0, lam, M, J, n, e, r, v, ws[16], F,
                Mom)
    fx = fy = fz = 0.0
    if ep[EP_COUPLED] != 0.0:
        fx, fy, fz = probe_force(ep, n, r, v, px, py, pz, vpx, vpy, vpz)
        F[n, 0] += fx
        F[n, 1] += fy
        F[n, 2] += fz
    rotate_rows(n, chart, Mom, True)  # moments into each link's chart axes
    rotational_terms(qd, J, n, cs, Mom, tau)
    T, epsd, aug, taul = ews[3], ews[4], ews[5], ews[6]
    p_axial = axial_tensions(n, l, lam, lamd, Ld, ps, T, epsd)
    stiff_terms(n, l, hg, ps, guess[5 * n: 6 * n], T, aug, taul)
    angle_stiff_terms(n, l, lam, hg, ps, cs, T, guess[2 * n: 4 * n], tau, ews[8])
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
    elastic_forward_dynamics(lam, M, J, n, a, b, e, cs, c, F, tau, taul, aug, ews[0], ews[1], ews[2], ws[15],
                             ews[7], ws[14], ews[8])
    if not prescribed:
        if hg != 0.0:
            Ldd = (T0 + d0 * (ews[7][0] - guess[5 * n] + aLg) + rest) / (mr + d0)
        else:
            Ldd = (T0 + rest) / mr
    reel_outputs(Ld, n, l, ep, dM, v, cs, qd, T0, Ldd, taum, slack, px, py, pz, fx, fy, fz, vpx, vpy, vpz, pm, pf,
                 out)
    out[O_PAXIAL] = p_axial


@njit(**JIT)
def eng_deriv_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, hg, guess, dz):
    """:func:`eng_deriv` of the elastic chain (``hg``, ``guess`` (len(z)): see :func:`eng_evaluate_elastic`)."""
    eng_evaluate_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ews, dM, out, hg, guess)
    qdd = ws[15]
    lamdd = ews[7]
    for i in range(2 * n):
        dz[i] = z[2 * n + i]
        dz[2 * n + i] = qdd[i]
    for k in range(n):
        dz[4 * n + k] = z[5 * n + k]
        dz[5 * n + k] = lamdd[k]
    b = 6 * n
    tail_rates(z, b, out, dz)
    dz[b + Z_WAX] = out[O_PAXIAL]
    loop_rates(t, z, n, b, ep, loop, hist, out, dz)


def elastic_pairs(n, pilot, receiver):
    """The second-order pairs (position row, velocity row, count) of the elastic engagement state:
    angles, lengths, the free length L and, if flown, the pilot's or the receiver's probe position.

    Parameters
    ----------
    n : int
        Number of links [-].
    pilot, receiver : bool
        The pilot (``EP_PIL``) or the receiver (``EP_RCV``) flies the probe.

    Returns
    -------
    numpy.ndarray (3 or 4, 3) of int64
    """
    b = 6 * n
    rows = [[0, 2 * n, 2 * n], [4 * n, 5 * n, n], [b + Z_L, b + Z_LD, 1]]
    if pilot:
        rows.append([b + Z_TAIL + PIL_Y, b + Z_TAIL + PIL_VY, 2])
    elif receiver:
        rows.append([b + Z_TAIL + RCV_X, b + Z_TAIL + RCV_VX, 3])
    return np.array(rows, dtype=np.int64)


elastic_pairs_jit = njit(**JIT)(elastic_pairs)


@njit(**JIT)
def eng_elastic_step(t, z, h, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs, work):
    """One step of size h [s] of the elastic engagement from (t, z), in place: RK4 or the SDIRK of
    :mod:`hosedrogue.model.implicit` (``ep[EP_SCHEME]``). ``work`` (8, len(z)): the stages (the
    SDIRK's in rows 0-3, the step's start in rows 4-5); ``work[7]`` holds the SDIRK's first slope
    guess (the last stage slope of the previous step, or dz/dt at z) and receives the next one.
    Returns OK, or STAGE_LIMIT if the SDIRK's stages did not converge even on 16 substeps (z
    then back at the step's start)."""
    if ep[EP_SCHEME] == SCHEME_RK4:
        k1, k2, k3, k4, tmp, g = work[0], work[1], work[2], work[3], work[4], work[5]
        eng_deriv_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, 0.0, g, k1)
        rk4_stage(z, 0.5 * h, k1, tmp)
        eng_deriv_elastic(t + 0.5 * h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out,
                          0.0, g, k2)
        rk4_stage(z, 0.5 * h, k2, tmp)
        eng_deriv_elastic(t + 0.5 * h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out,
                          0.0, g, k3)
        rk4_stage(z, h, k3, tmp)
        eng_deriv_elastic(t + h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, 0.0, g, k4)
        rk4_combine(z, h, k1, k2, k3, k4)
        return OK
    # the SDIRK: the step, or where a stage's corrections do not converge 2, 4, 8, 16 substeps
    z0, g0 = work[4], work[5]
    nz = z.shape[0]
    for i in range(nz):
        z0[i] = z[i]
        g0[i] = work[7][i]
    m = 1
    while m <= SDIRK_MAX_SUBSTEPS:
        hs = h / m
        ok = True
        for j in range(m):
            if not sdirk_step(t + j * hs, z, hs, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out,
                              pairs, work):
                ok = False
                break
        if ok:
            return OK
        for i in range(nz):
            z[i] = z0[i]
            work[7][i] = g0[i]
        m *= 2
    return STAGE_LIMIT


@njit(**JIT)
def sdirk_stage(t, zbase, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs, hg, Kg, K, Y):
    """One implicit stage from ``zbase`` (:mod:`hosedrogue.model.implicit`), the slope guess in Kg:
    corrections until the last moves no stage velocity by more than SDIRK_TOLERANCE_M_S, at least
    ``ep[EP_ITER]``, at most SDIRK_MAX_CORRECTIONS. The stage's slope into K (and Kg). Returns
    whether they converged."""
    nz = zbase.shape[0]
    least = int(ep[EP_ITER])
    for it in range(max(SDIRK_MAX_CORRECTIONS, least)):
        stage_point(zbase, Kg, hg, pairs, Y)
        eng_deriv_elastic(t, Y, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, hg, Kg, K)
        d = correction_size(n, hg, Kg, K, Y, ws[3])  # ws[3]: the frames of Y's evaluation
        for i in range(nz):
            Kg[i] = K[i]
        if not math.isfinite(d):
            return False
        if it + 1 >= least and d <= SDIRK_TOLERANCE_M_S:
            return True
    return False


@njit(**JIT)
def sdirk_step(t, z, h, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs, work):
    """One SDIRK step of size h [s] from (t, z), in place, the first stage's guess in ``work[7]``
    (which receives the next one). Returns False (z then undefined) if a stage's corrections did
    not converge."""
    hg = h * SDIRK2_GAMMA
    Kg, K1, zhat, Y, K2 = work[0], work[1], work[2], work[3], work[7]
    nz = z.shape[0]
    for i in range(nz):
        Kg[i] = K2[i]
    if not sdirk_stage(t + hg, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs, hg, Kg,
                       K1, Y):
        return False
    stage_point(z, K1, hg, pairs, Y)
    after_stage1(z, h, K1, zhat)
    for i in range(nz):
        Kg[i] = K1[i]  # the second stage's guess: the first stage's slope
    if not sdirk_stage(t + h, zhat, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs, hg,
                       Kg, K2, Y):
        return False
    stage_point(zhat, K2, hg, pairs, Y)
    for i in range(nz):
        z[i] = Y[i]
    return True


@njit(**JIT)
def plane_distance(z, n, l, ws, t, ep):
    """Signed distance [m] of the probe tip aft of the coupler plane (through joint n, normal to
    the last link, e_{n-1} pointing aft); positive before contact. Uses ws[0], ws[4] as filled by
    :func:`eng_evaluate` for z."""
    px, py, pz, _, _, _ = probe_tip(t, z, n, ep)
    e = ws[0]
    r = ws[4]
    k = n - 1
    return (px - r[n, 0]) * e[k, 0] + (py - r[n, 1]) * e[k, 1] + (pz - r[n, 2]) * e[k, 2]


@njit(**JIT)
def eng_energy(z, n, l, M, J, ps, ep, chart):
    """(hose kinetic, elastic bending (``moment``), reel kinetic) energy [J] of state z
    (:func:`~hosedrogue.model.kernels.chain_energy`; gravity's work is in the balance's terms);
    with elastic links the elastic energy includes their strain energy."""
    ws = make_workspace_jit(n)
    chain_kinematics(z, n, l, M, J, ep, chart, ws)
    T, _, U = chain_energy(n, l, M, J, ps, ws[0], ws[3], ws[4], ws[5], z[2 * n: 4 * n])
    nh = tail_start(n, ep)
    if ep[EP_ELASTIC] != 0.0:
        U += strain_energy(n, l, z[4 * n: 5 * n], ps)
    Tr = 0.0
    if ep[EP_LAW] != LAW_LOCKED:
        Tr = 0.5 * ep[EP_JR] * (z[nh + Z_LD] / ep[EP_RD]) ** 2
    return T, U, Tr


@njit(**JIT)
def eng_segment(z, t0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist,
                max_yaw, switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, loads):
    """Steps of size h from (t0, z) (global step index step0) for at most ``nsteps`` steps, in
    place: RK4, or for elastic links the integrator ``ep[EP_SCHEME]`` (:func:`eng_elastic_step`).

    Saves z at every global step that is a multiple of ``save_every`` (into ts, zs). Stops after
    the step at which the exit link's length leaves [merge_at, split_at] (SPLIT / MERGE), the probe
    tip crosses the coupler plane before coupling (PLANE; zprev then holds the state before the
    step), or the state fails (NONFINITE / YAW_LIMIT, or REEL_END: the free length left the reel's
    range). Returns (status, steps done, saved count).
    With a pilot (``ep[EP_PIL]``) the drogue's y, z, y', z' after every global step k go to
    ``hist[k]`` (row 0 at the start), for the pilot's delayed view of the drogue. With elastic
    links the loads of the state after every global step k go to ``loads[k]`` (:func:`state_loads`;
    ``loads`` has one row per step of the run, or is a (1, 4) placeholder for rigid links).
    """
    nz = z.shape[0]
    work = np.empty((8, nz))
    ws = make_workspace_jit(n)
    ws2 = make_workspace_jit(n)
    dM = np.empty(2)
    out = np.zeros(O_SIZE)
    return eng_steps(z, t0, 0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist,
                     max_yaw, switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, True, 0, work, ws, ws2,
                     dM, out, loads)


@njit(**JIT)
def eng_steps(z, t0, s0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist,
              max_yaw, switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, record, saved0, work, ws, ws2,
              dM, out, loads):
    """:func:`eng_segment` with its scratch given (``work`` (8, nz): the RK4 stages and the trial
    state, or the SDIRK's stages with its slope guess in ``work[7]``, carried from call to call;
    the workspaces ``ws``, ``ws2``, ``dM``, ``out`` of :func:`eng_evaluate`), the saved
    rows written from row ``saved0`` on and only if ``record``, the state ``s0`` steps after the
    time origin ``t0`` of its segment (step k after it is at ``t0 + k h``, as one uninterrupted
    segment counts: a segment continued in several calls takes the same times, and with elastic
    links the same SDIRK guesses). Returns (status, steps done, saved count)."""
    nz = z.shape[0]
    saved = saved0
    elastic = ep[EP_ELASTIC] != 0.0
    nh = tail_start(n, ep)
    ews = make_elastic_workspace_jit(n)
    pairs = elastic_pairs_jit(n, ep[EP_PIL] != 0.0, ep[EP_RCV] != 0.0)
    if elastic and s0 == 0:  # a segment's start: the SDIRK's first slope guess is dz/dt there
        eng_deriv_elastic(t0, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, 0.0, work[6],
                          work[7])
        if step0 == 0:
            state_loads(t0, z, n, l, M, J, ps, ep, chart, ws, ews, loads[0])
    probing = ep[EP_PROBE] != 0.0 and ep[EP_COUPLED] == 0.0
    piloted = ep[EP_PIL] != 0.0
    if piloted and step0 == 0:
        hist[0, 0], hist[0, 1], hist[0, 2], hist[0, 3] = drogue_motion(z, n, l, M, J, ep, chart, ws)
    d_before = 0.0
    if probing:
        chain_kinematics(z, n, l, M, J, ep, chart, ws)  # the frames and joint positions of z
        d_before = plane_distance(z, n, l, ws, t0 + s0 * h, ep)
    for s in range(1, nsteps + 1):
        t = t0 + (s0 + s - 1) * h
        for i in range(nz):
            zprev[i] = z[i]
        if elastic:
            if eng_elastic_step(t, z, h, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ews, dM, out, pairs,
                                work) != OK:
                return STAGE_LIMIT, s - 1, saved  # z is the state after the last step done
        else:
            eng_rigid_step(t, z, h, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, work)
        t = t0 + (s0 + s) * h
        status = step_status(z, n, max_yaw)
        if status != OK:
            return status, s, saved
        L = z[nh + Z_L]
        if L < ep[EP_L_MIN] or L > ep[EP_L_MAX]:
            return REEL_END, s, saved
        if piloted:
            hist[step0 + s, 0], hist[step0 + s, 1], hist[step0 + s, 2], hist[step0 + s, 3] = drogue_motion(
                z, n, l, M, J, ep, chart, ws)
        if elastic:
            state_loads(t, z, n, l, M, J, ps, ep, chart, ws, ews, loads[step0 + s])
        if record and (step0 + s) % save_every == 0:
            ts[saved] = t
            zs[saved, :] = z
            saved += 1
        for k in range(n):
            if abs(z[2 * k + 1]) > switch_yaw:
                return CHART, s, saved
        set_variable_link(z[nh + Z_L], n, l, M, J, ep)
        if l[0] > split_at:
            return SPLIT, s, saved
        if allow_merge and l[0] < merge_at:
            return MERGE, s, saved
        if probing:
            # the coupler plane needs the kinematics only: the frames and joint positions that the
            # full evaluation would write, bit for bit (chain_kinematics is its first half); with
            # elastic links state_loads has just written them for this z
            if not elastic:
                chain_kinematics(z, n, l, M, J, ep, chart, ws)
            d = plane_distance(z, n, l, ws, t, ep)
            if d_before > 0.0 and d <= 0.0:
                return PLANE, s, saved
            d_before = d
    return OK, nsteps, saved


@njit(**JIT)
def eng_rigid_step(t, z, h, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, work):
    """One RK4 step of size h [s] of the rigid engagement from (t, z), in place (``work`` (8,
    len(z)): the stages in rows 0-4)."""
    k1, k2, k3, k4, tmp = work[0], work[1], work[2], work[3], work[4]
    eng_deriv(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k1)
    rk4_stage(z, 0.5 * h, k1, tmp)
    eng_deriv(t + 0.5 * h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k2)
    rk4_stage(z, 0.5 * h, k2, tmp)
    eng_deriv(t + 0.5 * h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k3)
    rk4_stage(z, h, k3, tmp)
    eng_deriv(t + h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k4)
    rk4_combine(z, h, k1, k2, k3, k4)


@njit(**JIT)
def state_loads(t, z, n, l, M, J, ps, ep, chart, ws, ews, row):
    """The loads of an elastic state z from its kinematics alone (no solve): exit tension
    (:func:`~hosedrogue.model.elastic.elastic_exit_tension`) and drogue-end tension [N], probe
    load [N] and slack [m] into ``row`` (4,): the per-step record the run's peaks are taken from
    (docs/engagement.md, "What a run reports")."""
    nh = tail_start(n, ep)
    chain_kinematics(z, n, l, M, J, ep, chart, ws)
    lam = z[4 * n: 5 * n]
    T, epsd = ews[3], ews[4]
    axial_tensions(n, l, lam, z[5 * n: 6 * n], z[nh + Z_LD], ps, T, epsd)
    row[0] = elastic_exit_tension(n, l, lam, ps, ws[0], epsd)
    row[1] = T[n - 1]
    r, v = ws[4], ws[5]
    f = 0.0
    if ep[EP_COUPLED] != 0.0:
        px, py, pz, vpx, vpy, vpz = probe_tip(t, z, n, ep)
        fx, fy, fz = probe_force(ep, n, r, v, px, py, pz, vpx, vpy, vpz)
        f = math.sqrt(fx * fx + fy * fy + fz * fz)
    row[2] = f
    arc = 0.0
    for k in range(n):
        arc += lam[k]
    row[3] = arc - math.sqrt(r[n, 0] ** 2 + r[n, 1] ** 2 + r[n, 2] ** 2)


@njit(**JIT)
def evaluate_state(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, ews, dM, out):
    """The true accelerations and outputs of state z, rigid (:func:`eng_evaluate`) or elastic
    (:func:`eng_evaluate_elastic`)."""
    if ep[EP_ELASTIC] != 0.0:
        eng_evaluate_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ews, dM, out, 0.0, z)
    else:
        eng_evaluate(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)


@njit(**JIT)
def eng_raw(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out, raw):
    """The raw measurement (``hosedrogue.model.sampled.R_*``) of state z at time t [s]: drogue and
    probe tip positions and velocities, free length, take-up speed (-L'), exit tension of the
    evaluation with the commands as they are, coupled flag, an actuated drogue's dynamic pressure
    (NaN without control surfaces)."""
    if ep[EP_ELASTIC] != 0.0:
        eng_evaluate_elastic(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, make_elastic_workspace_jit(n), dM,
                             out, 0.0, z)
    else:
        eng_evaluate(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
    r, v = ws[4], ws[5]
    for i in range(3):
        raw[R_DROGUE + i] = r[n, i]
        raw[R_DROGUE_V + i] = v[n, i]
        raw[R_PROBE + i] = out[O_PX + i]
        raw[R_PROBE_V + i] = out[O_VPX + i]
    raw[R_L] = z[tail_start(n, ep) + Z_L]
    raw[R_REEL_V] = -z[tail_start(n, ep) + Z_LD]
    raw[R_T0] = out[O_T0]
    raw[R_COUPLED] = ep[EP_COUPLED]
    raw[R_Q] = out[O_Q] if ep[EP_CTRL] != 0.0 and DA.is_actuated(loop.act) else math.nan


@njit(**JIT)
def eng_advance(ctr, z, h, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist, max_yaw,
                switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, record, work, ws, ws2, dM, out, ring,
                delay, sample_h, noise3, noise3_dt, balance, mbuf, loads):
    """Integrate from the counters ``ctr`` (``hosedrogue.model.sampled.C_*``: global step,
    saved rows, the segment's origin ``C_ORIGIN``; updated in place) toward global step
    ``ctr[C_TARGET]`` (:func:`eng_steps`); when it is
    reached, the raw measurement of the next sample (``ctr[C_SAMPLE] + 1``) into the ring and
    its measurement (delayed by ``delay`` samples) into ``mbuf``, and the sample counter moves on
    (``loads``: the elastic links' per-step record, :func:`eng_segment`).
    Returns the status of the segment (an event - a remesh, the coupler plane - stops it early)."""
    step0 = ctr[C_STEP]
    target = ctr[C_TARGET]
    origin = ctr[C_ORIGIN]
    status, done, saved = eng_steps(z, origin * h, step0 - origin, step0, h, target - step0, save_every, n, l, M, J,
                                    ps, env, gust, ep, chart, loop, hist, max_yaw, switch_yaw, split_at, merge_at,
                                    allow_merge, zprev, ts, zs, record, ctr[C_SAVED], work, ws, ws2, dM, out, loads)
    ctr[C_STEP] = step0 + done
    ctr[C_SAVED] = saved
    ctr[C_STATUS] = status
    failed = status == NONFINITE or status == YAW_LIMIT or status == REEL_END or status == STAGE_LIMIT
    if ctr[C_STEP] == target and not failed:
        k = ctr[C_SAMPLE] + 1
        eng_raw(target * h, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out, ring[k % ring.shape[0]])
        deliver(ring, k, delay, sample_h, noise3, noise3_dt, balance, mbuf)
        ctr[C_SAMPLE] = k
    return status


@njit(**JIT)
def eng_outputs(ts, zs, n, l, M, J, ps, env, gust, ep, chart, loop, joints, jvel, scal, tow, tension_drogue,
                drogue_drag, link_tension):
    """Derived outputs at saved states: joints (N, n+1, 3), joint velocities, the ``out`` scalars
    (N, O_SIZE), tow-point force (N, 3), the tension in the last link [N] (N,), the drogue's
    drag (N, 3) [N] and, for elastic links, every link's tension EA eps + c_a deps/dt [N] (N, n;
    untouched for rigid links). The tow-point force includes the weight of the hose mass lumped
    at the exit (half the exit link's with ``split`` lumping, as the fixed-length chain's)."""
    ws = make_workspace_jit(n)
    ws2 = make_workspace_jit(n)
    ews = make_elastic_workspace_jit(n)
    dM = np.empty(2)
    out = np.zeros(O_SIZE)
    for i in range(ts.shape[0]):
        if ep[EP_ELASTIC] != 0.0:
            eng_evaluate_elastic(ts[i], zs[i], n, l, M, J, ps, env, gust, ep, chart, loop, ws, ews, dM, out, 0.0,
                                 zs[i])
            joints[i] = ws[4]
            jvel[i] = ws[5]
            scal[i] = out
            for j in range(3):
                tow[i, j] = ws[14][j]
                drogue_drag[i, j] = ws[13][j]
            if ep[EP_SPLIT] != 0.0:
                tow[i, 2] += 0.5 * ep[EP_MU] * l[0] * ps[PS_G]
            tension_drogue[i] = ews[3][n - 1]  # the last link's tension EA eps + c_a deps/dt
            link_tension[i] = ews[3]
            continue
        eng_evaluate(ts[i], zs[i], n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
        out[O_PAXIAL] = 0.0
        joints[i] = ws[4]
        jvel[i] = ws[5]
        scal[i] = out
        Ldd = out[O_LDD]
        # total force of the hose on the exit: F_0 + sum (F_k - M_k A_k)
        for j in range(3):
            tow[i, j] = ws[14][j] + Ldd * ws2[14][j]
            drogue_drag[i, j] = ws[13][j]
        if ep[EP_SPLIT] != 0.0:
            tow[i, 2] += 0.5 * ep[EP_MU] * l[0] * ps[PS_G]
        # last link's tension: the drogue joint's load minus its inertia, along the link
        # (joint n's acceleration from the recursion: A_n = L'' e_0 + sum of link terms)
        e = ws[0]
        qdd = ws[15]
        Ax = Ldd * e[0, 0]
        Ay = Ldd * e[0, 1]
        Az = Ldd * e[0, 2]
        for k in range(n):
            Ax += l[k] * (ws[1][k, 0] * qdd[2 * k] + ws[2][k, 0] * qdd[2 * k + 1]) + ws[6][k, 0]
            Ay += l[k] * (ws[1][k, 1] * qdd[2 * k] + ws[2][k, 1] * qdd[2 * k + 1]) + ws[6][k, 1]
            Az += l[k] * (ws[1][k, 2] * qdd[2 * k] + ws[2][k, 2] * qdd[2 * k + 1]) + ws[6][k, 2]
        F = ws[7]
        m = M[n - 1]
        tension_drogue[i] = ((F[n, 0] - m * Ax) * e[n - 1, 0] + (F[n, 1] - m * Ay) * e[n - 1, 1]
                             + (F[n, 2] - m * Az) * e[n - 1, 2])
