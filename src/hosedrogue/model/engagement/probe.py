"""The engagement's probe (numba): the prescribed path, a path fed from outside (the engagement
FMU's), the tip flown by the pilot or the receiver, the coupling's spring-damper, and the bow
wave of the receiver's forebody in the air of an evaluation (docs/engagement.md, "Probe",
"Coupled phase", "Bow wave").
"""

from __future__ import annotations

import math

from numba import njit

from ...jit import JIT, JIT_INLINE, JIT_NO_ALLOC
from ..chain_loads import fill_env
from ..layout import (
    BW_OFF, ENV_BW, ENV_BW_LEN, ENV_BW_Q, ENV_BW_X, ENV_BW_Y, ENV_BW_Z, EP_BW, EP_BW_DX, EP_BW_DY, EP_BW_DZ,
    EP_BW_LEN, EP_BW_Q, EP_COUPLED, EP_CP, EP_FEED, EP_FEED_A, EP_FEED_J, EP_FEED_P, EP_FEED_T0, EP_FEED_V, EP_KP,
    EP_P0X, EP_P0Y, EP_P0Z, EP_PIL, EP_PUSH, EP_RCV, EP_S_CAP, EP_T_CAP, EP_T_STOP, EP_VC, PIL_VY, PIL_VZ, PIL_Y,
    PIL_Z, RCV_VX, RCV_X, Z_TAIL,
)
from .chain import tail_start


@njit(**JIT_NO_ALLOC)
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


@njit(**JIT_INLINE)
def fed_axis(s, ep, i):
    """Position, velocity and acceleration [m, m/s, m/s^2] along axis i of the fed path (``EP_FEED``)
    s seconds after ``EP_FEED_T0``."""
    v0, a0, j = ep[EP_FEED_V + i], ep[EP_FEED_A + i], ep[EP_FEED_J + i]
    return (ep[EP_FEED_P + i] + s * (v0 + s * (0.5 * a0 + s * (j / 6.0))), v0 + s * (a0 + 0.5 * s * j),
            a0 + s * j)


@njit(**JIT_NO_ALLOC)
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


@njit(**JIT_NO_ALLOC)
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


@njit(**JIT_NO_ALLOC)
def air_with_bow_wave(t, env, gust, ep, px, py, pz, scratch):
    """This evaluation's air (``env`` into ``scratch``, with the gust at time t when uniform:
    :func:`~hosedrogue.model.chain_loads.env_at`) and the bow wave of the forebody whose probe tip is
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
