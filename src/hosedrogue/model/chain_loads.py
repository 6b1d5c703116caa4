"""The link chain's kinematics and loads (numba): link frames, joint positions, velocities and
velocity-product accelerations, the air at a point (free stream, wake, gust, bow wave, the
tanker's rotation), and the external forces and moments on the joints and links (gravity, link
and drogue drag, control, bending, structural bending damping).

Everything here is a pure function of float64 arrays; no Python objects, no I/O, no validation
(that is :mod:`hosedrogue.model.system`'s job). Notation follows ``docs/model.md``:

* state ``x = [q, qd]``, ``q = [th_11, th_12, ..., th_n1, th_n2]`` (pitch down, yaw left), so
  link ``k`` (0-based here) has pitch ``q[2k]`` and yaw ``q[2k+1]``;
* ``e_k = [-c1 c2, -s2, s1 c2]`` points aft along link k; ``a_k = de/dth1``, ``b_k = de/dth2``;
* joint 0 is the tow point (origin of S_p); joint k+1 is the aft end of link k and carries the
  lumped mass ``M[k]`` (the drogue's mass is included in ``M[n-1]``). Which share of each link's
  mass a joint carries (``aft`` or ``split`` lumping) is decided in ``model/system.py``; the
  kernels only see the joint masses.

The equations of motion these loads enter are in :mod:`hosedrogue.model.chain_dynamics`. The
scalar arrays ``ps`` (the model's) and ``env`` (the air's; with the tanker's motion,
:mod:`hosedrogue.model.frame`) are laid out in :mod:`hosedrogue.model.layout` (``PS_*``,
``ENV_*``).
"""

from __future__ import annotations

import math

from numba import njit

from ..environment.bow_wave import bow_wave_velocity
from ..environment.turbulence import gust_at
from ..environment.wake import wake_velocity
from ..jit import JIT_NO_ALLOC, JIT_NO_ALLOC_INLINE
from .frame import frame_terms, frame_wind
from .layout import (
    BENDING_OFF, BENDING_PAPER, DRAG_GAUSS2, ENV_BW, ENV_BW_LEN, ENV_BW_Q, ENV_BW_X, ENV_BW_Y, ENV_BW_Z, ENV_FROZEN,
    ENV_GU, ENV_GV, ENV_GW, ENV_G_CUBIC, ENV_G_DT, ENV_G_NOW, ENV_G_T0, ENV_M_ON, ENV_M_T, ENV_M_V0, ENV_SIZE,
    ENV_T_OFF, ENV_T_ON, ENV_V, ENV_WAKE, PS_BENDING, PS_BEND_DAMP, PS_CN, PS_CT, PS_DO, PS_DRAG_QUAD,
    PS_DROGUE_CDA, PS_EI, PS_G, PS_RHO,
)


#: Two-point Gauss-Legendre abscissa on [0, 1] measured from the link's centre: 1/(2 sqrt 3).
GAUSS2_OFFSET = 0.5 / math.sqrt(3.0)


@njit(**JIT_NO_ALLOC)
def air_velocity(px, py, pz, t, env, gust):
    """Air velocity [m/s] in S_p at point (px, py, pz) [m, relative to the tow point], time t [s]:
    free stream, wake, gust and (in an engagement's evaluation) the receiver's bow wave."""
    wx, wy, wz = still_air_velocity(px, py, pz, t, env, gust)
    if env[ENV_BW] != 0.0:
        bx, by, bz = bow_wave_velocity(px, py, pz, env[ENV_BW], env[ENV_BW_X], env[ENV_BW_Y], env[ENV_BW_Z],
                                       env[ENV_BW_Q], env[ENV_BW_LEN])
        return wx + bx, wy + by, wz + bz
    return wx, wy, wz


@njit(**JIT_NO_ALLOC_INLINE)
def still_air_velocity(px, py, pz, t, env, gust, full=True):
    """:func:`air_velocity` without the bow wave: free stream, wake and gust [m/s] (and, when the
    tanker manoeuvres, the air's rotation relative to its axes, :func:`frame.frame_wind`).
    ``full`` False (a constant of the compiled caller): level flight in still air
    (:func:`still_level`), whose gust ``env_at`` has written; the tanker's motion and the gust
    record are then never compiled (docs/develop.md, "The compiled core")."""
    V = env[ENV_V]
    wy, wz = wake_velocity(py, pz, env, ENV_WAKE)
    if not full or env[ENV_G_NOW] != 0.0:
        wx, wy, wz = -V + env[ENV_GU], wy + env[ENV_GV], wz + env[ENV_GW]
    else:
        t_eff = t
        if env[ENV_FROZEN] != 0.0:
            # a point a distance -px behind the tow point meets the frozen gust field -px/V later
            # (manoeuvring: the field is laid along the path flown, read at path time + -px/V_0)
            if env[ENV_M_ON] != 0.0:
                t_eff = env[ENV_M_T] + px / env[ENV_M_V0]
            else:
                t_eff = t + px / V
        gu, gv, gw = gust_at(t_eff, env[ENV_G_T0], env[ENV_G_DT], gust, env[ENV_T_ON], env[ENV_T_OFF],
                             env[ENV_G_CUBIC] != 0.0)
        wx, wy, wz = -V + gu, wy + gv, wz + gw
    if full and env[ENV_M_ON] != 0.0:
        fx, fy, fz = frame_wind(px, py, pz, env)
        return wx + fx, wy + fy, wz + fz
    return wx, wy, wz


def still_level(env, t: float = 0.0) -> bool:
    """Whether the air of ``env`` at time ``t`` [s] is that of level flight in still air without a
    bow wave: no tanker motion, no gust at t (the gust record's window misses it) and the uniform
    gust distribution, the case of the evaluations compiled with ``full`` False
    (:func:`still_air_velocity`; docs/develop.md, "The compiled core").

    Parameters
    ----------
    env : numpy.ndarray
        The air's scalars (:data:`hosedrogue.model.layout.ENV`).
    t : float
        Time [s].

    Returns
    -------
    bool
    """
    gust_off = not (t >= env[ENV_T_ON] and t < env[ENV_T_OFF])
    return bool(env[ENV_M_ON] == 0.0 and env[ENV_BW] == 0.0 and env[ENV_FROZEN] == 0.0 and gust_off)


@njit(**JIT_NO_ALLOC)
def link_frames(q, n, e, a, b, cs):
    """Fill e, a, b (n,3) and cs (n,4) = [c1, s1, c2, s2] for every link."""
    for k in range(n):
        c1 = math.cos(q[2 * k])
        s1 = math.sin(q[2 * k])
        c2 = math.cos(q[2 * k + 1])
        s2 = math.sin(q[2 * k + 1])
        cs[k, 0] = c1
        cs[k, 1] = s1
        cs[k, 2] = c2
        cs[k, 3] = s2
        e[k, 0] = -c1 * c2
        e[k, 1] = -s2
        e[k, 2] = s1 * c2
        a[k, 0] = s1 * c2
        a[k, 1] = 0.0
        a[k, 2] = c1 * c2
        b[k, 0] = c1 * s2
        b[k, 1] = -c2
        b[k, 2] = -s1 * s2


@njit(**JIT_NO_ALLOC)
def joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, c):
    """Joint positions r and velocities v (n+1,3; row 0 = tow point) and each link's
    velocity-product acceleration c (n,3) = l_k d2e_k/dt2 at zero qdd (paper Eq. 16), so that
    joint k+1 accelerates as A_{k+1} = A_k + l_k (a_k qdd_k1 + b_k qdd_k2) + c_k."""
    for i in range(3):
        r[0, i] = 0.0
        v[0, i] = 0.0
    for k in range(n):
        d1 = qd[2 * k]
        d2 = qd[2 * k + 1]
        c1, s1, c2, s2 = cs[k, 0], cs[k, 1], cs[k, 2], cs[k, 3]
        lk = l[k]
        p11 = d1 * d1 + d2 * d2
        p12 = 2.0 * d1 * d2
        c[k, 0] = lk * (c1 * c2 * p11 - s1 * s2 * p12)
        c[k, 1] = lk * s2 * d2 * d2
        c[k, 2] = lk * (-s1 * c2 * p11 - c1 * s2 * p12)
        for i in range(3):
            r[k + 1, i] = r[k, i] + lk * e[k, i]
            v[k + 1, i] = v[k, i] + lk * (a[k, i] * d1 + b[k, i] * d2)


@njit(**JIT_NO_ALLOC_INLINE)
def kink(e, k):
    """Bend at joint k+1 between links k and k+1: (e_k x e_{k+1}) components, its length
    sin(gamma), and the angle gamma (atan2, accurate near 0)."""
    wx = e[k, 1] * e[k + 1, 2] - e[k, 2] * e[k + 1, 1]
    wy = e[k, 2] * e[k + 1, 0] - e[k, 0] * e[k + 1, 2]
    wz = e[k, 0] * e[k + 1, 1] - e[k, 1] * e[k + 1, 0]
    sn = math.sqrt(wx * wx + wy * wy + wz * wz)
    cn = e[k, 0] * e[k + 1, 0] + e[k, 1] * e[k + 1, 1] + e[k, 2] * e[k + 1, 2]
    return wx, wy, wz, sn, math.atan2(sn, cn)


@njit(**JIT_NO_ALLOC_INLINE)
def segment_drag(q_ct, q_cn, lw, sf, sp, k, e, v, wx, wy, wz):
    """Drag [N] of the piece of link k of length lw [m] at the point sf r_k + sp r_k+1 (sf + sp
    = 1), in air moving at (wx, wy, wz) [m/s] there: from the relative velocity, tangential
    -q_ct lw v_t |v_t| n_k and normal -q_cn lw |V_n| V_n, with q_c = rho pi d_o c / 2 and
    n_k = -e_k."""
    vtx = sf * v[k, 0] + sp * v[k + 1, 0] - wx
    vty = sf * v[k, 1] + sp * v[k + 1, 1] - wy
    vtz = sf * v[k, 2] + sp * v[k + 1, 2] - wz
    # n_k = -e_k; tangential and normal parts of the relative velocity
    vt = -(vtx * e[k, 0] + vty * e[k, 1] + vtz * e[k, 2])
    vnx = vtx + vt * e[k, 0]
    vny = vty + vt * e[k, 1]
    vnz = vtz + vt * e[k, 2]
    vn = math.sqrt(vnx * vnx + vny * vny + vnz * vnz)
    ft = -q_ct * lw * vt * abs(vt)  # along n_k = -e_k
    fn = -q_cn * lw * vn
    return -ft * e[k, 0] + fn * vnx, -ft * e[k, 1] + fn * vny, -ft * e[k, 2] + fn * vnz


@njit(**JIT_NO_ALLOC_INLINE)
def link_omega(k, l, e, v):
    """Angular velocity of link k [rad/s] from its end velocities: omega_k = e_k x de_k/dt with
    de_k/dt = (V_k+1 - V_k) / l_k (omega_k is perpendicular to e_k, docs/model.md §1)."""
    dx = (v[k + 1, 0] - v[k, 0]) / l[k]
    dy = (v[k + 1, 1] - v[k, 1]) / l[k]
    dz = (v[k + 1, 2] - v[k, 2]) / l[k]
    return (e[k, 1] * dz - e[k, 2] * dy, e[k, 2] * dx - e[k, 0] * dz, e[k, 0] * dy - e[k, 1] * dx)


@njit(**JIT_NO_ALLOC_INLINE)
def drag_rule(ps, rho):
    """The link drag's factors and quadrature: ``(q_ct, q_cn, npts, s0, s1, w)``.

    ``q_ct``, ``q_cn`` = 1/2 rho pi d_o c_t (c_n) [kg/m^2], the drag per unit length over the
    squared speed; the ``npts`` points at s0, s1 (0 fore joint, 1 aft joint) carry weight w each.
    A point load at s goes (1 - s) to the fore joint and s to the aft joint, which is exactly
    what that load's partial velocities give (the point moves as (1 - s) V_k + s V_k+1).
    """
    q_ct = 0.5 * rho * math.pi * ps[PS_DO] * ps[PS_CT]
    q_cn = 0.5 * rho * math.pi * ps[PS_DO] * ps[PS_CN]
    if ps[PS_DRAG_QUAD] == DRAG_GAUSS2:
        return q_ct, q_cn, 2, 0.5 - GAUSS2_OFFSET, 0.5 + GAUSS2_OFFSET, 0.5
    return q_ct, q_cn, 1, 0.5, 0.5, 1.0


@njit(**JIT_NO_ALLOC_INLINE)
def joint_forces(t, u, l, M, ps, env, gust, n, e, r, v, F, Mom, drogue_drag, full=True):
    """External forces on every joint F (n+1,3; row 0 acts on the tow point), moments on every
    link Mom (n,3) and the drogue drag (3,). Gravity, link and drogue drag, control, bending,
    structural bending damping. When the tanker manoeuvres (``env[ENV_M_ON]``) gravity is left
    to :func:`frame.frame_loads`, with the other apparent forces. ``full``: as
    :func:`still_air_velocity`'s."""
    if full:
        joint_forces_stretched(t, u, l, l, M, ps, env, gust, n, e, r, v, F, Mom, drogue_drag)
    else:
        joint_forces_still(t, u, l, l, M, ps, env, gust, n, e, r, v, F, Mom, drogue_drag)


def _joint_forces(full):
    """:func:`joint_forces_stretched` compiled for every case (``full``) or for level flight in still
    air at rest only (:func:`joint_forces_still`; ``full`` False as :func:`still_air_velocity`'s, and
    the joints' velocities zero, so no structural damping): a closure over the constant, whose
    other branches numba prunes before it types them."""

    @njit(**JIT_NO_ALLOC)
    def joint_forces_stretched(t, u, l, lam, M, ps, env, gust, n, e, r, v, F, Mom, drogue_drag):
        """:func:`joint_forces` of a chain whose links have the material (unstretched) lengths l and
        the actual lengths lam [m] (the elastic chain, :mod:`hosedrogue.model.elastic`): the drag
        area and the bending's lbar are per material length, the links' angular velocities (the
        structural damping) use the actual lengths; ``lam`` is ``l`` for rigid links."""
        g = ps[PS_G]
        rho = ps[PS_RHO]
        level = env[ENV_M_ON] == 0.0
        for k in range(n + 1):
            for i in range(3):
                F[k, i] = 0.0
        for k in range(n):
            for i in range(3):
                Mom[k, i] = 0.0
            if level:
                F[k + 1, 2] += M[k] * g
        if rho > 0.0:
            q_ct, q_cn, npts, s0, s1, w = drag_rule(ps, rho)
            # the air's velocity where it is a function of y and z only (the gust the same at every
            # point, env_at): the gust, then the wake added per point
            uniform = env[ENV_G_NOW] != 0.0
            ux = -env[ENV_V] + env[ENV_GU]
            gv = env[ENV_GV]
            gw = env[ENV_GW]
            for k in range(n):
                for j in range(npts):
                    sp = s0 if j == 0 else s1
                    sf = 1.0 - sp
                    px = sf * r[k, 0] + sp * r[k + 1, 0]
                    py = sf * r[k, 1] + sp * r[k + 1, 1]
                    pz = sf * r[k, 2] + sp * r[k + 1, 2]
                    if not full or uniform:
                        wy, wz = wake_velocity(py, pz, env, ENV_WAKE)
                        wx, wy, wz = ux, wy + gv, wz + gw
                        if full and not level:
                            fx, fy, fz = frame_wind(px, py, pz, env)
                            wx, wy, wz = wx + fx, wy + fy, wz + fz
                        if full and env[ENV_BW] != 0.0:
                            bx, by, bz = bow_wave_velocity(px, py, pz, env[ENV_BW], env[ENV_BW_X], env[ENV_BW_Y],
                                                           env[ENV_BW_Z], env[ENV_BW_Q], env[ENV_BW_LEN])
                            wx, wy, wz = wx + bx, wy + by, wz + bz
                    else:
                        wx, wy, wz = air_velocity(px, py, pz, t, env, gust)
                    dx, dy, dz = segment_drag(q_ct, q_cn, w * l[k], sf, sp, k, e, v, wx, wy, wz)
                    F[k, 0] += sf * dx
                    F[k, 1] += sf * dy
                    F[k, 2] += sf * dz
                    F[k + 1, 0] += sp * dx
                    F[k + 1, 1] += sp * dy
                    F[k + 1, 2] += sp * dz
            if full:
                wx, wy, wz = air_velocity(r[n, 0], r[n, 1], r[n, 2], t, env, gust)
            else:
                wx, wy, wz = still_air_velocity(r[n, 0], r[n, 1], r[n, 2], t, env, gust, False)
            vrx = v[n, 0] - wx
            vry = v[n, 1] - wy
            vrz = v[n, 2] - wz
            vr = math.sqrt(vrx * vrx + vry * vry + vrz * vrz)
            c = -0.5 * rho * ps[PS_DROGUE_CDA] * vr
            drogue_drag[0] = c * vrx
            drogue_drag[1] = c * vry
            drogue_drag[2] = c * vrz
        else:
            drogue_drag[0] = 0.0
            drogue_drag[1] = 0.0
            drogue_drag[2] = 0.0
        F[n, 0] += drogue_drag[0]
        F[n, 1] += drogue_drag[1] + u[0]
        F[n, 2] += drogue_drag[2] + u[1]

        mode = ps[PS_BENDING]
        EI = ps[PS_EI]
        if mode != BENDING_OFF and EI > 0.0:
            for k in range(n - 1):
                lbar = 0.5 * (l[k] + l[k + 1])
                if mode == BENDING_PAPER:
                    # equivalent force 8 E I gamma / lbar^2 on the joint, along unit(e_{k+1} - e_k)
                    dx = e[k + 1, 0] - e[k, 0]
                    dy = e[k + 1, 1] - e[k, 1]
                    dz = e[k + 1, 2] - e[k, 2]
                    dn = math.sqrt(dx * dx + dy * dy + dz * dz)
                    gamma = 2.0 * math.asin(min(0.5 * dn, 1.0))
                    scale = 8.0 * EI / (lbar * lbar)
                    scale *= gamma / dn if dn > 1e-300 else 1.0
                    F[k + 1, 0] += scale * dx
                    F[k + 1, 1] += scale * dy
                    F[k + 1, 2] += scale * dz
                else:
                    # restoring moment (E I / lbar) gamma about e_k x e_{k+1}: + on link k, - on k+1
                    wx, wy, wz, sn, gamma = kink(e, k)
                    scale = EI / lbar
                    scale *= gamma / sn if sn > 1e-300 else 1.0
                    Mom[k, 0] += scale * wx
                    Mom[k, 1] += scale * wy
                    Mom[k, 2] += scale * wz
                    Mom[k + 1, 0] -= scale * wx
                    Mom[k + 1, 1] -= scale * wy
                    Mom[k + 1, 2] -= scale * wz

        # structural (Kelvin-Voigt) damping of the hose wall, c_b dkappa/dt lumped at every inner
        # joint: the moment (c_b / lbar) (w_k+1 - w_k) on link k and the opposite on link k+1, w the
        # links' angular velocities perpendicular to their axes (e x de/dt). Each link is a line
        # without axial inertia or torsion, so only the part of a moment perpendicular to its axis
        # acts on it (the partial angular velocity [0,1,0] has an axial part -s2 e: the frame's
        # twist, which is no motion of the line). It dissipates
        # sum (c_b / lbar) |w_k+1 - w_k|^2.
        # (at rest, the still case, it adds zeros: v = +0 everywhere, and a moment that starts at
        # +0 and only sums is never -0, so adding a signed zero leaves its bits)
        cb = ps[PS_BEND_DAMP]
        if full and cb > 0.0:
            ox, oy, oz = link_omega(0, lam, e, v)
            for k in range(n - 1):
                px, py, pz = link_omega(k + 1, lam, e, v)
                cd = cb / (0.5 * (l[k] + l[k + 1]))
                mx = cd * (px - ox)
                my = cd * (py - oy)
                mz = cd * (pz - oz)
                ak = mx * e[k, 0] + my * e[k, 1] + mz * e[k, 2]
                ak1 = mx * e[k + 1, 0] + my * e[k + 1, 1] + mz * e[k + 1, 2]
                Mom[k, 0] += mx - ak * e[k, 0]
                Mom[k, 1] += my - ak * e[k, 1]
                Mom[k, 2] += mz - ak * e[k, 2]
                Mom[k + 1, 0] -= mx - ak1 * e[k + 1, 0]
                Mom[k + 1, 1] -= my - ak1 * e[k + 1, 1]
                Mom[k + 1, 2] -= mz - ak1 * e[k + 1, 2]
                ox, oy, oz = px, py, pz

    return joint_forces_stretched


#: :func:`_joint_forces`' function of every case, and of level flight in still air (:func:`still_level`)
joint_forces_stretched, joint_forces_still = _joint_forces(True), _joint_forces(False)


@njit(**JIT_NO_ALLOC)
def rotational_terms(qd, J, n, cs, Mom, tau):
    """tau (n,2): generalized forces of each link's own rotation - its inertia's velocity terms
    and the moments on it, through the partial angular velocities [0,1,0], [s1,0,c1]."""
    for k in range(n):
        c1, s1, c2, s2 = cs[k, 0], cs[k, 1], cs[k, 2], cs[k, 3]
        d1 = qd[2 * k]
        d2 = qd[2 * k + 1]
        # link inertia J (I - e e^T) in S_p: T_rot = J/2 (c2^2 d1^2 + d2^2) (paper Eq. 18); the
        # drogue's inertia is transverse inertia of the last link (in J[n-1], docs/model.md §2)
        tau[k, 0] = 2.0 * J[k] * c2 * s2 * d1 * d2 + Mom[k, 1]
        tau[k, 1] = -J[k] * c2 * s2 * d1 * d1 + s1 * Mom[k, 0] + c1 * Mom[k, 2]


@njit(**JIT_NO_ALLOC_INLINE)
def env_at(t, env, gust, scratch, full=True):
    """``env`` copied into ``scratch`` with, when every point sees the same gust (``uniform``),
    the gust at time t looked up once (air_velocity then reads it instead of the record);
    returns ``scratch`` (call it from kernels without numba's runtime only: an array returned
    across the runtime boundary is not reference-counted; elsewhere use :func:`fill_env`).
    ``full``: as :func:`still_air_velocity`'s."""
    if full:
        fill_env(t, env, gust, scratch)
    else:
        fill_env_still(t, env, gust, scratch)
    return scratch


def _fill_env(full):
    """:func:`fill_env` compiled for every case (``full``) or for level flight in still air only
    (:func:`fill_env_still`; ``full`` as :func:`still_air_velocity`'s)."""

    @njit(**JIT_NO_ALLOC)
    def fill_env(t, env, gust, scratch):
        """:func:`env_at` without the return value."""
        for i in range(ENV_G_NOW):
            scratch[i] = env[i]
        for i in range(ENV_BW, ENV_SIZE):
            scratch[i] = env[i]
        scratch[ENV_G_NOW] = 0.0
        t_gust = t
        if full and env[ENV_M_ON] != 0.0:
            # the frame terms at t; the air's speed, the wake's circulation and the gust record's
            # time (the path flown over V_0: the turbulence is a frozen field along the tanker's path)
            V, wake_factor = frame_terms(t, env, ENV_SIZE, scratch)
            scratch[ENV_V] = V
            scratch[ENV_WAKE + 1] = env[ENV_WAKE + 1] * wake_factor
            t_gust = scratch[ENV_M_T]
        if env[ENV_FROZEN] == 0.0:
            if full:
                gu, gv, gw = gust_at(t_gust, env[ENV_G_T0], env[ENV_G_DT], gust, env[ENV_T_ON], env[ENV_T_OFF],
                                     env[ENV_G_CUBIC] != 0.0)
            else:
                gu, gv, gw = 0.0, 0.0, 0.0  # gust_at's outside its window
            scratch[ENV_GU] = gu
            scratch[ENV_GV] = gv
            scratch[ENV_GW] = gw
            scratch[ENV_G_NOW] = 1.0

    return fill_env


#: :func:`_fill_env`'s function of every case, and of level flight in still air (:func:`still_level`)
fill_env, fill_env_still = _fill_env(True), _fill_env(False)


@njit(**JIT_NO_ALLOC)
def chain_positions(l, e, r):
    """Joint positions r (n+1, 3) [m] in S_p from the link directions e: ``r_k = sum_{j<=k} l_j e_j``
    (row 0 is the tow point), summed in the order of :func:`joint_kinematics` and
    :func:`drogue_from_frames`, so every path gives the same bits."""
    for i in range(3):
        r[0, i] = 0.0
    for k in range(l.shape[0]):
        for i in range(3):
            r[k + 1, i] = r[k, i] + l[k] * e[k, i]


@njit(**JIT_NO_ALLOC)
def drogue_from_frames(l, e):
    """Drogue (joint n) lateral and vertical position [m] from the link directions e: the one
    definition of the drogue position from a state (after :func:`link_frames`)."""
    y = 0.0
    z = 0.0
    for k in range(l.shape[0]):
        y += l[k] * e[k, 1]
        z += l[k] * e[k, 2]
    return y, z
