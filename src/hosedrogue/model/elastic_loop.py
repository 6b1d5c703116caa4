"""The fixed-length elastic chain's closed loop (numba): RK4 or the stiff SDIRK (docs/model.md §11).

The state is ``z = [x, xc, (ua)]`` with the elastic hose state ``x = [q, qd, lam, lamd]`` (6n:
angles [rad], their rates [rad/s], the links' actual lengths [m] and their rates [m/s]), then the
controller's and the rate-limited actuator's states as in :mod:`hosedrogue.model.integrate`,
whose control, actuator and controller laws it uses. ``scheme`` 0 is the classical RK4, 1 the
SDIRK of :mod:`hosedrogue.model.implicit`, both the steps of :mod:`hosedrogue.model.steppers`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..jit import JIT, JIT_INLINE, JIT_NO_ALLOC
from .elastic import elastic_drogue_yz, elastic_evaluate_ws, hose_rates, make_elastic_workspace_jit
from .integrate import actuator_rates, applied_force_at, controller_rates, is_open_loop, step_status
from .chain_dynamics import (WS_CS, WS_DRAG, WS_R, WS_T0, WS_TOW, WS_V, copy_matrix, copy_vector,
                             make_workspace_jit)
from .layout import OK, SCHEME_RK4, STAGE_LIMIT
from .steppers import rk4, sdirk2


@njit(**JIT_NO_ALLOC)
def elastic_loop_deriv(t, z, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews, hg,
                       guess, dz, u):
    """dz/dt of z = [x, xc, (ua)] (x the 6n elastic hose state); u receives the force applied to
    the drogue. ``hg``, ``guess``: an implicit stage's (:func:`hosedrogue.model.elastic.stiff_terms`);
    0 and anything for the true derivative. Returns the axial dissipation [W]."""
    n = l.shape[0]
    nx = 6 * n
    if is_open_loop(z, nx, Cc, Dc):
        u[0] = 0.0
        u[1] = 0.0
        m0 = m1 = c0 = c1 = 0.0
    else:
        y, zz = elastic_drogue_yz(z[: 2 * n], z[4 * n: 5 * n], n, ws)
        m0, m1, c0, c1 = applied_force_at(t, z, nx, y, zz, Cc, Dc, y_ref, act, noise, noise_dt, u)
    p = elastic_evaluate_ws(t, z[:nx], u, l, M, J, ps, env, gust, ws, ews, hg, guess)
    hose_rates(z, n, ws, ews, dz)
    actuator_rates(c0, c1, z, nx + Ac.shape[0], act, dz)
    controller_rates(m0, m1, z, nx, Ac, Bc, dz)
    return p


@njit(**JIT_INLINE)
def elastic_rate(t, z, model, hg, guess, dz):
    """:func:`elastic_loop_deriv` as the steppers' derivative (:mod:`hosedrogue.model.steppers`):
    ``model`` is ``(l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews,
    u)``."""
    l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews, u = model
    elastic_loop_deriv(t, z, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews, hg, guess,
                       dz, u)


_rk4_step, _ = rk4(elastic_rate)
_sdirk2_step = sdirk2(elastic_rate)


@njit(**JIT_NO_ALLOC)
def elastic_step(t, z, h, scheme, iters, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws,
                 ews, pairs, work, u):
    """One step of size h [s] from (t, z), in place: RK4 or the SDIRK (``scheme``; ``iters`` the
    SDIRK's least corrections per stage) of :mod:`hosedrogue.model.steppers`. ``work`` (8,
    len(z)): the stages; ``work[7]`` must hold the slope guess of the SDIRK's first stage (the
    previous step's last stage slope, or dz/dt at z) and receives the next one. Returns OK, or
    STAGE_LIMIT if the SDIRK's stages did not converge even on 16 substeps (z then back at the
    step's start). A function of its own without numba's runtime (as ``rk4_steps``): the steps
    inlined into it then take no reference counts of the arrays they unpack from ``model``, which
    they would inlined into :func:`elastic_run` (it allocates)."""
    model = (l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews, u)
    if scheme == SCHEME_RK4:
        _rk4_step(t, z, h, model, work)
        return OK
    return _sdirk2_step(t, z, h, model, l.shape[0], iters, ws[WS_CS], pairs, work)  # ws[WS_CS]: the frames


def hose_pairs(n):
    """The second-order pairs (position row, velocity row, count) of the elastic hose state.

    Parameters
    ----------
    n : int
        Number of links [-].

    Returns
    -------
    numpy.ndarray (2, 3) of int64
        ``(0, 2n, 2n)`` for the angles and ``(4n, 5n, n)`` for the lengths.
    """
    return np.array([[0, 2 * n, 2 * n], [4 * n, 5 * n, n]], dtype=np.int64)


hose_pairs_jit = njit(**JIT)(hose_pairs)


@njit(**JIT)
def elastic_run(z0, t0, h, nsteps, save_every, scheme, iters, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise,
                noise_dt, max_yaw, ts, zs, us, joints, drogue_vel, drogue_drag, tow, tension):
    """Integrate ``nsteps`` steps of size h [s] from (t0, z0) with ``scheme`` (RK4 or SDIRK with
    ``iters`` corrections per stage); keep
    every ``save_every``-th state in ts, zs, us and its outputs (joints [m], drogue velocity
    [m/s], drogue drag [N], tow-point force [N], exit tension [N]), as
    :func:`~hosedrogue.model.integrate.rk4_run`. Returns (status, saved count, stop time)."""
    n = l.shape[0]
    z = z0.copy()
    nz = z.shape[0]
    work = np.zeros((8, nz))
    u = np.empty(2)
    ws = make_workspace_jit(n)
    ews = make_elastic_workspace_jit(n)
    pairs = hose_pairs_jit(n)
    saved = 0
    for step in range(nsteps + 1):
        t = t0 + step * h
        if step % save_every == 0 or step == 0:
            # the true derivative at the saved state: its outputs, and the SDIRK's first guess
            elastic_loop_deriv(t, z, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt, ws, ews,
                               0.0, work[6], work[6], u)
            if step == 0:
                for i in range(nz):
                    work[7, i] = work[6, i]
            ts[saved] = t
            copy_vector(zs[saved], z)  # element by element: no array assignment (docs/develop.md)
            us[saved, 0] = u[0]
            us[saved, 1] = u[1]
            copy_matrix(joints[saved], ws[WS_R])
            copy_vector(drogue_vel[saved], ws[WS_V][n])
            copy_vector(drogue_drag[saved], ws[WS_DRAG])
            copy_vector(tow[saved], ws[WS_TOW])
            tension[saved] = ws[WS_T0][0]
            saved += 1
        if step == nsteps:
            break
        if elastic_step(t, z, h, scheme, iters, l, M, J, ps, env, gust, Ac, Bc, Cc, Dc, y_ref, act, noise, noise_dt,
                        ws, ews, pairs, work, u) != OK:
            return STAGE_LIMIT, saved, t  # the state of step t kept (the run's last saved row may be older)
        status = step_status(z, n, max_yaw)
        if status != OK:
            return status, saved, t + h
    return OK, saved, t0 + nsteps * h
