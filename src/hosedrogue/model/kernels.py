"""The numerical core: kinematics, forces and Kane's equations of the link chain (numba).

Everything here is a pure function of float64 arrays; no Python objects, no I/O, no validation
(that is :mod:`hosedrogue.model.system`'s job). Notation follows ``docs/model.md``:

* state ``x = [q, qd]``, ``q = [th_11, th_12, ..., th_n1, th_n2]`` (pitch down, yaw left), so
  link ``k`` (0-based here) has pitch ``q[2k]`` and yaw ``q[2k+1]``;
* ``e_k = [-c1 c2, -s2, s1 c2]`` points aft along link k; ``a_k = de/dth1``, ``b_k = de/dth2``;
* joint 0 is the tow point (origin of S_p); joint k+1 is the aft end of link k and carries the
  lumped mass ``M[k]`` (the drogue's mass is included in ``M[n-1]``). Which share of each link's
  mass a joint carries (``aft`` or ``split`` lumping) is decided in ``model/system.py``; the
  kernels only see the joint masses.

Kane's equations give ``H(q) qdd = Q(q, qd, t, u)``. With masses lumped at joints and
``dV_i/dqd_{j}`` zero for ``j > i`` every generalized force is a dot product of a link's partial
velocity with a *suffix sum* of joint forces, so ``Q`` costs O(n). ``H`` is dense (its entry for
links i, j is ``S_max(i,j) l_i l_j g_i . g_j`` with ``S_k`` the mass at and aft of joint k+1), but
the time integrators never form it: :func:`chain_forward_dynamics` solves for ``qdd`` in O(n) by
an articulated-body recursion. The dense path (:func:`accelerations_dense`) stays as the
reference the recursion is tested against.

The scalar arrays ``ps`` (the model's) and ``env`` (the air's; with the tanker's motion,
:mod:`hosedrogue.model.frame`) are laid out in :mod:`hosedrogue.model.layout` (``PS_*``,
``ENV_*``). The drogue's rotational inertia is the last link's transverse inertia (in
``J[n-1]``, docs/model.md §2).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..environment.bow_wave import bow_wave_velocity
from ..environment.turbulence import gust_at
from ..environment.wake import wake_velocity

from ..jit import JIT, JIT_NO_ALLOC  # noqa: E402 - the one set of compilation options
from .frame import frame_loads, frame_terms, frame_wind
from .layout import (  # the ps and env tables, their codes and the status codes, declared there
    BENDING_MOMENT, BENDING_OFF, BENDING_PAPER, DRAG_GAUSS2, DRAG_MIDPOINT, ENV_BW, ENV_BW_LEN, ENV_BW_Q, ENV_BW_X,
    ENV_BW_Y, ENV_BW_Z, ENV_FROZEN, ENV_GU, ENV_GV, ENV_GW, ENV_G_CUBIC, ENV_G_DT, ENV_G_NOW, ENV_G_T0, ENV_M_ON,
    ENV_M_T, ENV_M_V0, ENV_SIZE, ENV_T_OFF, ENV_T_ON, ENV_V, ENV_WAKE, NONFINITE, OK, PS_BENDING, PS_BEND_DAMP,
    PS_CA, PS_CN, PS_CT, PS_DO, PS_DRAG_QUAD, PS_DROGUE_CDA, PS_EA, PS_EI, PS_G, PS_M_TOW, PS_RHO, PS_SIZE, PS_V,
    STAGE_LIMIT, STEP_LIMIT, YAW_LIMIT,
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


@njit(**JIT_NO_ALLOC)
def still_air_velocity(px, py, pz, t, env, gust):
    """:func:`air_velocity` without the bow wave: free stream, wake and gust [m/s] (and, when the
    tanker manoeuvres, the air's rotation relative to its axes, :func:`frame.frame_wind`)."""
    V = env[ENV_V]
    wy, wz = wake_velocity(py, pz, env, ENV_WAKE)
    if env[ENV_G_NOW] != 0.0:
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
    if env[ENV_M_ON] != 0.0:
        fx, fy, fz = frame_wind(px, py, pz, env)
        return wx + fx, wy + fy, wz + fz
    return wx, wy, wz


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


@njit(**JIT_NO_ALLOC)
def kink(e, k):
    """Bend at joint k+1 between links k and k+1: (e_k x e_{k+1}) components, its length
    sin(gamma), and the angle gamma (atan2, accurate near 0)."""
    wx = e[k, 1] * e[k + 1, 2] - e[k, 2] * e[k + 1, 1]
    wy = e[k, 2] * e[k + 1, 0] - e[k, 0] * e[k + 1, 2]
    wz = e[k, 0] * e[k + 1, 1] - e[k, 1] * e[k + 1, 0]
    sn = math.sqrt(wx * wx + wy * wy + wz * wz)
    cn = e[k, 0] * e[k + 1, 0] + e[k, 1] * e[k + 1, 1] + e[k, 2] * e[k + 1, 2]
    return wx, wy, wz, sn, math.atan2(sn, cn)


@njit(**JIT_NO_ALLOC)
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


@njit(**JIT_NO_ALLOC)
def link_omega(k, l, e, v):
    """Angular velocity of link k [rad/s] from its end velocities: omega_k = e_k x de_k/dt with
    de_k/dt = (V_k+1 - V_k) / l_k (omega_k is perpendicular to e_k, docs/model.md §1)."""
    dx = (v[k + 1, 0] - v[k, 0]) / l[k]
    dy = (v[k + 1, 1] - v[k, 1]) / l[k]
    dz = (v[k + 1, 2] - v[k, 2]) / l[k]
    return (e[k, 1] * dz - e[k, 2] * dy, e[k, 2] * dx - e[k, 0] * dz, e[k, 0] * dy - e[k, 1] * dx)


@njit(**JIT_NO_ALLOC)
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


@njit(**JIT_NO_ALLOC)
def joint_forces(t, u, l, M, ps, env, gust, n, e, r, v, F, Mom, drogue_drag):
    """External forces on every joint F (n+1,3; row 0 acts on the tow point), moments on every
    link Mom (n,3) and the drogue drag (3,). Gravity, link and drogue drag, control, bending,
    structural bending damping. When the tanker manoeuvres (``env[ENV_M_ON]``) gravity is left
    to :func:`frame.frame_loads`, with the other apparent forces."""
    joint_forces_stretched(t, u, l, l, M, ps, env, gust, n, e, r, v, F, Mom, drogue_drag)


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
                if uniform:
                    wy, wz = wake_velocity(py, pz, env, ENV_WAKE)
                    wx, wy, wz = ux, wy + gv, wz + gw
                    if not level:
                        fx, fy, fz = frame_wind(px, py, pz, env)
                        wx, wy, wz = wx + fx, wy + fy, wz + fz
                    if env[ENV_BW] != 0.0:
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
        wx, wy, wz = air_velocity(r[n, 0], r[n, 1], r[n, 2], t, env, gust)
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
    cb = ps[PS_BEND_DAMP]
    if cb > 0.0:
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


@njit(**JIT)
def generalized_forces(l, M, n, a, b, c, F, tau, G, Q):
    """Q (2n): generalized active forces minus velocity-product inertia terms (dense path).

    G (n+1,3) receives the suffix sums G_k = sum_{m>=k} (F_m - M_m xi_m) over joints 1..n, with
    xi_m = sum_{i<m} c_i the velocity-product part of joint m's acceleration.
    """
    xi = np.zeros((n + 1, 3))
    for k in range(n):
        for i in range(3):
            xi[k + 1, i] = xi[k, i] + c[k, i]
    for i in range(3):
        G[n, i] = 0.0
    for k in range(n - 1, -1, -1):
        for i in range(3):
            G[k, i] = G[k + 1, i] + F[k + 1, i] - M[k] * xi[k + 1, i]
    for k in range(n):
        lk = l[k]
        Q[2 * k] = lk * (a[k, 0] * G[k, 0] + a[k, 1] * G[k, 1] + a[k, 2] * G[k, 2]) + tau[k, 0]
        Q[2 * k + 1] = lk * (b[k, 0] * G[k, 0] + b[k, 1] * G[k, 1] + b[k, 2] * G[k, 2]) + tau[k, 1]


@njit(**JIT_NO_ALLOC)
def mass_matrix(l, S, J, ps, n, a, b, cs, H):
    """H (2n,2n): S_max(i,j) l_i l_j g_i . g_j plus the links' rotational inertia (the drogue's is
    the last link's, ``J[n-1]``)."""
    for j in range(n):
        for i in range(j, n):
            s = S[i] * l[i] * l[j]
            aa = a[j, 0] * a[i, 0] + a[j, 1] * a[i, 1] + a[j, 2] * a[i, 2]
            ab = a[j, 0] * b[i, 0] + a[j, 1] * b[i, 1] + a[j, 2] * b[i, 2]
            ba = b[j, 0] * a[i, 0] + b[j, 1] * a[i, 1] + b[j, 2] * a[i, 2]
            bb = b[j, 0] * b[i, 0] + b[j, 1] * b[i, 1] + b[j, 2] * b[i, 2]
            H[2 * j, 2 * i] = s * aa
            H[2 * j, 2 * i + 1] = s * ab
            H[2 * j + 1, 2 * i] = s * ba
            H[2 * j + 1, 2 * i + 1] = s * bb
            H[2 * i, 2 * j] = s * aa
            H[2 * i + 1, 2 * j] = s * ab
            H[2 * i, 2 * j + 1] = s * ba
            H[2 * i + 1, 2 * j + 1] = s * bb
    for k in range(n):
        c2 = cs[k, 2]
        H[2 * k, 2 * k] += J[k] * c2 * c2
        H[2 * k + 1, 2 * k + 1] += J[k]


def make_workspace(n):
    """Scratch arrays for one chain of n links, allocated once per run (not per evaluation).

    Parameters
    ----------
    n : int
        Number of links [-].

    Returns
    -------
    tuple of numpy.ndarray
        The workspace; the comment on each slot names what it holds (frames, joint positions [m]
        and velocities [m/s], forces [N], accelerations, ...).
    """
    return (
        np.empty((n, 3)),  # 0 e
        np.empty((n, 3)),  # 1 a
        np.empty((n, 3)),  # 2 b
        np.empty((n, 4)),  # 3 cs
        np.empty((n + 1, 3)),  # 4 r
        np.empty((n + 1, 3)),  # 5 v
        np.empty((n, 3)),  # 6 c
        np.empty((n + 1, 3)),  # 7 F
        np.empty((n, 3)),  # 8 Mom
        np.empty((n, 2)),  # 9 tau
        np.empty((n, 6)),  # 10 U (3x2, row-major)
        np.empty((n, 4)),  # 11 Dinv (2x2, row-major)
        np.empty((n, 2)),  # 12 right-hand sides of the joint equations
        np.empty(3),  # 13 drogue drag
        np.empty(3),  # 14 tow force
        np.empty(2 * n),  # 15 qdd
        np.empty(ENV_SIZE),  # 16 this evaluation's copy of env (with the gust at its time)
        np.empty(1),  # 17 exit tension [N] (exit_tension)
    )


make_workspace_jit = njit(**JIT)(make_workspace)


@njit(**JIT_NO_ALLOC)
def chain_forward_dynamics(l, M, J, n, a, b, cs, c, F, tau, U, Dinv, rv, qdd, tow_force):
    """Solve H qdd = Q in O(n) by an articulated-body recursion for this chain.

    The part of the chain aft of joint k, cut through link k, resists the acceleration A of
    joint k with the force ``IA_k A + beta_k``. Backward pass: from the drogue, fold each
    link's two joint equations into (IA, beta) of the joint ahead of it. Forward pass: from the
    tow point (A_0 = 0), solve each link's 2x2 joint equations. Returns the force the hose
    exerts on the tow point, ``F_0 - (IA_1 A_0 + beta_1)`` with A_0 = 0.
    """
    # IA (symmetric 3x3, stored full) and beta of the subsystem aft of the current joint
    IA00 = IA01 = IA02 = IA11 = IA12 = IA22 = 0.0
    be0 = be1 = be2 = 0.0
    for k in range(n - 1, -1, -1):
        # add the lumped mass and external force of joint k+1
        IA00 += M[k]
        IA11 += M[k]
        IA22 += M[k]
        be0 -= F[k + 1, 0]
        be1 -= F[k + 1, 1]
        be2 -= F[k + 1, 2]
        lk = l[k]
        g0x, g0y, g0z = lk * a[k, 0], lk * a[k, 1], lk * a[k, 2]
        g1x, g1y, g1z = lk * b[k, 0], lk * b[k, 1], lk * b[k, 2]
        # U = IA G (3x2)
        u00 = IA00 * g0x + IA01 * g0y + IA02 * g0z
        u10 = IA01 * g0x + IA11 * g0y + IA12 * g0z
        u20 = IA02 * g0x + IA12 * g0y + IA22 * g0z
        u01 = IA00 * g1x + IA01 * g1y + IA02 * g1z
        u11 = IA01 * g1x + IA11 * g1y + IA12 * g1z
        u21 = IA02 * g1x + IA12 * g1y + IA22 * g1z
        # D = G^T IA G + R (R: the link's rotational inertia; the last link's includes the drogue's)
        c2 = cs[k, 2]
        r0 = J[k] * c2 * c2
        r1 = J[k]
        d00 = g0x * u00 + g0y * u10 + g0z * u20 + r0
        d01 = g0x * u01 + g0y * u11 + g0z * u21
        d11 = g1x * u01 + g1y * u11 + g1z * u21 + r1
        det = d00 * d11 - d01 * d01
        i00 = d11 / det
        i01 = -d01 / det
        i11 = d00 / det
        # right-hand side of the joint equations without the fore joint's acceleration
        h0 = tau[k, 0] - (g0x * be0 + g0y * be1 + g0z * be2)
        h1 = tau[k, 1] - (g1x * be0 + g1y * be1 + g1z * be2)
        U[k, 0], U[k, 1], U[k, 2], U[k, 3], U[k, 4], U[k, 5] = u00, u01, u10, u11, u20, u21
        Dinv[k, 0], Dinv[k, 1], Dinv[k, 2], Dinv[k, 3] = i00, i01, i01, i11
        rv[k, 0] = h0
        rv[k, 1] = h1
        # W = U Dinv (3x2)
        w00 = u00 * i00 + u01 * i01
        w01 = u00 * i01 + u01 * i11
        w10 = u10 * i00 + u11 * i01
        w11 = u10 * i01 + u11 * i11
        w20 = u20 * i00 + u21 * i01
        w21 = u20 * i01 + u21 * i11
        # articulated inertia seen through the link: IA - U Dinv U^T
        IA00 -= w00 * u00 + w01 * u01
        IA01 -= w00 * u10 + w01 * u11
        IA02 -= w00 * u20 + w01 * u21
        IA11 -= w10 * u10 + w11 * u11
        IA12 -= w10 * u20 + w11 * u21
        IA22 -= w20 * u20 + w21 * u21
        # bias seen through the link: IA~ c + U Dinv h + beta
        cx, cy, cz = c[k, 0], c[k, 1], c[k, 2]
        be0 += IA00 * cx + IA01 * cy + IA02 * cz + w00 * h0 + w01 * h1
        be1 += IA01 * cx + IA11 * cy + IA12 * cz + w10 * h0 + w11 * h1
        be2 += IA02 * cx + IA12 * cy + IA22 * cz + w20 * h0 + w21 * h1
    tow_force[0] = F[0, 0] - be0
    tow_force[1] = F[0, 1] - be1
    tow_force[2] = F[0, 2] - be2
    Ax = Ay = Az = 0.0
    for k in range(n):
        px = Ax + c[k, 0]
        py = Ay + c[k, 1]
        pz = Az + c[k, 2]
        h0 = rv[k, 0] - (U[k, 0] * px + U[k, 2] * py + U[k, 4] * pz)
        h1 = rv[k, 1] - (U[k, 1] * px + U[k, 3] * py + U[k, 5] * pz)
        q1 = Dinv[k, 0] * h0 + Dinv[k, 1] * h1
        q2 = Dinv[k, 2] * h0 + Dinv[k, 3] * h1
        qdd[2 * k] = q1
        qdd[2 * k + 1] = q2
        lk = l[k]
        Ax = px + lk * (a[k, 0] * q1 + b[k, 0] * q2)
        Ay = py + lk * (a[k, 1] * q1 + b[k, 1] * q2)
        Az = pz + lk * (a[k, 2] * q1 + b[k, 2] * q2)


@njit(**JIT_NO_ALLOC)
def loads(t, q, qd, u, l, M, J, ps, env, gust, ws):
    """Kinematics and loads of a state into the workspace: link frames ws[0:4], joint positions
    ws[4] and velocities ws[5], velocity-product accelerations ws[6], joint forces ws[7], link
    moments ws[8], rotational generalized forces ws[9], drogue drag ws[13]."""
    link_frames(q, l.shape[0], ws[0], ws[1], ws[2], ws[3])
    loads_given_frames(t, q, qd, u, l, M, J, ps, env, gust, ws)


@njit(**JIT_NO_ALLOC)
def env_at(t, env, gust, scratch):
    """``env`` copied into ``scratch`` with, when every point sees the same gust (``uniform``),
    the gust at time t looked up once (air_velocity then reads it instead of the record);
    returns ``scratch`` (call it from kernels without numba's runtime only: an array returned
    across the runtime boundary is not reference-counted; elsewhere use :func:`fill_env`)."""
    fill_env(t, env, gust, scratch)
    return scratch


@njit(**JIT_NO_ALLOC)
def fill_env(t, env, gust, scratch):
    """:func:`env_at` without the return value."""
    for i in range(ENV_G_NOW):
        scratch[i] = env[i]
    for i in range(ENV_BW, ENV_SIZE):
        scratch[i] = env[i]
    scratch[ENV_G_NOW] = 0.0
    t_gust = t
    if env[ENV_M_ON] != 0.0:
        # the frame terms at t; the air's speed, the wake's circulation and the gust record's
        # time (the path flown over V_0: the turbulence is a frozen field along the tanker's path)
        V, wake_factor = frame_terms(t, env, ENV_SIZE, scratch)
        scratch[ENV_V] = V
        scratch[ENV_WAKE + 1] = env[ENV_WAKE + 1] * wake_factor
        t_gust = scratch[ENV_M_T]
    if env[ENV_FROZEN] == 0.0:
        gu, gv, gw = gust_at(t_gust, env[ENV_G_T0], env[ENV_G_DT], gust, env[ENV_T_ON], env[ENV_T_OFF],
                             env[ENV_G_CUBIC] != 0.0)
        scratch[ENV_GU] = gu
        scratch[ENV_GV] = gv
        scratch[ENV_GW] = gw
        scratch[ENV_G_NOW] = 1.0


@njit(**JIT_NO_ALLOC)
def loads_given_frames(t, q, qd, u, l, M, J, ps, env, gust, ws):
    """:func:`loads` when the link frames ws[0:4] already hold those of q."""
    n = l.shape[0]
    e, a, b, cs, r, v, c, F, Mom, tau = ws[0], ws[1], ws[2], ws[3], ws[4], ws[5], ws[6], ws[7], ws[8], ws[9]
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, c)
    joint_forces(t, u, l, M, ps, env_at(t, env, gust, ws[16]), gust, n, e, r, v, F, Mom, ws[13])
    frame_loads(ps[PS_G], ps[PS_M_TOW], l, M, J, n, e, r, v, ws[16], F, Mom)
    rotational_terms(qd, J, n, cs, Mom, tau)


@njit(**JIT_NO_ALLOC)
def evaluate_ws(t, x, u, l, M, S, J, ps, env, gust, ws):
    """Accelerations (ws[15]) and outputs in the workspace: joint positions ws[4], velocities
    ws[5], drogue drag ws[13], tow-point force ws[14]. O(n)."""
    n = l.shape[0]
    loads(t, x[: 2 * n], x[2 * n:], u, l, M, J, ps, env, gust, ws)
    forward_dynamics_ws(l, M, J, ps, ws)


@njit(**JIT_NO_ALLOC)
def forward_dynamics_ws(l, M, J, ps, ws):
    """qdd (ws[15]), tow-point force (ws[14]) and exit tension (ws[17]) from the loads in the workspace."""
    n = l.shape[0]
    chain_forward_dynamics(l, M, J, n, ws[1], ws[2], ws[3], ws[6], ws[7], ws[9],
                           ws[10], ws[11], ws[12], ws[15], ws[14])
    ws[17][0] = exit_tension(l, ps, ws[0], ws[7], ws[14], n)
    # the mass lumped at the (fixed) tow point adds only its weight to the tow-point force
    ws[14][2] += ps[PS_M_TOW] * ps[PS_G]


@njit(**JIT_NO_ALLOC)
def exit_tension(l, ps, e, F, pull, n):
    """The exit tension T_0 [N]: the hose's pull on the exit (the recursion's tow-point force
    ``pull``, before the tow-point mass's weight) less the exit joint's own external load ``F[0]``,
    along the exit link e_0 - the generalized force of the hose on its free length L, so the
    force a hose drum holds. With the ``moment`` bending it includes the bending energy's
    dependence on L through lbar_0 = (l_0 + l_1) / 2 (``-dU/dL``, which keeps the varying-length
    model conservative); the one definition for the fixed-length and the engagement chains."""
    T = 0.0
    for i in range(3):
        T += (pull[i] - F[0, i]) * e[0, i]
    if ps[PS_BENDING] == BENDING_MOMENT and n > 1:
        lbar = 0.5 * (l[0] + l[1])
        gamma = kink(e, 0)[4]
        T += 0.25 * ps[PS_EI] * gamma * gamma / (lbar * lbar)
    return T


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


@njit(**JIT_NO_ALLOC)
def rhs_ws(t, x, u, l, M, S, J, ps, env, gust, ws, dx):
    """State derivative dx (4n) of x = [q, qd], using the workspace ws (no allocation)."""
    n = l.shape[0]
    evaluate_ws(t, x, u, l, M, S, J, ps, env, gust, ws)
    qdd = ws[15]
    for i in range(2 * n):
        dx[i] = x[2 * n + i]
        dx[2 * n + i] = qdd[i]


@njit(**JIT)
def rhs(t, x, u, l, M, S, J, ps, env, gust, dx):
    """State derivative dx (4n) of x = [q, qd] (allocates its own workspace)."""
    ws = make_workspace_jit(l.shape[0])
    rhs_ws(t, x, u, l, M, S, J, ps, env, gust, ws, dx)


@njit(**JIT)
def accelerations_dense(t, x, u, l, M, S, J, ps, env, gust):
    """qdd by forming the dense mass matrix and solving it (O(n^3)); the reference the
    recursion is tested against."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    loads(t, x[: 2 * n], x[2 * n:], u, l, M, J, ps, env, gust, ws)
    G = np.empty((n + 1, 3))
    Q = np.empty(2 * n)
    generalized_forces(l, M, n, ws[1], ws[2], ws[6], ws[7], ws[9], G, Q)
    H = np.empty((2 * n, 2 * n))
    mass_matrix(l, S, J, ps, n, ws[1], ws[2], ws[3], H)
    return np.linalg.solve(H, Q)


@njit(**JIT)
def static_residual(q, l, M, J, ps, env, gust, t, Q):
    """Generalized forces at rest (qd = 0, u = 0) into Q (2n): zero exactly at an equilibrium."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    loads(t, q, np.zeros(2 * n), np.zeros(2), l, M, J, ps, env, gust, ws)
    G = np.empty((n + 1, 3))
    generalized_forces(l, M, n, ws[1], ws[2], ws[6], ws[7], ws[9], G, Q)


@njit(**JIT)
def energy(x, l, M, J, ps):
    """(kinetic, potential) energy [J]; potential = gravity (z down) + bending-moment elastic
    energy (the ``moment`` option is the conservative one)."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    q = x[: 2 * n]
    qd = x[2 * n:]
    e, a, b, cs, r, v, c = ws[0], ws[1], ws[2], ws[3], ws[4], ws[5], ws[6]
    link_frames(q, n, e, a, b, cs)
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, c)
    T, Ug, Ub = chain_energy(n, l, M, J, ps, e, cs, r, v, qd)
    return T, Ug + Ub


@njit(**JIT_NO_ALLOC)
def chain_energy(n, l, M, J, ps, e, cs, r, v, qd):
    """(kinetic, gravity, bending) energy [J] of a chain whose frames, joint positions r and
    velocities v are given: the joint masses' translation, the links' transverse rotation
    ``J_k (c2^2 thd1^2 + thd2^2) / 2`` (the drogue's in the last link's), ``-sum M_k g z_k``
    and, for the ``moment`` bending, ``sum (E I / lbar) gamma^2 / 2``. The one energy of both
    chains (the engagement's velocities include the reel's L' e_0)."""
    g = ps[PS_G]
    T = 0.0
    Ug = 0.0
    for k in range(n):
        T += 0.5 * M[k] * (v[k + 1, 0] ** 2 + v[k + 1, 1] ** 2 + v[k + 1, 2] ** 2)
        c2 = cs[k, 2]
        T += 0.5 * J[k] * (c2 * c2 * qd[2 * k] ** 2 + qd[2 * k + 1] ** 2)
        Ug -= M[k] * g * r[k + 1, 2]
    Ub = 0.0
    if ps[PS_BENDING] == BENDING_MOMENT:
        for k in range(n - 1):
            gamma = kink(e, k)[4]
            Ub += 0.5 * ps[PS_EI] / (0.5 * (l[k] + l[k + 1])) * gamma * gamma
    return T, Ug, Ub


@njit(**JIT)
def mass_matrix_at(q, l, S, J, ps):
    """Dense H(q) for tests and linear analysis."""
    n = l.shape[0]
    e = np.empty((n, 3))
    a = np.empty((n, 3))
    b = np.empty((n, 3))
    cs = np.empty((n, 4))
    H = np.empty((2 * n, 2 * n))
    link_frames(q, n, e, a, b, cs)
    mass_matrix(l, S, J, ps, n, a, b, cs, H)
    return H


@njit(**JIT)
def outputs_series(ts, xs, us, l, M, S, J, ps, env, gust, joints, drogue_vel, drogue_drag, tow, tension):
    """Derived outputs at every saved state: joints (N, n+1, 3), drogue velocity, drogue drag
    and tow-point force (N, 3), exit tension (N,)."""
    n = l.shape[0]
    ws = make_workspace_jit(n)
    for i in range(ts.shape[0]):
        evaluate_ws(ts[i], xs[i], us[i], l, M, S, J, ps, env, gust, ws)
        joints[i] = ws[4]
        drogue_vel[i] = ws[5][n]
        drogue_drag[i] = ws[13]
        tow[i] = ws[14]
        tension[i] = ws[17][0]
