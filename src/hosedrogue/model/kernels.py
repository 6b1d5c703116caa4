"""The numerical core: kinematics, forces and Kane's equations of the link chain (numba).

Everything here is a pure function of float64 arrays; no Python objects, no I/O, no validation
(that is :mod:`hosedrogue.model.system`'s job). Notation follows ``MODEL.md``:

* state ``x = [q, qd]``, ``q = [th_11, th_12, ..., th_n1, th_n2]`` (pitch down, yaw left), so
  link ``k`` (0-based here) has pitch ``q[2k]`` and yaw ``q[2k+1]``;
* ``e_k = [-c1 c2, -s2, s1 c2]`` points aft along link k; ``a_k = de/dth1``, ``b_k = de/dth2``;
* joint 0 is the tow point (origin of S_p); joint k+1 is the aft end of link k and carries the
  lumped mass ``M[k]`` (the drogue's mass is included in ``M[n-1]``).

Kane's equations give ``H(q) qdd = Q(q, qd, t, u)``. With masses lumped at joints and
``dV_i/dqd_{j}`` zero for ``j > i`` every generalized force is a dot product of a link's partial
velocity with a *suffix sum* of joint forces, so ``Q`` costs O(n). ``H`` is dense: its entry for
links i, j is ``S_max(i,j) l_i l_j g_i . g_j`` with ``S_k`` the mass at and aft of joint k+1.

Layout of the scalar arrays (indices are the module constants below):

``ps`` (model): gravity, density, airspeed, outer diameter, c_t, c_n, drogue area x c_d, E I,
bending mode (0 off, 1 paper, 2 moment), drogue inertia.
``env`` (air): airspeed, frozen flag, gust window on/off, gust record t0/dt, then the 6 wake
scalars of :func:`hosedrogue.environment.wake.wake_scalars`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..environment.turbulence import gust_at
from ..environment.wake import wake_velocity

# ps layout
PS_G, PS_RHO, PS_V, PS_DO, PS_CT, PS_CN, PS_DROGUE_CDA, PS_EI, PS_BENDING, PS_JD = range(10)
PS_SIZE = 10
BENDING_OFF, BENDING_PAPER, BENDING_MOMENT = 0, 1, 2

# env layout
ENV_V, ENV_FROZEN, ENV_T_ON, ENV_T_OFF, ENV_G_T0, ENV_G_DT = range(6)
ENV_WAKE = 6
ENV_SIZE = 12

# status codes of the integrators
OK, NONFINITE, YAW_LIMIT, STEP_LIMIT = 0, 1, 2, 3


@njit(cache=True)
def air_velocity(px, py, pz, t, env, gust):
    """Air velocity [m/s] in S_p at point (px, py, pz) [m, relative to the tow point], time t [s]."""
    V = env[ENV_V]
    wy, wz = wake_velocity(py, pz, env[ENV_WAKE:ENV_WAKE + 6])
    t_eff = t
    if env[ENV_FROZEN] != 0.0:
        # a point a distance -px behind the tow point meets the frozen gust field -px/V later
        t_eff = t + px / V
    gu, gv, gw = gust_at(t_eff, env[ENV_G_T0], env[ENV_G_DT], gust, env[ENV_T_ON], env[ENV_T_OFF])
    return -V + gu, wy + gv, wz + gw


@njit(cache=True)
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


@njit(cache=True)
def joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, xi):
    """Joint positions r, velocities v (n+1,3; row 0 = tow point) and the velocity-product part of
    the joint accelerations xi (n+1,3): a_k = sum_j l_j (a_j qdd_j1 + b_j qdd_j2) + xi_k."""
    for i in range(3):
        r[0, i] = 0.0
        v[0, i] = 0.0
        xi[0, i] = 0.0
    for k in range(n):
        d1 = qd[2 * k]
        d2 = qd[2 * k + 1]
        c1, s1, c2, s2 = cs[k, 0], cs[k, 1], cs[k, 2], cs[k, 3]
        lk = l[k]
        p11 = d1 * d1 + d2 * d2
        p12 = 2.0 * d1 * d2
        # second derivative of e_k at zero qdd (paper Eq. 16)
        ex = c1 * c2 * p11 - s1 * s2 * p12
        ey = s2 * d2 * d2
        ez = -s1 * c2 * p11 - c1 * s2 * p12
        for i in range(3):
            r[k + 1, i] = r[k, i] + lk * e[k, i]
            v[k + 1, i] = v[k, i] + lk * (a[k, i] * d1 + b[k, i] * d2)
        xi[k + 1, 0] = xi[k, 0] + lk * ex
        xi[k + 1, 1] = xi[k, 1] + lk * ey
        xi[k + 1, 2] = xi[k, 2] + lk * ez


@njit(cache=True)
def joint_forces(t, u, l, M, ps, env, gust, n, e, r, v, F, Mom, drogue_drag):
    """External forces on every joint F (n+1,3; row 0 acts on the tow point), moments on every
    link Mom (n,3) and the drogue drag (3,). Gravity, link and drogue drag, control, bending."""
    g = ps[PS_G]
    rho = ps[PS_RHO]
    for k in range(n + 1):
        for i in range(3):
            F[k, i] = 0.0
    for k in range(n):
        for i in range(3):
            Mom[k, i] = 0.0
        F[k + 1, 2] += M[k] * g
    if rho > 0.0:
        q_ct = 0.5 * rho * math.pi * ps[PS_DO] * ps[PS_CT]
        q_cn = 0.5 * rho * math.pi * ps[PS_DO] * ps[PS_CN]
        for k in range(n):
            mx = 0.5 * (r[k, 0] + r[k + 1, 0])
            my = 0.5 * (r[k, 1] + r[k + 1, 1])
            mz = 0.5 * (r[k, 2] + r[k + 1, 2])
            wx, wy, wz = air_velocity(mx, my, mz, t, env, gust)
            vtx = 0.5 * (v[k, 0] + v[k + 1, 0]) - wx
            vty = 0.5 * (v[k, 1] + v[k + 1, 1]) - wy
            vtz = 0.5 * (v[k, 2] + v[k + 1, 2]) - wz
            # n_k = -e_k; tangential and normal parts of the relative velocity
            vt = -(vtx * e[k, 0] + vty * e[k, 1] + vtz * e[k, 2])
            vnx = vtx + vt * e[k, 0]
            vny = vty + vt * e[k, 1]
            vnz = vtz + vt * e[k, 2]
            vn = math.sqrt(vnx * vnx + vny * vny + vnz * vnz)
            ft = -q_ct * l[k] * vt * abs(vt)  # along n_k = -e_k
            fn = -q_cn * l[k] * vn
            dx = -ft * e[k, 0] + fn * vnx
            dy = -ft * e[k, 1] + fn * vny
            dz = -ft * e[k, 2] + fn * vnz
            F[k, 0] += 0.5 * dx
            F[k, 1] += 0.5 * dy
            F[k, 2] += 0.5 * dz
            F[k + 1, 0] += 0.5 * dx
            F[k + 1, 1] += 0.5 * dy
            F[k + 1, 2] += 0.5 * dz
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
                wx = e[k, 1] * e[k + 1, 2] - e[k, 2] * e[k + 1, 1]
                wy = e[k, 2] * e[k + 1, 0] - e[k, 0] * e[k + 1, 2]
                wz = e[k, 0] * e[k + 1, 1] - e[k, 1] * e[k + 1, 0]
                sn = math.sqrt(wx * wx + wy * wy + wz * wz)
                cn = e[k, 0] * e[k + 1, 0] + e[k, 1] * e[k + 1, 1] + e[k, 2] * e[k + 1, 2]
                gamma = math.atan2(sn, cn)
                scale = EI / lbar
                scale *= gamma / sn if sn > 1e-300 else 1.0
                Mom[k, 0] += scale * wx
                Mom[k, 1] += scale * wy
                Mom[k, 2] += scale * wz
                Mom[k + 1, 0] -= scale * wx
                Mom[k + 1, 1] -= scale * wy
                Mom[k + 1, 2] -= scale * wz


@njit(cache=True)
def generalized_forces(qd, l, M, J, ps, n, a, b, cs, xi, F, Mom, G, Q):
    """Q (2n): generalized active forces minus velocity-product inertia terms.

    G (n+1,3) receives the suffix sums G_k = sum_{m>=k} (F_m - M_m xi_m) over joints 1..n.
    """
    for i in range(3):
        G[n, i] = 0.0
    for k in range(n - 1, -1, -1):
        for i in range(3):
            G[k, i] = G[k + 1, i] + F[k + 1, i] - M[k] * xi[k + 1, i]
    for k in range(n):
        lk = l[k]
        Q[2 * k] = lk * (a[k, 0] * G[k, 0] + a[k, 1] * G[k, 1] + a[k, 2] * G[k, 2])
        Q[2 * k + 1] = lk * (b[k, 0] * G[k, 0] + b[k, 1] * G[k, 1] + b[k, 2] * G[k, 2])
        c1, s1, c2, s2 = cs[k, 0], cs[k, 1], cs[k, 2], cs[k, 3]
        d1 = qd[2 * k]
        d2 = qd[2 * k + 1]
        # link rotational inertia J (I - e e^T) in S_p: T_rot = J/2 (c2^2 d1^2 + d2^2) (Eq. 18)
        Q[2 * k] += 2.0 * J[k] * c2 * s2 * d1 * d2
        Q[2 * k + 1] -= J[k] * c2 * s2 * d1 * d1
        # moments through the partial angular velocities [0,1,0] and [s1,0,c1] (Eqs. 13-14)
        Q[2 * k] += Mom[k, 1]
        Q[2 * k + 1] += s1 * Mom[k, 0] + c1 * Mom[k, 2]
    # the drogue's isotropic inertia Jd I on link n has constant coefficients: no velocity terms


@njit(cache=True)
def mass_matrix(l, S, J, ps, n, a, b, cs, H):
    """H (2n,2n): S_max(i,j) l_i l_j g_i . g_j plus the links' and drogue's rotational inertia."""
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
    H[2 * n - 2, 2 * n - 2] += ps[PS_JD]
    H[2 * n - 1, 2 * n - 1] += ps[PS_JD]


@njit(cache=True)
def evaluate(t, x, u, l, M, S, J, ps, env, gust, qdd, r, v, drogue_drag, tow_force):
    """Accelerations qdd (2n) and outputs: joint positions r and velocities v (n+1,3), drogue
    drag (3) and the force the hose exerts on the tow point (3), all in S_p."""
    n = l.shape[0]
    q = x[: 2 * n]
    qd = x[2 * n:]
    e = np.empty((n, 3))
    a = np.empty((n, 3))
    b = np.empty((n, 3))
    cs = np.empty((n, 4))
    xi = np.empty((n + 1, 3))
    F = np.empty((n + 1, 3))
    Mom = np.empty((n, 3))
    G = np.empty((n + 1, 3))
    Q = np.empty(2 * n)
    H = np.empty((2 * n, 2 * n))
    link_frames(q, n, e, a, b, cs)
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, xi)
    joint_forces(t, u, l, M, ps, env, gust, n, e, r, v, F, Mom, drogue_drag)
    generalized_forces(qd, l, M, J, ps, n, a, b, cs, xi, F, Mom, G, Q)
    mass_matrix(l, S, J, ps, n, a, b, cs, H)
    sol = np.linalg.solve(H, Q)
    for i in range(2 * n):
        qdd[i] = sol[i]
    # force on the tow point = half of link 1's drag + sum of joint forces - sum of m a
    for i in range(3):
        acc = F[0, i] + G[0, i]
        for k in range(n):
            acc -= S[k] * l[k] * (a[k, i] * qdd[2 * k] + b[k, i] * qdd[2 * k + 1])
        tow_force[i] = acc


@njit(cache=True)
def rhs(t, x, u, l, M, S, J, ps, env, gust, dx):
    """State derivative dx (4n) of x = [q, qd]."""
    n = l.shape[0]
    qdd = np.empty(2 * n)
    r = np.empty((n + 1, 3))
    v = np.empty((n + 1, 3))
    dd = np.empty(3)
    tf = np.empty(3)
    evaluate(t, x, u, l, M, S, J, ps, env, gust, qdd, r, v, dd, tf)
    for i in range(2 * n):
        dx[i] = x[2 * n + i]
        dx[2 * n + i] = qdd[i]


@njit(cache=True)
def static_residual(q, l, M, J, ps, env, gust, t, Q):
    """Generalized forces at rest (qd = 0, u = 0): zero exactly at an equilibrium."""
    n = l.shape[0]
    qd = np.zeros(2 * n)
    u = np.zeros(2)
    e = np.empty((n, 3))
    a = np.empty((n, 3))
    b = np.empty((n, 3))
    cs = np.empty((n, 4))
    r = np.empty((n + 1, 3))
    v = np.empty((n + 1, 3))
    xi = np.empty((n + 1, 3))
    F = np.empty((n + 1, 3))
    Mom = np.empty((n, 3))
    G = np.empty((n + 1, 3))
    dd = np.empty(3)
    link_frames(q, n, e, a, b, cs)
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, xi)
    joint_forces(t, u, l, M, ps, env, gust, n, e, r, v, F, Mom, dd)
    generalized_forces(qd, l, M, J, ps, n, a, b, cs, xi, F, Mom, G, Q)


@njit(cache=True)
def energy(x, l, M, J, ps):
    """(kinetic, potential) energy [J]; potential = gravity (z down) + bending-moment elastic
    energy (the ``moment`` option is the conservative one)."""
    n = l.shape[0]
    q = x[: 2 * n]
    qd = x[2 * n:]
    e = np.empty((n, 3))
    a = np.empty((n, 3))
    b = np.empty((n, 3))
    cs = np.empty((n, 4))
    r = np.empty((n + 1, 3))
    v = np.empty((n + 1, 3))
    xi = np.empty((n + 1, 3))
    link_frames(q, n, e, a, b, cs)
    joint_kinematics(q, qd, l, n, e, a, b, cs, r, v, xi)
    g = ps[PS_G]
    T = 0.0
    U = 0.0
    for k in range(n):
        vv = v[k + 1, 0] ** 2 + v[k + 1, 1] ** 2 + v[k + 1, 2] ** 2
        T += 0.5 * M[k] * vv
        c2 = cs[k, 2]
        d1 = qd[2 * k]
        d2 = qd[2 * k + 1]
        T += 0.5 * J[k] * (c2 * c2 * d1 * d1 + d2 * d2)
        U -= M[k] * g * r[k + 1, 2]
    T += 0.5 * ps[PS_JD] * (qd[2 * n - 2] ** 2 + qd[2 * n - 1] ** 2)
    if ps[PS_BENDING] == BENDING_MOMENT:
        for k in range(n - 1):
            wx = e[k, 1] * e[k + 1, 2] - e[k, 2] * e[k + 1, 1]
            wy = e[k, 2] * e[k + 1, 0] - e[k, 0] * e[k + 1, 2]
            wz = e[k, 0] * e[k + 1, 1] - e[k, 1] * e[k + 1, 0]
            sn = math.sqrt(wx * wx + wy * wy + wz * wz)
            cn = e[k, 0] * e[k + 1, 0] + e[k, 1] * e[k + 1, 1] + e[k, 2] * e[k + 1, 2]
            gamma = math.atan2(sn, cn)
            U += 0.5 * ps[PS_EI] / (0.5 * (l[k] + l[k + 1])) * gamma * gamma
    return T, U


@njit(cache=True)
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
