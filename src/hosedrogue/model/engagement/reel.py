"""The engagement's reel (numba): the locked reel's payout schedule, the motor torque of the
constant-tension and response laws, the commanded reel, the rates of the masses that change
with L, and an evaluation's outputs of the reel, the probe and the powers (docs/engagement.md,
"Reel").
"""

from __future__ import annotations

import math

from numba import njit

from ...jit import JIT, JIT_NO_ALLOC
from ..layout import (
    EP_CR, EP_DB, EP_JLINK, EP_JR, EP_KS, EP_KV, EP_K_GOV, EP_LAW, EP_MU, EP_PAY_A, EP_PAY_DIST, EP_PAY_T0,
    EP_PAY_V, EP_RD, EP_REEL_SLOT, EP_REEL_TV, EP_SPLIT, EP_TAU_MAX, EP_TSET, EP_V_IN_MAX, EP_V_OUT_MAX,
    LAW_RESPONSE, O_FPX, O_FPY, O_FPZ, O_LDD, O_PEXIT, O_PFLUX, O_PFRIC, O_PMOTOR, O_PPROBE, O_PX, O_PY, O_PZ,
    O_SLACK, O_T0, O_TAU, O_VPX, O_VPY, O_VPZ, Z_TAIL,
)
from .chain import tail_start


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


@njit(**JIT_NO_ALLOC)
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


@njit(**JIT_NO_ALLOC)
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


@njit(**JIT_NO_ALLOC)
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
