"""Time integrators (numba): fixed-step classical RK4 with an optional linear controller in the
loop, compiled end to end so a run is not dominated by Python overhead.

The closed-loop state is ``z = [x, xc, ua]``: the hose state ``x = [q, qd]`` (4n), the
controller state ``xc``, and - only when the actuator is rate-limited - the applied force ``ua``
(2). The controller reads the drogue's lateral and vertical offset from ``y_ref`` (plus sensor
noise) and commands ``u = Cc xc + Dc y`` [N], clipped to ``+-act[0:2]`` per axis. ``act`` is
``[max_hor_n, max_ver_n, max_rate_n_s, time_constant_s]``; with a finite rate the applied force
follows the command as ``ua' = clip((u - ua) / time_constant, -rate, rate)``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .kernels import (
    NONFINITE,
    OK,
    YAW_LIMIT,
    drogue_from_frames,
    forward_dynamics_ws,
    link_frames,
    loads_given_frames,
    make_workspace_jit,
)


@njit(cache=True)
def drogue_yz(x, l):
    """Drogue (joint n) lateral and vertical position [m] in S_p."""
    n = l.shape[0]
    y = 0.0
    z = 0.0
    for k in range(n):
        c2 = math.cos(x[2 * k + 1])
        y -= l[k] * math.sin(x[2 * k + 1])
        z += l[k] * math.sin(x[2 * k]) * c2
    return y, z


@njit(cache=True)
def noise_at(t, noise, noise_dt):
    """Zero-order-held sensor noise sample [m] (2,) at time t."""
    i = int(t / noise_dt)
    if i >= noise.shape[0]:
        i = noise.shape[0] - 1
    if i < 0:
        i = 0
    return noise[i, 0], noise[i, 1]


@njit(cache=True)
def control_law(t, z, nx, y, zz, Cc, Dc, y_ref, u_max, noise, noise_dt, u):
    """Commanded force u (2,) [N] for the drogue at lateral y, vertical zz [m] (saturated);
    returns the measured offsets."""
    ny, nz = noise_at(t, noise, noise_dt)
    m0 = y - y_ref[0] + ny
    m1 = zz - y_ref[1] + nz
    nc = Cc.shape[1]
    for i in range(2):
        acc = Dc[i, 0] * m0 + Dc[i, 1] * m1
        for j in range(nc):
            acc += Cc[i, j] * z[nx + j]
        if acc > u_max[i]:
            acc = u_max[i]
        elif acc < -u_max[i]:
            acc = -u_max[i]
        u[i] = acc
    return m0, m1


@njit(cache=True)
def applied_force(t, z, nx, l, Cc, Dc, y_ref, act, noise, noise_dt, u):
    """Force acting on the drogue (2,) [N] into u; returns the measured offsets and the
    commanded force (which differs from u only for a rate-limited actuator)."""
    y, zz = drogue_yz(z[:nx], l)
    return applied_force_at(t, z, nx, y, zz, Cc, Dc, y_ref, act, noise, noise_dt, u)


@njit(cache=True)
def applied_force_at(t, z, nx, y, zz, Cc, Dc, y_ref, act, noise, noise_dt, u):
    """:func:`applied_force` for a drogue at lateral y, vertical zz [m]."""
    m0, m1 = control_law(t, z, nx, y, zz, Cc, Dc, y_ref, act, noise, noise_dt, u)
    c0, c1 = u[0], u[1]
    na = nx + Cc.shape[1]
    if z.shape[0] > na:
        u[0] = z[na]
        u[1] = z[na + 1]
    return m0, m1, c0, c1


@njit(cache=True)
def closed_loop_deriv(t, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act,
                      noise, noise_dt, ws, dz, u):
    """dz/dt of z = [x, xc, (ua)]; u receives the force applied to the drogue."""
    n = l.shape[0]
    nx = 4 * n
    # link frames first: the controller measures the drogue from them, the loads reuse them
    link_frames(z[: 2 * n], n, ws[0], ws[1], ws[2], ws[3])
    y, zz = drogue_from_frames(l, ws[0])
    m0, m1, c0, c1 = applied_force_at(t, z, nx, y, zz, Cc, Dc, y_ref, act, noise, noise_dt, u)
    loads_given_frames(t, z[: 2 * n], z[2 * n: nx], u, l, M, J, ps, env, gust, ws)
    forward_dynamics_ws(l, M, J, ps, ws)
    qdd = ws[15]
    for i in range(2 * n):
        dz[i] = z[2 * n + i]
        dz[2 * n + i] = qdd[i]
    nc = Ac.shape[0]
    na = nx + nc
    if z.shape[0] > na:
        rate = act[2]
        for i in range(2):
            r = ((c0 if i == 0 else c1) - z[na + i]) / act[3]
            dz[na + i] = min(max(r, -rate), rate)
    for i in range(nc):
        acc = Bc[i, 0] * m0 + Bc[i, 1] * m1
        for j in range(nc):
            acc += Ac[i, j] * z[nx + j]
        dz[nx + i] = acc


@njit(cache=True)
def rk4_step(t, z, h, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws,
             k1, k2, k3, k4, tmp, u):
    """One classical RK4 step of the closed loop from (t, z), in place."""
    nz = z.shape[0]
    closed_loop_deriv(t, z, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, k1, u)
    for i in range(nz):
        tmp[i] = z[i] + 0.5 * h * k1[i]
    closed_loop_deriv(t + 0.5 * h, tmp, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise,
                      noise_dt, ws, k2, u)
    for i in range(nz):
        tmp[i] = z[i] + 0.5 * h * k2[i]
    closed_loop_deriv(t + 0.5 * h, tmp, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise,
                      noise_dt, ws, k3, u)
    for i in range(nz):
        tmp[i] = z[i] + h * k3[i]
    closed_loop_deriv(t + h, tmp, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise,
                      noise_dt, ws, k4, u)
    for i in range(nz):
        z[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


@njit(cache=True)
def step_status(z, n, max_yaw):
    """OK, or why the state may not go on: non-finite, or a link yaw beyond max_yaw [rad]."""
    for i in range(z.shape[0]):
        if not math.isfinite(z[i]):
            return NONFINITE
    for k in range(n):
        if abs(z[2 * k + 1]) > max_yaw:
            return YAW_LIMIT
    return OK


@njit(cache=True)
def rk4_run(z0, t0, h, nsteps, save_every, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref,
            act, noise, noise_dt, max_yaw, ts, zs, us):
    """Integrate ``nsteps`` RK4 steps of size h from (t0, z0); keep every ``save_every``-th state
    in ts, zs, us (the force applied at that state). Returns (status, saved count, stop time).

    Stops early on a non-finite state (status NONFINITE) or a link yaw beyond ``max_yaw`` [rad]
    (status YAW_LIMIT); what was saved up to then stays valid.
    """
    n = l.shape[0]
    nz = z0.shape[0]
    nx = 4 * n
    z = z0.copy()
    k1 = np.empty(nz)
    k2 = np.empty(nz)
    k3 = np.empty(nz)
    k4 = np.empty(nz)
    tmp = np.empty(nz)
    u = np.empty(2)
    ws = make_workspace_jit(n)
    ts[0] = t0
    zs[0, :] = z
    applied_force(t0, z, nx, l, Cc, Dc, y_ref, act, noise, noise_dt, u)
    us[0, 0] = u[0]
    us[0, 1] = u[1]
    saved = 1
    for step in range(1, nsteps + 1):
        t = t0 + (step - 1) * h
        rk4_step(t, z, h, l, M, S, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws,
                 k1, k2, k3, k4, tmp, u)
        t = t0 + step * h
        status = step_status(z, n, max_yaw)
        if status != OK:
            return status, saved, t
        if step % save_every == 0:
            ts[saved] = t
            zs[saved, :] = z
            applied_force(t, z, nx, l, Cc, Dc, y_ref, act, noise, noise_dt, u)
            us[saved, 0] = u[0]
            us[saved, 1] = u[1]
            saved += 1
    return OK, saved, t0 + nsteps * h
