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
the moving masses, work of the probe on the drogue). ``ep`` holds the engagement scalars
(indices below); ``ws`` is :func:`~hosedrogue.model.kernels.make_workspace` of n links and
``ws2`` a second one for the unit-L'' solve.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..environment.bow_wave import SHAPE_LINE, SHAPE_OFF, SHAPE_RANKINE
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
    joint_kinematics,
    link_frames,
    make_workspace_jit,
    rotational_terms,
)
from .integrate import (actuator_rates, applied_force_at, control_law, controller_rates, rk4_combine, rk4_stage,
                        step_status)
from . import drogue_actuator as DA
from .frame import frame_loads
from .kernels import NONFINITE, YAW_LIMIT
from .sampled import (C_ORIGIN, C_SAMPLE, C_SAVED, C_STATUS, C_STEP, C_TARGET, R_COUPLED, R_Q, R_DROGUE, R_DROGUE_V, R_L, R_PROBE, R_PROBE_V,
                      R_REEL_V, R_T0, deliver)

# --- ep layout -------------------------------------------------------------------------------
(EP_MU, EP_MD, EP_SPLIT, EP_JLINK, EP_L0,
 EP_LAW, EP_RD, EP_JR, EP_CR, EP_TSET, EP_TAU_MAX, EP_V_IN_MAX, EP_V_OUT_MAX, EP_K_GOV,
 EP_KS, EP_DB, EP_KV,
 EP_PAY_T0, EP_PAY_DIST, EP_PAY_V, EP_PAY_A,
 EP_PROBE, EP_P0X, EP_P0Y, EP_P0Z, EP_VC, EP_PUSH, EP_T_STOP, EP_KP, EP_CP, EP_COUPLED, EP_T_CAP,
 EP_S_CAP, EP_JD,
 EP_BW, EP_BW_DX, EP_BW_DY, EP_BW_DZ, EP_BW_Q, EP_BW_LEN,
 EP_CTRL, EP_NPIL, EP_PIL_DELAY, EP_PIL_LAG, EP_PIL_TV, EP_PIL_VMAX, EP_PIL_AMAX, EP_H,
 EP_L_MIN, EP_L_MAX) = range(50)
# the sampled-data controllers' entries (docs/controllers.md): the pilot flag, the receiver and
# the commanded reel
(EP_PIL, EP_RCV, EP_RCV_TV, EP_RCV_VMAX, EP_RCV_AMAX, EP_REEL_SLOT, EP_REEL_TV) = (50, 51, 52, 53, 56, 59, 60)
EP_SIZE = 61
# EP_CTRL: 1 with a drogue controller in the loop (its states follow the pilot's, see below);
# EP_NPIL: number of states of the block after the tail (the pilot's PIL_STATES or the receiver's
# RCV_STATES, and the commanded reel's one; see below); EP_PIL_*: the pilot's reaction time [s], lag
# [s], velocity time constant [s], speed [m/s] and acceleration [m/s^2] bounds; EP_H: the RK4
# step [s] (the index of the drogue history the pilot's delay reads); EP_L_MIN, EP_L_MAX: the free
# hose length's range [m] between the drum's end stops (fully reeled in, fully paid out)
# EP_PIL: 1 when the pilot flies the probe (its states open the block after the tail); EP_RCV: 1
# when the receiver flies it (its RCV_STATES states open the block: probe tip position and
# velocity [m, m/s] and the held velocity command [m/s]), with the velocity time constant
# EP_RCV_TV [s] and the per-axis bounds EP_RCV_VMAX (3) [m/s] and EP_RCV_AMAX (3) [m/s^2];
# EP_REEL_SLOT: 1 + the place in the block of the held take-up speed command [m/s] of the
# commanded reel (LAW_COMMANDED), 0 without; EP_REEL_TV: its speed time constant [s]. EP_NPIL
# counts the whole block.

# bow-wave shapes (EP_BW); EP_BW_D* is the source (the line's forward end) minus the probe tip [m]
BW_OFF, BW_RANKINE, BW_LINE = SHAPE_OFF, SHAPE_RANKINE, SHAPE_LINE

LAW_LOCKED, LAW_CONSTANT_TENSION, LAW_RESPONSE, LAW_COMMANDED = 0, 1, 2, 3

# state tail (after the 4n hose entries)
Z_L, Z_LD, Z_WM, Z_WF, Z_WX, Z_WFLUX, Z_WP = range(7)
Z_TAIL = 7
# after the tail: the pilot's states (if any: probe tip y, z [m] and their rates [m/s]), then the
# controller's states and, for a rate-limited actuator, the applied force [N] - the layout of
# hosedrogue.model.integrate's closed loop with x = everything before the controller
PIL_Y, PIL_Z, PIL_VY, PIL_VZ = range(4)
PIL_STATES = 4
# or the receiver's: probe tip position, velocity, held velocity command (tanker frame)
RCV_X, RCV_VX, RCV_CX = 0, 3, 6
RCV_STATES = 9

# out layout (scalars of one evaluation)
(O_T0, O_LDD, O_TAU, O_SLACK, O_PX, O_PY, O_PZ, O_FPX, O_FPY, O_FPZ, O_VPX, O_VPY, O_VPZ,
 O_PMOTOR, O_PFRIC, O_PEXIT, O_PFLUX, O_PPROBE,
 O_UY, O_UZ, O_MY, O_MZ, O_CY, O_CZ, O_Q, O_EY, O_EZ) = range(27)
#: an actuated drogue's servo derivatives (:func:`hosedrogue.model.drogue_actuator.servo_rates`):
#: the surfaces' deflection rates [rad/s] first, then (second order) the servo rates' derivatives
O_SERVO = 27
O_SIZE = O_SERVO + 2 * DA.MAX_SURFACES
# O_UY, O_UZ: control force applied at the drogue [N]; O_MY, O_MZ: the measured drogue offsets
# [m]; O_CY, O_CZ: the commanded force [N] (differs from the applied one for a rate-limited actuator);
# O_Q: an actuated drogue's dynamic pressure [Pa]; O_EY, O_EZ: its anti-windup error [N]

# segment stop codes (besides kernels.OK / NONFINITE / YAW_LIMIT)
SPLIT, MERGE, PLANE, CHART = 10, 11, 12, 13
# failure code: the free hose length left [EP_L_MIN, EP_L_MAX] (the reel reached an end stop)
REEL_END = 20


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
def probe_tip(t, z, n, ep):
    """Probe-tip position and velocity [m, m/s] at time t and state z: :func:`probe_state`, whose
    lateral and vertical motion the pilot's states replace when a pilot flies the probe; the
    receiver's states when the receiver flies it."""
    if ep[EP_RCV] != 0.0:
        b = 4 * n + Z_TAIL
        return (z[b + RCV_X], z[b + RCV_X + 1], z[b + RCV_X + 2], z[b + RCV_VX], z[b + RCV_VX + 1],
                z[b + RCV_VX + 2])
    px, py, pz, vpx, vpy, vpz = probe_state(t, ep)
    if ep[EP_PIL] != 0.0:
        b = 4 * n + Z_TAIL
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
    b = 4 * n + Z_TAIL
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
def receiver_rates(z, n, ep, dz):
    """dz/dt of the receiver's states (docs/controllers.md): per axis the held velocity command,
    clipped to the speed bound, is followed through the first-order lag tau_v with the
    acceleration clipped to its bound (the pilot model's response, :func:`pilot_rates`); the
    command itself is held (zero rate)."""
    b = 4 * n + Z_TAIL
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
    vcmd = z[4 * n + Z_TAIL + int(ep[EP_REEL_SLOT]) - 1]  # take-up speed, positive reeling in
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
    included (the accelerations in the standard chart: no ``rotate_rows``)."""
    set_variable_link(z[4 * n + Z_L], n, l, M, J, ep)
    q = z[: 2 * n]
    qd = z[2 * n: 4 * n]
    e, a, b, cs, r, v, c = ws[0], ws[1], ws[2], ws[3], ws[4], ws[5], ws[6]
    link_frames(q, n, e, a, b, cs)
    apply_charts(n, chart, e, a, b)
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, c)
    patch_kinematics(z[4 * n + Z_LD], n, e, a, b, qd, v, c)


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
        kp = ep[EP_KP]
        cp = ep[EP_CP]
        fx = kp * (px - r[n, 0]) + cp * (vpx - v[n, 0])
        fy = kp * (py - r[n, 1]) + cp * (vpy - v[n, 1])
        fz = kp * (pz - r[n, 2]) + cp * (vpz - v[n, 2])
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
    # power of the kinetic energy carried by hose joining (L' > 0) or leaving the moving masses
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
    dz[b + Z_L] = z[b + Z_LD]
    dz[b + Z_LD] = out[O_LDD]
    dz[b + Z_WM] = out[O_PMOTOR]
    dz[b + Z_WF] = out[O_PFRIC]
    dz[b + Z_WX] = out[O_PEXIT]
    dz[b + Z_WFLUX] = out[O_PFLUX]
    dz[b + Z_WP] = out[O_PPROBE]
    npil = int(ep[EP_NPIL])
    if ep[EP_PIL] != 0.0:
        pilot_rates(t, z, n, ep, hist, dz)
    elif ep[EP_RCV] != 0.0:
        receiver_rates(z, n, ep, dz)
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
    (:func:`~hosedrogue.model.kernels.chain_energy`; gravity's work is in the balance's terms)."""
    ws = make_workspace_jit(n)
    chain_kinematics(z, n, l, M, J, ep, chart, ws)
    T, _, U = chain_energy(n, l, M, J, ps, ws[0], ws[3], ws[4], ws[5], z[2 * n: 4 * n])
    Tr = 0.0
    if ep[EP_LAW] != LAW_LOCKED:
        Tr = 0.5 * ep[EP_JR] * (z[4 * n + Z_LD] / ep[EP_RD]) ** 2
    return T, U, Tr


@njit(**JIT)
def eng_segment(z, t0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist,
                max_yaw, switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs):
    """RK4 from (t0, z) (global step index step0) for at most ``nsteps`` steps, in place.

    Saves z at every global step that is a multiple of ``save_every`` (into ts, zs). Stops after
    the step at which the exit link's length leaves [merge_at, split_at] (SPLIT / MERGE), the probe
    tip crosses the coupler plane before coupling (PLANE; zprev then holds the state before the
    step), or the state fails (NONFINITE / YAW_LIMIT, or REEL_END: the free length left the reel's
    range). Returns (status, steps done, saved count).
    With a pilot (``ep[EP_PIL]``) the drogue's y, z, y', z' after every global step k go to
    ``hist[k]`` (row 0 at the start), for the pilot's delayed view of the drogue.
    """
    nz = z.shape[0]
    work = np.empty((5, nz))
    ws = make_workspace_jit(n)
    ws2 = make_workspace_jit(n)
    dM = np.empty(2)
    out = np.zeros(O_SIZE)
    return eng_steps(z, t0, 0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist,
                     max_yaw, switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, True, 0, work, ws, ws2,
                     dM, out)


@njit(**JIT)
def eng_steps(z, t0, s0, step0, h, nsteps, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist,
              max_yaw, switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, record, saved0, work, ws, ws2,
              dM, out):
    """:func:`eng_segment` with its scratch given (``work`` (5, nz): the RK4 stages and the trial
    state; the workspaces ``ws``, ``ws2``, ``dM``, ``out`` of :func:`eng_evaluate`), the saved
    rows written from row ``saved0`` on and only if ``record``, the state ``s0`` steps after the
    time origin ``t0`` of its segment (step k after it is at ``t0 + k h``, as one uninterrupted
    segment counts: a segment continued in several calls takes the same times). Returns (status,
    steps done, saved count)."""
    nz = z.shape[0]
    k1, k2, k3, k4, tmp = work[0], work[1], work[2], work[3], work[4]
    saved = saved0
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
        eng_deriv(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k1)
        rk4_stage(z, 0.5 * h, k1, tmp)
        eng_deriv(t + 0.5 * h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k2)
        rk4_stage(z, 0.5 * h, k2, tmp)
        eng_deriv(t + 0.5 * h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k3)
        rk4_stage(z, h, k3, tmp)
        eng_deriv(t + h, tmp, n, l, M, J, ps, env, gust, ep, chart, loop, hist, ws, ws2, dM, out, k4)
        rk4_combine(z, h, k1, k2, k3, k4)
        t = t0 + (s0 + s) * h
        status = step_status(z, n, max_yaw)
        if status != OK:
            return status, s, saved
        L = z[4 * n + Z_L]
        if L < ep[EP_L_MIN] or L > ep[EP_L_MAX]:
            return REEL_END, s, saved
        if piloted:
            hist[step0 + s, 0], hist[step0 + s, 1], hist[step0 + s, 2], hist[step0 + s, 3] = drogue_motion(
                z, n, l, M, J, ep, chart, ws)
        if record and (step0 + s) % save_every == 0:
            ts[saved] = t
            zs[saved, :] = z
            saved += 1
        for k in range(n):
            if abs(z[2 * k + 1]) > switch_yaw:
                return CHART, s, saved
        set_variable_link(z[4 * n + Z_L], n, l, M, J, ep)
        if l[0] > split_at:
            return SPLIT, s, saved
        if allow_merge and l[0] < merge_at:
            return MERGE, s, saved
        if probing:
            # the coupler plane needs the kinematics only: the frames and joint positions that the
            # full evaluation would write, bit for bit (chain_kinematics is its first half)
            chain_kinematics(z, n, l, M, J, ep, chart, ws)
            d = plane_distance(z, n, l, ws, t, ep)
            if d_before > 0.0 and d <= 0.0:
                return PLANE, s, saved
            d_before = d
    return OK, nsteps, saved


@njit(**JIT)
def eng_raw(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out, raw):
    """The raw measurement (``hosedrogue.model.sampled.R_*``) of state z at time t [s]: drogue and
    probe tip positions and velocities, free length, take-up speed (-L'), exit tension of the
    evaluation with the commands as they are, coupled flag, an actuated drogue's dynamic pressure
    (NaN without control surfaces)."""
    eng_evaluate(t, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
    r, v = ws[4], ws[5]
    for i in range(3):
        raw[R_DROGUE + i] = r[n, i]
        raw[R_DROGUE_V + i] = v[n, i]
        raw[R_PROBE + i] = out[O_PX + i]
        raw[R_PROBE_V + i] = out[O_VPX + i]
    raw[R_L] = z[4 * n + Z_L]
    raw[R_REEL_V] = -z[4 * n + Z_LD]
    raw[R_T0] = out[O_T0]
    raw[R_COUPLED] = ep[EP_COUPLED]
    raw[R_Q] = out[O_Q] if ep[EP_CTRL] != 0.0 and DA.is_actuated(loop.act) else math.nan


@njit(**JIT)
def eng_advance(ctr, z, h, save_every, n, l, M, J, ps, env, gust, ep, chart, loop, hist, max_yaw,
                switch_yaw, split_at, merge_at, allow_merge, zprev, ts, zs, record, work, ws, ws2, dM, out, ring,
                delay, sample_h, noise3, noise3_dt, balance, mbuf):
    """Integrate from the counters ``ctr`` (``hosedrogue.model.sampled.C_*``: global step,
    saved rows, the segment's origin ``C_ORIGIN``; updated in place) toward global step
    ``ctr[C_TARGET]`` (:func:`eng_steps`); when it is
    reached, the raw measurement of the next sample (``ctr[C_SAMPLE] + 1``) into the ring and
    its measurement (delayed by ``delay`` samples) into ``mbuf``, and the sample counter moves on.
    Returns the status of the segment (an event - a remesh, the coupler plane - stops it early)."""
    step0 = ctr[C_STEP]
    target = ctr[C_TARGET]
    origin = ctr[C_ORIGIN]
    status, done, saved = eng_steps(z, origin * h, step0 - origin, step0, h, target - step0, save_every, n, l, M, J,
                                    ps, env, gust, ep, chart, loop, hist, max_yaw, switch_yaw, split_at, merge_at,
                                    allow_merge, zprev, ts, zs, record, ctr[C_SAVED], work, ws, ws2, dM, out)
    ctr[C_STEP] = step0 + done
    ctr[C_SAVED] = saved
    ctr[C_STATUS] = status
    if ctr[C_STEP] == target and status != NONFINITE and status != YAW_LIMIT and status != REEL_END:
        k = ctr[C_SAMPLE] + 1
        eng_raw(target * h, z, n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out, ring[k % ring.shape[0]])
        deliver(ring, k, delay, sample_h, noise3, noise3_dt, balance, mbuf)
        ctr[C_SAMPLE] = k
    return status


@njit(**JIT)
def eng_outputs(ts, zs, n, l, M, J, ps, env, gust, ep, chart, loop, joints, jvel, scal, tow, tension_drogue,
                drogue_drag):
    """Derived outputs at saved states: joints (N, n+1, 3), joint velocities, the ``out`` scalars
    (N, O_SIZE), tow-point force (N, 3), the tension in the last link [N] (N,) and the drogue's
    drag (N, 3) [N]. The tow-point force includes the weight of the hose mass lumped at the exit
    (half the exit link's with ``split`` lumping, as the fixed-length chain's)."""
    ws = make_workspace_jit(n)
    ws2 = make_workspace_jit(n)
    dM = np.empty(2)
    out = np.zeros(O_SIZE)
    for i in range(ts.shape[0]):
        eng_evaluate(ts[i], zs[i], n, l, M, J, ps, env, gust, ep, chart, loop, ws, ws2, dM, out)
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
